// fastddsgen 2.3.0's generated syrof_msgs.cxx names an array bound declared
// in the IDL's module (MAX_ANCHORS) without its namespace in out-of-class
// definitions, which does not compile; bringing the constant into the global
// scope first lets the generated file compile unchanged.
#include "syrof_msgs.h"

using syrof::msg::dds_::MAX_ANCHORS;

#include "syrof_msgs.cxx"
