#include "syrof/sim_dds/topics.h"

#include "syrof/base/check.h"

namespace syrof::sim_dds {
namespace {

struct TopicRow {
  const char* name;  // per-robot topics: the part after "rt/robot_<i>/"
  const dds_topic_descriptor_t* descriptor;
  bool per_robot;
  TopicQos qos;
};

// The table of topics.h, in TopicKind order.
const TopicRow& Row(TopicKind kind) {
  static const TopicRow rows[kTopicKinds] = {
      {"rt/syrof/beacon", &syrof_msg_dds__Beacon__desc, false, {.reliable = false, .transient_local = false, .keep_last = 1}},
      {"syrof/imu", &syrof_msg_dds__Imu__desc, true, {.reliable = false, .transient_local = false, .keep_last = 4}},
      {"syrof/flow", &syrof_msg_dds__Flow__desc, true, {.reliable = false, .transient_local = false, .keep_last = 4}},
      {"syrof/uwb", &syrof_msg_dds__Uwb__desc, true, {.reliable = false, .transient_local = false, .keep_last = 4}},
      {"syrof/drive", &syrof_msg_dds__Drive__desc, true, {.reliable = false, .transient_local = false, .keep_last = 1}},
      {"rt/syrof/control", &syrof_msg_dds__Control__desc, false, {.reliable = true, .transient_local = true, .keep_last = 1}},
      {"rt/syrof/report", &syrof_msg_dds__Report__desc, false, {.reliable = true, .transient_local = false, .keep_last = 0}},
      {"rt/syrof/status", &syrof_msg_dds__Status__desc, false, {.reliable = true, .transient_local = true, .keep_last = 1}},
  };
  const auto index = static_cast<int>(kind);
  SYROF_CHECK(index >= 0 && index < kTopicKinds);
  return rows[index];
}

}  // namespace

bool IsPerRobot(TopicKind kind) { return Row(kind).per_robot; }

std::string TopicName(TopicKind kind, uint16_t robot) {
  const TopicRow& row = Row(kind);
  if (!row.per_robot) return row.name;
  return "rt/robot_" + std::to_string(robot) + "/" + row.name;
}

const dds_topic_descriptor_t* TopicDescriptor(TopicKind kind) { return Row(kind).descriptor; }

TopicQos QosOf(TopicKind kind) { return Row(kind).qos; }

Qos::Qos(TopicKind kind) : qos_(dds_create_qos()) {
  const TopicQos qos = QosOf(kind);
  if (qos.reliable) {
    dds_qset_reliability(qos_, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  } else {
    dds_qset_reliability(qos_, DDS_RELIABILITY_BEST_EFFORT, 0);
  }
  dds_qset_durability(qos_, qos.transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  if (qos.keep_last > 0) {
    dds_qset_history(qos_, DDS_HISTORY_KEEP_LAST, qos.keep_last);
  } else {
    dds_qset_history(qos_, DDS_HISTORY_KEEP_ALL, 0);
  }
  // XCDR1: what Fast DDS 2.9's readers accept (toolchain facts).
  const dds_data_representation_id_t xcdr1[] = {DDS_DATA_REPRESENTATION_XCDR1};
  dds_qset_data_representation(qos_, 1, xcdr1);
}

EntityOrError CreateTopic(const Participant& participant, TopicKind kind, uint16_t robot) {
  const std::string name = TopicName(kind, robot);
  const Qos qos(kind);
  const dds_entity_t topic = dds_create_topic(participant.handle(), TopicDescriptor(kind), name.c_str(), qos.get(), nullptr);
  if (topic < 0) return EntityOrError::Failed(DdsError(name, "dds_create_topic", topic));
  return EntityOrError::Of(topic);
}

EntityOrError CreateWriter(const Participant& participant, TopicKind kind, uint16_t robot) {
  EntityOrError topic = CreateTopic(participant, kind, robot);
  if (!topic.ok()) return topic;
  const Qos qos(kind);
  const dds_entity_t writer = dds_create_writer(participant.handle(), topic.entity, qos.get(), nullptr);
  if (writer < 0) return EntityOrError::Failed(DdsError(TopicName(kind, robot), "dds_create_writer", writer));
  return EntityOrError::Of(writer);
}

EntityOrError CreateReader(const Participant& participant, TopicKind kind, uint16_t robot,
                           const dds_listener_t* listener) {
  EntityOrError topic = CreateTopic(participant, kind, robot);
  if (!topic.ok()) return topic;
  const Qos qos(kind);
  const dds_entity_t reader = dds_create_reader(participant.handle(), topic.entity, qos.get(), listener);
  if (reader < 0) return EntityOrError::Failed(DdsError(TopicName(kind, robot), "dds_create_reader", reader));
  return EntityOrError::Of(reader);
}

}  // namespace syrof::sim_dds
