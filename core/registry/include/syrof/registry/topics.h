// Every topic id of a robot's broker, in one list.
//
// A topic's id is the broker's key (pubsub::Broker::RegisterPublisher), so two
// modules that picked the same id would collide at start-up, in whichever
// runtime registered the second. The ids live here, with a compile-time check
// that they are unique and fit the broker's TopicId; the typed constants
// (pubsub::Topic<T>) stay beside their message types and take id and name from
// this list:
//
//   inline constexpr pubsub::Topic<ImuReading> kImuTopic{registry::topics::kImu.id,
//                                                        registry::topics::kImu.name};
//
// This header holds plain numbers and names only (no pubsub, no message
// types), so that every module may include it. A new topic gets a line below
// and an entry in kAll. The values themselves mean nothing beyond being
// distinct: no output of the lab depends on them.
#pragma once

#include <cstddef>
#include <cstdint>

namespace syrof::registry {

/// Largest id the broker takes: pubsub::TopicId is uint8_t (the paper's id).
/// syrof/estimation/topics.h checks that the two agree.
inline constexpr int kMaxTopicId = UINT8_MAX;

/// One topic: its broker id and the name logs and tools show.
struct TopicEntry {
  int id;
  const char* name;
};

namespace topics {

// Sensor drivers (the MPU-9250, the flow sensor, the DWM1000, or the lab's
// simulated sensors) -> the estimator's state task. Payloads in
// syrof/estimation/messages.h.
inline constexpr TopicEntry kImu{1, "imu"};
inline constexpr TopicEntry kFlow{2, "flow"};
inline constexpr TopicEntry kUwb{3, "uwb"};
// The estimator's Kalman task -> the runtime's round and motion tasks.
inline constexpr TopicEntry kStateEstimate{4, "state_estimate"};
// The runtime's motion task -> the motor driver or the lab's bodies
// (syrof/motion/drive.h).
inline constexpr TopicEntry kDrive{5, "drive"};

/// Every topic above; the checks below run over this list.
inline constexpr TopicEntry kAll[] = {kImu, kFlow, kUwb, kStateEstimate, kDrive};

}  // namespace topics

/// Topics a robot's broker carries: size its StaticBroker's publisher table
/// with at least this many.
inline constexpr size_t kTopicCount = sizeof(topics::kAll) / sizeof(topics::kAll[0]);

/// Whether every id of `list` fits the broker's TopicId.
template <size_t N>
constexpr bool TopicIdsInRange(const TopicEntry (&list)[N]) {
  for (const TopicEntry& topic : list) {
    if (topic.id < 0 || topic.id > kMaxTopicId) return false;
  }
  return true;
}

/// Whether no two entries of `list` share an id.
template <size_t N>
constexpr bool TopicIdsUnique(const TopicEntry (&list)[N]) {
  for (size_t i = 0; i < N; ++i) {
    for (size_t j = i + 1; j < N; ++j) {
      if (list[i].id == list[j].id) return false;
    }
  }
  return true;
}

namespace detail {
constexpr bool SameName(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) {
    ++a;
    ++b;
  }
  return *a == *b;
}
}  // namespace detail

/// Whether no two entries of `list` share a name.
template <size_t N>
constexpr bool TopicNamesUnique(const TopicEntry (&list)[N]) {
  for (size_t i = 0; i < N; ++i) {
    for (size_t j = i + 1; j < N; ++j) {
      if (detail::SameName(list[i].name, list[j].name)) return false;
    }
  }
  return true;
}

static_assert(TopicIdsInRange(topics::kAll), "a topic id is outside the broker's TopicId range 0 .. 255");
static_assert(TopicIdsUnique(topics::kAll), "two topics share an id: give each topic in registry::topics its own");
static_assert(TopicNamesUnique(topics::kAll), "two topics share a name");

}  // namespace syrof::registry
