// The swarm's DDS topics: their names (ROS 2's "rt/" convention), types
// (sim_dds/idl/syrof_msgs.idl, generated into "syrof_msgs.h") and QoS, in
// one table, and helpers that create a topic with its reader or writer.
//
//   topic                      type      QoS
//   rt/syrof/beacon            Beacon_   best effort, keep last 1, volatile (keyed by sender, run)
//   rt/robot_<i>/syrof/imu     Imu_      best effort, keep last 4, volatile (keyed by robot, run)
//   rt/robot_<i>/syrof/flow    Flow_     best effort, keep last 4, volatile (keyed by robot, run)
//   rt/robot_<i>/syrof/uwb     Uwb_      best effort, keep last 4, volatile (keyed by robot, run)
//   rt/robot_<i>/syrof/drive   Drive_    best effort, keep last 1, volatile (keyed by robot, run)
//   rt/syrof/control           Control_  reliable, keep last 1, transient-local
//   rt/syrof/report            Report_   reliable, keep all, volatile
//   rt/syrof/status            Status_   reliable, keep last 1, transient-local (keyed by robot, run)
//
// Keyed by the run as well as the robot: runs that share a domain use the
// same robot ids, and "keep last" keeps the newest per key, so one run's
// samples never push another's out of a reader's history.
//
// Every type is @final and sent as XCDR1 (forced), which Fast DDS 2.9 reads.
// Readers and writers take the topic's QoS, so every pair matches.
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <optional>
#include <string>

#include "syrof/sim_dds/participant.h"
#include "syrof_msgs.h"

namespace syrof::sim_dds {

enum class TopicKind : uint8_t {
  kBeacon = 0,
  kImu,
  kFlow,
  kUwb,
  kDrive,
  kControl,
  kReport,
  kStatus,
};

inline constexpr int kTopicKinds = 8;

/// True for the topics with one instance per robot (rt/robot_<i>/...).
bool IsPerRobot(TopicKind kind);

/// The DDS topic name; `robot` is used by per-robot topics only
/// ("rt/robot_3/syrof/imu").
std::string TopicName(TopicKind kind, uint16_t robot = 0);

/// The generated type's descriptor (syrof_msg_dds__Beacon__desc, ...).
const dds_topic_descriptor_t* TopicDescriptor(TopicKind kind);

/// How the QoS table above reads for one topic.
struct TopicQos {
  bool reliable = false;
  bool transient_local = false;
  int32_t keep_last = 1;  ///< 0: keep all
};
TopicQos QosOf(TopicKind kind);

/// An owned dds_qos_t for a topic, its readers and its writers.
class Qos {
 public:
  explicit Qos(TopicKind kind);
  ~Qos() { dds_delete_qos(qos_); }
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
  const dds_qos_t* get() const { return qos_; }
  /// To add a policy of one endpoint's own (ignore local, a listener mask).
  dds_qos_t* mutable_get() { return qos_; }

 private:
  dds_qos_t* qos_;
};

/// A DDS entity (topic, reader, writer) or why it could not be made.
struct EntityOrError {
  dds_entity_t entity = 0;
  std::optional<Error> error;
  bool ok() const { return !error; }
  static EntityOrError Of(dds_entity_t entity) { return {entity, std::nullopt}; }
  static EntityOrError Failed(Error why) { return {0, std::move(why)}; }
};

/// Creates (or finds again) the topic on `participant`; where = its name.
EntityOrError CreateTopic(const Participant& participant, TopicKind kind, uint16_t robot = 0);

/// A writer of the topic with its QoS (creating the topic). Deleted with the
/// participant, or by dds_delete.
EntityOrError CreateWriter(const Participant& participant, TopicKind kind, uint16_t robot = 0);

/// A reader of the topic with its QoS; `listener` (may be null) is copied
/// by Cyclone.
EntityOrError CreateReader(const Participant& participant, TopicKind kind, uint16_t robot = 0,
                           const dds_listener_t* listener = nullptr);

}  // namespace syrof::sim_dds
