#include "dds_links.h"

#include <cstring>

#include "syrof/sim_dds/topics.h"
#include "take_samples.h"

namespace syrof::sim_dds {

void DdsSensorSink::OnImu(const estimation::ImuReading& r) {
  syrof_msg_dds__Imu_ s{};
  s.robot = robot_;
  s.run_id = run_id_;
  s.world_time_ns = r.timestamp_ns;
  std::memcpy(s.accel_g, r.accel_g, sizeof s.accel_g);
  std::memcpy(s.gyro_dps, r.gyro_dps, sizeof s.gyro_dps);
  (void)dds_write(imu_, &s);
}

void DdsSensorSink::OnFlow(const estimation::FlowReading& r) {
  syrof_msg_dds__Flow_ s{};
  s.robot = robot_;
  s.run_id = run_id_;
  s.world_time_ns = r.timestamp_ns;
  s.interval_ns = r.interval_ns;
  s.delta_x_px = r.delta_x_px;
  s.delta_y_px = r.delta_y_px;
  (void)dds_write(flow_, &s);
}

void DdsSensorSink::OnUwb(const estimation::UwbReading& r) {
  syrof_msg_dds__Uwb_ s{};
  s.robot = robot_;
  s.run_id = run_id_;
  s.world_time_ns = r.timestamp_ns;
  std::memcpy(s.range_m, r.range_m, sizeof s.range_m);
  s.valid_mask = r.valid_mask;
  s.sweep = r.sweep;
  (void)dds_write(uwb_, &s);
}

namespace {

bool AssignEntity(const EntityOrError& e, dds_entity_t& out) {
  if (!e.ok()) return false;
  out = e.entity;
  return true;
}

}  // namespace

bool DdsLinks::Create(const Participant& participant) {
  for (uint16_t id = 0; id < robots_.size(); ++id) {
    RobotLinks& r = robots_[id];
    const bool ok = AssignEntity(CreateWriter(participant, TopicKind::kImu, id), r.imu) &&
                    AssignEntity(CreateWriter(participant, TopicKind::kFlow, id), r.flow) &&
                    AssignEntity(CreateWriter(participant, TopicKind::kUwb, id), r.uwb) &&
                    AssignEntity(CreateReader(participant, TopicKind::kDrive, id), r.drive);
    if (!ok) return false;
    r.sink = std::make_unique<DdsSensorSink>(id, run_id_, r.imu, r.flow, r.uwb);
  }
  return true;
}

void DdsLinks::TakeDrives(const std::function<void(uint16_t, const motion::DriveCommand&)>& apply) {
  for (uint16_t id = 0; id < robots_.size(); ++id) {
    TakeSamples<syrof_msg_dds__Drive_>(robots_[id].drive, [&](const syrof_msg_dds__Drive_& s, const dds_sample_info_t&) {
      if (s.run_id != run_id_) {
        ++drives_other_runs_;  // the same robot of another run on this domain
        return;
      }
      if (s.robot != id || s.kind > 1) return;
      motion::DriveCommand command{};
      command.timestamp_ns = s.robot_time_ns;
      command.kind = static_cast<motion::DriveKind>(s.kind);
      command.vx_mps = s.vx_mps;
      command.vy_mps = s.vy_mps;
      command.yaw_rate_radps = s.yaw_rate_radps;
      command.left_mps = s.left_mps;
      command.right_mps = s.right_mps;
      apply(id, command);
    });
  }
}

}  // namespace syrof::sim_dds
