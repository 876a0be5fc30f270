// The estimator's topics on the broker: one definition each, used by the
// publishers (drivers, simulated sensors, the Kalman task) and subscribers
// alike. The estimator owns topic ids 16 .. 31.
#pragma once

#include "syrof/estimation/messages.h"
#include "syrof/pubsub/topic.h"

namespace syrof::estimation {

inline constexpr pubsub::Topic<ImuReading> kImuTopic{16, "imu"};
inline constexpr pubsub::Topic<FlowReading> kFlowTopic{17, "flow"};
inline constexpr pubsub::Topic<UwbReading> kUwbTopic{18, "uwb"};
inline constexpr pubsub::Topic<StateEstimate> kStateEstimateTopic{19, "state_estimate"};

}  // namespace syrof::estimation
