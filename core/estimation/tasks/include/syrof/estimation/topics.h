// The estimator's topics on the broker: one typed constant each, used by the
// publishers (drivers, simulated sensors, the Kalman task) and subscribers
// alike. Ids and names come from the robot's one topic list,
// syrof/registry/topics.h.
#pragma once

#include <limits>

#include "syrof/estimation/messages.h"
#include "syrof/pubsub/topic.h"
#include "syrof/registry/topics.h"

namespace syrof::estimation {

static_assert(registry::kMaxTopicId == std::numeric_limits<pubsub::TopicId>::max(),
              "the registry's id range is the broker's TopicId");

inline constexpr pubsub::Topic<ImuReading> kImuTopic{registry::topics::kImu.id, registry::topics::kImu.name};
inline constexpr pubsub::Topic<FlowReading> kFlowTopic{registry::topics::kFlow.id, registry::topics::kFlow.name};
inline constexpr pubsub::Topic<UwbReading> kUwbTopic{registry::topics::kUwb.id, registry::topics::kUwb.name};
inline constexpr pubsub::Topic<StateEstimate> kStateEstimateTopic{registry::topics::kStateEstimate.id,
                                                                  registry::topics::kStateEstimate.name};

}  // namespace syrof::estimation
