// One simulated robot: the real robot software (runtime::Robot) on its own
// simulation port and broker, and its simulated hardware (sensor bank, drive
// subscription) on the lab side of the topics. Internal to lab/sim.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "syrof/app/app.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sensors/sensor_publishers.h"
#include "syrof/lab/world/world.h"
#include "syrof/motion/drive.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/registry/topics.h"
#include "syrof/runtime/robot.h"

namespace syrof::lab::sim {

class LabRobot {
 public:
  /// `world`, `radio` and `scheduler` outlive the robot; the app is owned.
  LabRobot(const scenario::Scenario& scenario, const scenario::RobotSpec& spec, os::SimScheduler& scheduler,
           world::World& world, const runtime::RobotConfig& config, std::unique_ptr<app::App> app,
           runtime::Radio& radio);
  LabRobot(const LabRobot&) = delete;
  LabRobot& operator=(const LabRobot&) = delete;

  /// Advertises the sensor topics, attaches the robot's software to its port
  /// and broker, and subscribes the hardware to the drive topic. Once.
  void Attach();

  /// The robot's hardware, once per IMU period while the robot runs: the
  /// latest drive command to its body, then the sensor readings due, sampled
  /// from the body's true state.
  void StepHardware(int64_t now_ns);
  /// StepHardware in two halves, for `--threads`: SampleHardware takes the
  /// latest drive command and samples the sensors (it touches this robot's
  /// broker, noise and body state, read only); ApplyDrive then hands the
  /// command taken to the body (the world counts refused ones). The
  /// readings do not depend on the drive, so the halves give StepHardware.
  void SampleHardware();
  void ApplyDrive();

  uint16_t id() const { return spec_.id; }
  const char* app_name() const { return app_->name(); }
  os::SimPort& port() { return port_; }
  const os::SimPort& port() const { return port_; }
  runtime::Robot& robot() { return robot_; }
  const runtime::Robot& robot() const { return robot_; }

  /// The robot's hardware, software and app (its RecordingApp's call
  /// history) into `digest` (base/state_digest.h); its port's tasks are the
  /// scheduler's.
  void AddToDigest(base::StateDigest& digest) const;

  bool invalid_command_recorded = false;  ///< the replay records the first of each per robot
  bool payload_refusal_recorded = false;

 private:
  scenario::RobotSpec spec_;
  world::World& world_;
  os::SimPort port_;
  // One publisher slot per robot topic (registry::topics), with room to
  // spare; subscriptions: the estimator's, the round and motion tasks' and
  // the drive poller's.
  static constexpr size_t kBrokerPublishers = 8;
  static_assert(kBrokerPublishers >= registry::kTopicCount, "a robot's broker holds every robot topic");
  pubsub::StaticBroker<kBrokerPublishers, 12> broker_;
  sensors::SensorBank bank_;
  sensors::SensorPublishers publishers_;
  pubsub::Subscriber<motion::DriveCommand> drive_;
  motion::DriveCommand drive_taken_{};  // SampleHardware's, for ApplyDrive
  bool drive_was_taken_ = false;
  std::unique_ptr<app::App> app_;
  runtime::Robot robot_;
};

}  // namespace syrof::lab::sim
