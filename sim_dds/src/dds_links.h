// How the DDS world's readings go out and the robots' drives come back, as
// the world loop's RemoteLinks (lab/sim/remote_world.h): each robot's
// readings as its Imu_/Flow_/Uwb_ samples, its Drive_ samples as drive
// commands. Internal to sim_dds.
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sim/remote_world.h"
#include "syrof/sim_dds/participant.h"

namespace syrof::sim_dds {

/// Sends one robot's simulated readings as its DDS sensor samples.
class DdsSensorSink final : public lab::sensors::ReadingSink {
 public:
  DdsSensorSink(uint16_t robot, uint64_t run_id, dds_entity_t imu, dds_entity_t flow, dds_entity_t uwb)
      : robot_(robot), run_id_(run_id), imu_(imu), flow_(flow), uwb_(uwb) {}
  void OnImu(const estimation::ImuReading& r) override;
  void OnFlow(const estimation::FlowReading& r) override;
  void OnUwb(const estimation::UwbReading& r) override;

 private:
  uint16_t robot_;
  uint64_t run_id_;
  dds_entity_t imu_, flow_, uwb_;
};

class DdsLinks final : public lab::sim::RemoteLinks {
 public:
  /// The links of `robots` robots of run `run_id`.
  DdsLinks(uint16_t robots, uint64_t run_id) : run_id_(run_id), robots_(robots) {}

  /// Creates every robot's sensor writers and drive reader on
  /// `participant`, robot by robot; false when one could not be created.
  bool Create(const Participant& participant);

  /// The Drive_ samples taken since the last call, robot by robot: each
  /// one of this run from the robot its topic is for, of a known kind.
  void TakeDrives(const std::function<void(uint16_t, const motion::DriveCommand&)>& apply) override;
  lab::sensors::ReadingSink* Readings(uint16_t id) override { return robots_[id].sink.get(); }

  /// Drive_ samples of another run on the domain (the same robot id).
  int64_t drives_other_runs() const { return drives_other_runs_; }

 private:
  struct RobotLinks {
    dds_entity_t imu = 0, flow = 0, uwb = 0, drive = 0;
    std::unique_ptr<DdsSensorSink> sink;
  };

  const uint64_t run_id_;
  std::vector<RobotLinks> robots_;
  int64_t drives_other_runs_ = 0;
};

}  // namespace syrof::sim_dds
