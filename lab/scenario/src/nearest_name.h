// Moved to the public header (assignment files share the reader).
#pragma once

#include "syrof/lab/scenario/yaml/nearest_name.h"
