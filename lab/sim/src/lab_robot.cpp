#include "lab_robot.h"

#include "syrof/base/check.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/recording_app.h"

namespace syrof::lab::sim {
namespace {

// The simulated hardware is lab code, not robot code: one world task steps
// every robot's sensors and actuators (in robot order, at the drivers'
// priority) instead of one task per robot. Its drive subscriptions are read
// by polling, so they name no task: a port ignores notifications to an id
// it does not have (port.h).
constexpr os::TaskId kPolledTask = UINT16_MAX;

}  // namespace

LabRobot::LabRobot(const scenario::Scenario& scenario, const scenario::RobotSpec& spec, os::SimScheduler& scheduler,
                   world::World& world, const runtime::RobotConfig& config, std::unique_ptr<app::App> app,
                   runtime::Radio& radio)
    : spec_(spec),
      world_(world),
      port_(scheduler, "robot"),
      broker_(port_),
      bank_(SensorConfigFor(scenario, spec), SensorSeed(scenario.seed, spec.id)),
      app_(std::move(app)),
      robot_(config, *app_, radio) {}

void LabRobot::Attach() {
  SYROF_CHECK(publishers_.Advertise(broker_) == pubsub::BrokerError::kOk);
  const runtime::RobotSetupError error = robot_.Attach(port_, broker_);
  SYROF_CHECK(error == runtime::RobotSetupError::kOk);
  SYROF_CHECK(drive_.Subscribe(broker_, motion::kDriveTopic, kPolledTask) == pubsub::BrokerError::kOk);
}

void LabRobot::StepHardware(int64_t now_ns) {
  (void)now_ns;  // readings are stamped by the robot's own clock, as its drivers would
  SampleHardware();
  ApplyDrive();
}

void LabRobot::SampleHardware() {
  drive_was_taken_ = drive_.TakeLatest(drive_taken_);
  bank_.Sample(port_.now_ns(), world_.true_state(spec_.id), publishers_);
}

void LabRobot::ApplyDrive() {
  if (drive_was_taken_) world_.SetDrive(spec_.id, drive_taken_);
  drive_was_taken_ = false;
}

void LabRobot::AddToDigest(base::StateDigest& digest) const {
  broker_.AddToDigest(digest);
  bank_.AddToDigest(digest);
  digest.AddValue(drive_taken_);
  digest.AddValue(drive_was_taken_);
  const auto* app = dynamic_cast<const RecordingApp*>(app_.get());
  SYROF_CHECK(app != nullptr);  // the simulation wraps every app
  app->AddToDigest(digest);
  robot_.AddToDigest(digest);
}

}  // namespace syrof::lab::sim
