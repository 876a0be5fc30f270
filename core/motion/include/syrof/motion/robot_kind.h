// The robot kinds (omni, rover, drone) as a robot's motion layer knows them:
// each kind's default body and limits, the controller a robot of a kind runs,
// and the safety filter's view of a swarm of given kinds. The lab
// (lab/sim robot_config.h: a scenario's `kinds:` and robots) and the robot
// image (firmware/robot: its `kind` boot words, the default limits compiled
// in) both configure a robot through these, so a drone on the firmware runs
// the controller and braking model of the lab's drone. The estimator's part
// (a drone's flow sensor and antenna at its flight height) is
// runtime::ConfigureKinds (runtime/robot_kinds.h).
//
// Portable: no allocation; the limits are doubles as a scenario gives them
// (the defaults are constants) and become the controller's floats here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/motion/controller.h"
#include "syrof/motion/drive.h"
#include "syrof/motion/safety_filter.h"

namespace syrof::motion {

enum class RobotKind : uint8_t {
  kOmni = 0,   ///< omnidirectional (the paper's robots): commanded by a velocity vector
  kRover = 1,  ///< differential drive: commanded by wheel speeds
  kDrone = 2,  ///< planar multirotor at a fixed flight height: commanded by a velocity vector, through a tilt lag
};
inline constexpr size_t kRobotKindCount = 3;

/// "omni", "rover" or "drone"; "?" otherwise.
const char* ToString(RobotKind kind);
/// The kind named `name` (ToString's words); false for any other.
bool ParseRobotKind(const char* name, RobotKind& kind);

/// A drone's position gain (1/s): its velocity follows the setpoint through
/// its tilt lag tau, and a position loop of gain k over that lag is damped
/// 1 / (2 sqrt(k tau)): 0.5 at the omni's 4/s and 0.25 s, 0.71 at 2/s.
inline constexpr float kDronePositionGainPerS = 2.0f;

/// A kind's body and limits, SI units (a scenario's `kinds.<kind>`, less
/// what only the world plays: a drone's drift).
struct KindLimits {
  double body_radius_m = 0.1;        ///< bodies are discs
  double max_speed_mps = 0.5;        ///< omni, drone: |v|; rover: each wheel's ground speed
  double max_accel_mps2 = 1.0;       ///< omni, drone: |dv/dt|; rover: each wheel's
  double max_turn_rate_radps = 3.0;  ///< omni, drone: yaw rate limit
  double wheel_base_m = 0.16;        ///< rover only: distance between the wheels
  double tilt_time_constant_s = 0;   ///< drone only: the velocity's lag behind the command; 0 for the others
  double flight_height_m = 0;        ///< drone only: the height its flow sensor and UWB antenna fly at; 0 for the others
};

/// The defaults: omni radius 0.10 m, 0.5 m/s, 1.0 m/s^2, 3 rad/s; rover
/// radius 0.12 m, 0.4 m/s, 0.8 m/s^2, wheel base 0.16 m; drone radius 0.12 m
/// (its rotors), 0.8 m/s, 0.5 m/s^2, 3 rad/s, tilt time constant 0.25 s,
/// flight height 0.30 m. The lab's world::DefaultKindSpec and the robot
/// image take them from here.
constexpr KindLimits DefaultKindLimits(RobotKind kind) {
  KindLimits limits;  // the struct's defaults are the omni robot's
  if (kind == RobotKind::kRover) {
    limits.body_radius_m = 0.12;
    limits.max_speed_mps = 0.4;
    limits.max_accel_mps2 = 0.8;
    limits.wheel_base_m = 0.16;
  }
  if (kind == RobotKind::kDrone) {
    limits.body_radius_m = 0.12;
    limits.max_speed_mps = 0.8;
    limits.max_accel_mps2 = 0.5;
    limits.tilt_time_constant_s = 0.25;
    limits.flight_height_m = 0.30;
  }
  return limits;
}

/// The drive a kind is commanded with: omni and drone a velocity, rover wheels.
constexpr DriveKind DriveKindFor(RobotKind kind) {
  return kind == RobotKind::kRover ? DriveKind::kWheels : DriveKind::kOmni;
}

/// A motion controller configuration with `limits` (as floats) and the
/// default gains and tolerances; the drive kind follows the robot kind. A
/// drone's response lag is its tilt time constant, its position gain
/// kDronePositionGainPerS, and it holds its position (it drifts).
ControllerConfig ControllerConfigFor(RobotKind kind, const KindLimits& limits);

/// One kind present in a swarm, with its limits.
struct SwarmKind {
  RobotKind kind = RobotKind::kOmni;
  KindLimits limits{};
};

/// Sets `safety`'s view of the other robots from the kinds present in the
/// swarm (each once; a beacon does not say its sender's kind): the fastest
/// speed limit, the largest body, the weakest braking (braking_fraction x
/// max_accel) and the longest response lag among them. Nothing else changes;
/// an empty `swarm` changes nothing.
void SetOthers(SafetyConfig& safety, std::span<const SwarmKind> swarm);

}  // namespace syrof::motion
