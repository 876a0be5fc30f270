// The motion controllers in closed loop with simple plant models written
// here (a point mass with an acceleration limit; a differential-drive rover
// with wheel acceleration limits), fed a perfect estimate.
#include "syrof/motion/controller.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "syrof/app/commands.h"

namespace syrof::motion {
namespace {

constexpr int64_t kStepNs = 10'000'000;  // the motion task's 100 Hz
constexpr float kDt = 0.01f;

estimation::StateEstimate Perfect(float x_m, float y_m, float heading_rad) {
  estimation::StateEstimate estimate{};
  estimate.x_m = x_m;
  estimate.y_m = y_m;
  estimate.heading_rad = heading_rad;
  estimate.status = estimation::kEstimateInitialized;
  return estimate;
}

constexpr syrof_car_command MoveTo(float x_m, float y_m, float speed_mps) {
  return app::MoveToCommand(x_m, y_m, speed_mps);
}
constexpr syrof_car_command Velocity(float vx_mps, float vy_mps) { return app::VelocityCommand(vx_mps, vy_mps); }
constexpr syrof_car_command TurnTo(float heading_rad) { return app::TurnToCommand(heading_rad); }

ControllerConfig OmniConfig() {
  ControllerConfig config;
  config.kind = DriveKind::kOmni;
  config.limits = MotionLimits{0.5f, 1.0f, 3.0f, 0.16f, 0.1f};
  return config;
}

ControllerConfig RoverConfig() {
  ControllerConfig config;
  config.kind = DriveKind::kWheels;
  config.limits = MotionLimits{0.4f, 0.8f, 3.0f, 0.16f, 0.12f};
  return config;
}

// A point mass whose velocity follows the setpoint at most max_accel per
// second, like the lab's omni bodies.
struct PointMass {
  float x_m = 0, y_m = 0, vx_mps = 0, vy_mps = 0, heading_rad = 0;

  void Step(const DriveCommand& drive, float max_accel_mps2) {
    float dvx = drive.vx_mps - vx_mps;
    float dvy = drive.vy_mps - vy_mps;
    const float dv = std::sqrt(dvx * dvx + dvy * dvy);
    const float max_dv = max_accel_mps2 * kDt;
    if (dv > max_dv) {
      dvx *= max_dv / dv;
      dvy *= max_dv / dv;
    }
    x_m += (vx_mps + 0.5f * dvx) * kDt;
    y_m += (vy_mps + 0.5f * dvy) * kDt;
    vx_mps += dvx;
    vy_mps += dvy;
    heading_rad = WrapAngle(heading_rad + drive.yaw_rate_radps * kDt);
  }
};

// A differential-drive rover whose wheels follow their setpoints at most
// max_accel per second.
struct Rover {
  float x_m = 0, y_m = 0, heading_rad = 0, left_mps = 0, right_mps = 0;

  void Step(const DriveCommand& drive, const MotionLimits& limits) {
    const float max_dv = limits.max_accel_mps2 * kDt;
    left_mps += std::clamp(drive.left_mps - left_mps, -max_dv, max_dv);
    right_mps += std::clamp(drive.right_mps - right_mps, -max_dv, max_dv);
    const float speed = 0.5f * (left_mps + right_mps);
    const float rate = (right_mps - left_mps) / limits.wheel_base_m;
    x_m += speed * std::cos(heading_rad + 0.5f * rate * kDt) * kDt;
    y_m += speed * std::sin(heading_rad + 0.5f * rate * kDt) * kDt;
    heading_rad = WrapAngle(heading_rad + rate * kDt);
  }
};

TEST(WrapAngleTest, WrapsIntoMinusPiToPi) {
  EXPECT_NEAR(WrapAngle(3.0f * std::numbers::pi_v<float>), std::numbers::pi_v<float>, 1e-5f);
  EXPECT_NEAR(WrapAngle(-0.5f - 4.0f * std::numbers::pi_v<float>), -0.5f, 1e-5f);
  EXPECT_FLOAT_EQ(WrapAngle(0.25f), 0.25f);
  EXPECT_EQ(WrapAngle(std::numeric_limits<float>::quiet_NaN()), 0.0f);
}

TEST(MotionControllerTest, StartsStoppedAndArrived) {
  MotionController controller(OmniConfig());

  const DriveCommand drive = controller.Update(Perfect(1, 1, 0), 5 * kStepNs);

  EXPECT_TRUE(controller.arrived());
  EXPECT_EQ(drive.timestamp_ns, 5 * kStepNs);
  EXPECT_EQ(drive.kind, DriveKind::kOmni);
  EXPECT_EQ(drive.vx_mps, 0.0f);
  EXPECT_EQ(drive.vy_mps, 0.0f);
  EXPECT_EQ(drive.yaw_rate_radps, 0.0f);
}

TEST(MotionControllerTest, OmniMoveToConvergesWithoutOvershoot) {
  const ControllerConfig config = OmniConfig();
  MotionController controller(config);
  controller.SetCommand(MoveTo(1.2f, 0.9f, 0.4f));
  PointMass body;
  const float target_distance = std::hypot(1.2f, 0.9f);
  float furthest_along = 0;
  float fastest = 0;
  int steps = 0;

  for (; steps < 1000 && !(controller.arrived() && std::hypot(body.vx_mps, body.vy_mps) < 1e-4f); ++steps) {
    const DriveCommand drive = controller.Update(Perfect(body.x_m, body.y_m, 0), steps * kStepNs);
    body.Step(drive, config.limits.max_accel_mps2);
    furthest_along = std::max(furthest_along, (body.x_m * 1.2f + body.y_m * 0.9f) / target_distance);
    fastest = std::max(fastest, std::hypot(drive.vx_mps, drive.vy_mps));
  }

  EXPECT_LT(steps, 1000) << "never settled";
  EXPECT_TRUE(controller.arrived());
  EXPECT_LE(std::hypot(body.x_m - 1.2f, body.y_m - 0.9f), config.position_tolerance_m);
  EXPECT_LE(furthest_along, target_distance + config.position_tolerance_m);
  EXPECT_NEAR(fastest, 0.4f, 1e-5f);  // cruises at the commanded speed, never faster
}

TEST(MotionControllerTest, OmniMoveToCapsSpeedAtTheKindsLimit) {
  MotionController controller(OmniConfig());
  controller.SetCommand(MoveTo(3, 0, 5.0f));

  const DriveCommand drive = controller.Update(Perfect(0, 0, 0), 0);

  EXPECT_FLOAT_EQ(drive.vx_mps, 0.5f);
  EXPECT_FLOAT_EQ(drive.vy_mps, 0.0f);
  EXPECT_FALSE(controller.arrived());
}

TEST(MotionControllerTest, OmniMoveToHoldsWithinToleranceAndResumesWhenPushedAway) {
  MotionController controller(OmniConfig());
  controller.SetCommand(MoveTo(1, 1, 0.3f));

  const DriveCommand held = controller.Update(Perfect(1.015f, 1, 0), 0);
  const bool arrived_inside = controller.arrived();
  const DriveCommand still_held = controller.Update(Perfect(1.035f, 1, 0), kStepNs);  // within the release band
  const bool arrived_in_band = controller.arrived();
  const DriveCommand resumed = controller.Update(Perfect(1.1f, 1, 0), 2 * kStepNs);

  EXPECT_TRUE(arrived_inside);
  EXPECT_EQ(held.vx_mps, 0.0f);
  EXPECT_TRUE(arrived_in_band);
  EXPECT_EQ(still_held.vx_mps, 0.0f);
  EXPECT_FALSE(controller.arrived());
  EXPECT_LT(resumed.vx_mps, 0.0f);
}

TEST(MotionControllerTest, OmniVelocityIsClampedToMaxSpeed) {
  MotionController controller(OmniConfig());
  controller.SetCommand(Velocity(3, 4));

  const DriveCommand drive = controller.Update(Perfect(0, 0, 0), 0);

  EXPECT_FLOAT_EQ(drive.vx_mps, 0.3f);
  EXPECT_FLOAT_EQ(drive.vy_mps, 0.4f);
  EXPECT_FALSE(controller.arrived());
}

TEST(MotionControllerTest, OmniVelocityBelowMaxIsPassedThrough) {
  MotionController controller(OmniConfig());
  controller.SetCommand(Velocity(-0.1f, 0.2f));

  const DriveCommand drive = controller.Update(Perfect(0, 0, 0), 0);

  EXPECT_FLOAT_EQ(drive.vx_mps, -0.1f);
  EXPECT_FLOAT_EQ(drive.vy_mps, 0.2f);
}

TEST(MotionControllerTest, OmniTurnToCapsTheRateAndConverges) {
  const ControllerConfig config = OmniConfig();
  MotionController controller(config);
  controller.SetCommand(TurnTo(-2.0f));
  PointMass body;
  body.heading_rad = 1.0f;

  const DriveCommand first = controller.Update(Perfect(0, 0, body.heading_rad), 0);
  for (int step = 1; step < 300 && !controller.arrived(); ++step) {
    body.Step(controller.Update(Perfect(0, 0, body.heading_rad), step * kStepNs), config.limits.max_accel_mps2);
  }

  EXPECT_FLOAT_EQ(first.yaw_rate_radps, -3.0f);  // error -3 rad: capped, turning the short way
  EXPECT_EQ(first.vx_mps, 0.0f);
  EXPECT_TRUE(controller.arrived());
  EXPECT_LE(std::fabs(WrapAngle(body.heading_rad + 2.0f)), config.heading_tolerance_rad);
}

TEST(MotionControllerTest, StopCommandsZero) {
  MotionController controller(OmniConfig());
  controller.SetCommand(Velocity(0.2f, 0));
  controller.Update(Perfect(0, 0, 0), 0);
  syrof_car_command stop{};
  stop.kind = SYROF_COMMAND_STOP;

  controller.SetCommand(stop);
  const DriveCommand drive = controller.Update(Perfect(0, 0, 0), kStepNs);

  EXPECT_EQ(drive.vx_mps, 0.0f);
  EXPECT_EQ(drive.vy_mps, 0.0f);
  EXPECT_TRUE(controller.arrived());
  EXPECT_EQ(controller.invalid_commands(), 0u);
}

TEST(MotionControllerTest, NonFiniteMoveToBecomesStop) {
  MotionController controller(OmniConfig());

  controller.SetCommand(MoveTo(std::numeric_limits<float>::quiet_NaN(), 1, 0.3f));
  const DriveCommand drive = controller.Update(Perfect(0, 0, 0), 0);

  EXPECT_EQ(controller.command().kind, SYROF_COMMAND_STOP);
  EXPECT_EQ(controller.invalid_commands(), 1u);
  EXPECT_EQ(drive.vx_mps, 0.0f);
  EXPECT_TRUE(controller.arrived());
}

TEST(MotionControllerTest, InvalidCommandsAreCountedAndStop) {
  MotionController controller(OmniConfig());
  syrof_car_command unknown{};
  unknown.kind = 9;
  syrof_car_command infinite_velocity = Velocity(std::numeric_limits<float>::infinity(), 0);

  controller.SetCommand(unknown);
  controller.SetCommand(MoveTo(1, 1, 0.0f));  // speed must be > 0
  controller.SetCommand(infinite_velocity);
  const DriveCommand drive = controller.Update(Perfect(0, 0, 0), 0);

  EXPECT_EQ(controller.invalid_commands(), 3u);
  EXPECT_EQ(controller.command().kind, SYROF_COMMAND_STOP);
  EXPECT_EQ(drive.vx_mps, 0.0f);
}

TEST(MotionControllerTest, AMoveToBeyondWhatAMapCarriesBecomesStop) {
  // The controller applies app::CheckCommand, the rules the runtime reports.
  MotionController controller(OmniConfig());

  controller.SetCommand(MoveTo(40, 1, 0.3f));

  EXPECT_EQ(controller.invalid_commands(), 1u);
  EXPECT_EQ(controller.command().kind, SYROF_COMMAND_STOP);
}

TEST(MotionControllerTest, FieldsTheKindIgnoresMayHoldAnything) {
  MotionController controller(OmniConfig());
  syrof_car_command command = Velocity(0.1f, 0);
  command.x_m = std::numeric_limits<float>::quiet_NaN();

  controller.SetCommand(command);

  EXPECT_EQ(controller.invalid_commands(), 0u);
  EXPECT_EQ(controller.command().kind, SYROF_COMMAND_VELOCITY);
}

TEST(MotionControllerTest, UninitializedEstimateCommandsZero) {
  MotionController controller(OmniConfig());
  controller.SetCommand(MoveTo(2, 2, 0.3f));
  estimation::StateEstimate estimate = Perfect(0, 0, 0);
  estimate.status = 0;

  const DriveCommand drive = controller.Update(estimate, 0);

  EXPECT_EQ(drive.vx_mps, 0.0f);
  EXPECT_EQ(drive.vy_mps, 0.0f);
  EXPECT_EQ(controller.blind_updates(), 1u);
}

TEST(MotionControllerTest, RoverReachesAPointBehindIt) {
  const ControllerConfig config = RoverConfig();
  MotionController controller(config);
  controller.SetCommand(MoveTo(1.2f, 2.1f, 0.3f));
  Rover rover;
  rover.x_m = 2.0f;
  rover.y_m = 2.0f;
  float fastest_wheel = 0;
  int steps = 0;

  for (; steps < 2000 && !controller.arrived(); ++steps) {
    const DriveCommand drive = controller.Update(Perfect(rover.x_m, rover.y_m, rover.heading_rad), steps * kStepNs);
    fastest_wheel = std::max({fastest_wheel, std::fabs(drive.left_mps), std::fabs(drive.right_mps)});
    EXPECT_EQ(drive.kind, DriveKind::kWheels);
    EXPECT_EQ(drive.vx_mps, 0.0f);
    rover.Step(drive, config.limits);
  }

  EXPECT_LT(steps, 2000) << "never arrived";
  EXPECT_LE(std::hypot(rover.x_m - 1.2f, rover.y_m - 2.1f), config.position_tolerance_m);
  EXPECT_LE(fastest_wheel, config.limits.max_speed_mps + 1e-6f);
}

TEST(MotionControllerTest, RoverTurnsInPlaceFirstWhenTheTargetIsBehind) {
  MotionController controller(RoverConfig());
  controller.SetCommand(MoveTo(0, 0.1f, 0.3f));  // behind and slightly left of a rover facing +x

  const DriveCommand drive = controller.Update(Perfect(1, 0, 0), 0);

  EXPECT_FLOAT_EQ(drive.left_mps, -drive.right_mps);
  EXPECT_GT(drive.right_mps, 0.0f);  // counter-clockwise: the short way round
}

TEST(MotionControllerTest, RoverTurnToTurnsInPlaceAndArrives) {
  const ControllerConfig config = RoverConfig();
  MotionController controller(config);
  controller.SetCommand(TurnTo(-1.5f));
  Rover rover;

  const DriveCommand first = controller.Update(Perfect(0, 0, 0), 0);
  for (int step = 1; step < 500 && !controller.arrived(); ++step) {
    rover.Step(controller.Update(Perfect(rover.x_m, rover.y_m, rover.heading_rad), step * kStepNs), config.limits);
  }

  EXPECT_FLOAT_EQ(first.left_mps, -first.right_mps);
  EXPECT_LT(first.right_mps, 0.0f);  // clockwise
  EXPECT_TRUE(controller.arrived());
  EXPECT_LE(std::fabs(WrapAngle(rover.heading_rad + 1.5f)), config.heading_tolerance_rad);
  EXPECT_NEAR(rover.x_m, 0.0f, 1e-6f);
}

TEST(MotionControllerTest, RoverVelocityAlongTheHeadingDrivesBothWheelsAtTheSpeed) {
  MotionController controller(RoverConfig());
  controller.SetCommand(Velocity(0, 1.0f));  // faster than the rover may go

  const DriveCommand drive = controller.Update(Perfect(0, 0, std::numbers::pi_v<float> / 2), 0);

  EXPECT_NEAR(drive.left_mps, 0.4f, 1e-6f);
  EXPECT_NEAR(drive.right_mps, 0.4f, 1e-6f);
}

TEST(MotionControllerTest, RoverVelocityAgainstTheHeadingTurnsFirst) {
  MotionController controller(RoverConfig());
  controller.SetCommand(Velocity(-0.2f, 0));

  const DriveCommand drive = controller.Update(Perfect(0, 0, 0.1f), 0);

  EXPECT_FLOAT_EQ(drive.left_mps, -drive.right_mps);
  EXPECT_NE(drive.left_mps, 0.0f);
}

TEST(MotionControllerTest, RoverSteeringKeepsWheelsWithinMaxSpeed) {
  const ControllerConfig config = RoverConfig();
  MotionController controller(config);
  controller.SetCommand(Velocity(0.4f, 0.2f));  // at the limit, 0.46 rad off the heading

  const DriveCommand drive = controller.Update(Perfect(0, 0, 0), 0);

  EXPECT_LE(std::max(std::fabs(drive.left_mps), std::fabs(drive.right_mps)), config.limits.max_speed_mps + 1e-6f);
  EXPECT_GT(drive.right_mps, drive.left_mps);  // steering left toward the vector
}


syrof_car_command Stop() {
  syrof_car_command command{};
  command.kind = SYROF_COMMAND_STOP;
  return command;
}

// A drone's controller: a tilt lag and hold_position.
ControllerConfig DroneConfig() {
  ControllerConfig config = OmniConfig();
  config.limits.response_lag_s = 0.25f;
  config.position_gain_per_s = 2.0f;
  config.hold_position = true;
  return config;
}

TEST(MotionControllerTest, ALaggedMoveToBrakesOnTheLaggedCurve) {
  const ControllerConfig config = DroneConfig();
  MotionController controller(config);
  controller.SetCommand(MoveTo(3.0f, 0.0f, 0.5f));
  // 0.5 m short of the target, the braking curve with the lag binds.
  const DriveCommand drive = controller.Update(Perfect(2.5f, 0, 0), kStepNs);
  const float braking = config.braking_fraction * config.limits.max_accel_mps2;
  EXPECT_NEAR(drive.vx_mps, std::min({0.5f, BrakingSpeed(0.5f, braking, 0.25f), 2.0f * 0.5f}), 1e-6f);
  EXPECT_LT(drive.vx_mps, std::sqrt(2.0f * braking * 0.5f));
}

TEST(MotionControllerTest, AHoldingControllerKeepsAStoppedDroneWhereItStopped) {
  MotionController controller(DroneConfig());
  controller.SetCommand(Stop());
  // The first usable estimate is the hold point: nothing to correct yet.
  DriveCommand drive = controller.Update(Perfect(1.0f, 1.0f, 0), kStepNs);
  EXPECT_EQ(drive.vx_mps, 0.0f);
  EXPECT_TRUE(controller.hold().set);
  // Drifted 4 cm along +x: steered back at gain * distance.
  drive = controller.Update(Perfect(1.04f, 1.0f, 0), 2 * kStepNs);
  EXPECT_NEAR(drive.vx_mps, -2.0f * 0.04f, 1e-5f);
  EXPECT_NEAR(drive.vy_mps, 0.0f, 1e-6f);
  EXPECT_TRUE(controller.arrived());
  // Another STOP keeps the same point; a MOVE_TO and a STOP after it hold anew.
  controller.SetCommand(Stop());
  drive = controller.Update(Perfect(1.04f, 1.0f, 0), 3 * kStepNs);
  EXPECT_NEAR(drive.vx_mps, -0.08f, 1e-5f);
  controller.SetCommand(MoveTo(2.0f, 1.0f, 0.3f));
  controller.SetCommand(Stop());
  drive = controller.Update(Perfect(1.5f, 1.0f, 0), 4 * kStepNs);
  EXPECT_EQ(drive.vx_mps, 0.0f);
  EXPECT_FLOAT_EQ(controller.hold().x_m, 1.5f);
}

TEST(MotionControllerTest, AnArrivedDroneKeepsSteeringToItsTargetAndAnOmniDoesNot) {
  MotionController drone(DroneConfig());
  MotionController omni(OmniConfig());
  drone.SetCommand(MoveTo(1.0f, 1.0f, 0.3f));
  omni.SetCommand(MoveTo(1.0f, 1.0f, 0.3f));
  // 1 cm off: within the tolerance, arrived.
  const DriveCommand held = drone.Update(Perfect(1.01f, 1.0f, 0), kStepNs);
  const DriveCommand still = omni.Update(Perfect(1.01f, 1.0f, 0), kStepNs);
  EXPECT_TRUE(drone.arrived());
  EXPECT_TRUE(omni.arrived());
  EXPECT_NEAR(held.vx_mps, -0.02f, 1e-5f);
  EXPECT_EQ(still.vx_mps, 0.0f);
  EXPECT_FALSE(omni.hold().set);
}

}  // namespace
}  // namespace syrof::motion
