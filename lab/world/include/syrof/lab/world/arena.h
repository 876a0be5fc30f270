// What a world is made of: the arena (walls and UWB anchors) and the robot
// kinds (body and kinematic limits). A scenario (lab/scenario) holds these;
// the world is built from them.
//
// Units are in the names. Arena frame: origin at the arena's lower-left
// corner, x right, y up, z up from the floor.
#pragma once

#include <cstdint>
#include <vector>

#include "syrof/motion/robot_kind.h"

namespace syrof::lab::world {

/// A UWB anchor, metres.
struct AnchorSpec {
  double x_m = 0;
  double y_m = 0;
  double z_m = 0;
};

/// A rectangular arena [0, width] x [0, height] with walls on its four sides.
struct ArenaSpec {
  double width_m = 4;
  double height_m = 4;
  /// Default: the paper's layout stretched over the arena, (0,0,0), (W,H,0),
  /// (0,H,2), (W,0,2): estimation::DefaultArena() on the default 4 m x 4 m.
  /// 3 to estimation::kMaxAnchors once loaded.
  std::vector<AnchorSpec> anchors;
};

/// The robot kinds are the motion layer's (motion/robot_kind.h: omni,
/// rover, drone), so the lab and the robot image name and configure them
/// alike. ToString gives "omni", "rover" or "drone".
using RobotKind = motion::RobotKind;
using motion::ToString;

/// The body and kinematic limits of a robot kind. Defaults per kind come from
/// DefaultKindSpec(); a scenario may override any field.
struct KindSpec {
  double body_radius_m = 0.1;          ///< bodies are discs
  double max_speed_mps = 0.5;          ///< omni, drone: |v|; rover: each wheel's ground speed
  double max_accel_mps2 = 1.0;         ///< omni, drone: |dv/dt| (speeding up and braking); rover: each wheel's
  double max_turn_rate_radps = 3.0;    ///< omni, drone: yaw rate limit
  double wheel_base_m = 0.16;          ///< rover only: distance between the wheels
  /// Drone only: the velocity follows the commanded one as a first-order lag
  /// with this time constant (the time the body takes to tilt), within
  /// max_accel. 0 for the other kinds.
  double tilt_time_constant_s = 0;
  /// Drone only: standard deviation of the drift velocity (air, an
  /// imperfect hover), per axis; a Gauss-Markov process with correlation
  /// time kDriftCorrelationS drawn from the world's seed. 0 for the others.
  double drift_sigma_mps = 0;
  /// Drone only: the fixed height it flies at (its flow sensor and UWB
  /// antenna are there). 0 for the others (their sensors' heights are the
  /// scenario's sensor geometry).
  double flight_height_m = 0;
};

/// Correlation time of a drone's drift velocity, s.
inline constexpr double kDriftCorrelationS = 2.0;

/// The defaults: the motion layer's (motion::DefaultKindLimits: omni radius
/// 0.10 m, 0.5 m/s, 1.0 m/s^2, 3 rad/s; rover radius 0.12 m, 0.4 m/s,
/// 0.8 m/s^2, wheel base 0.16 m; drone radius 0.12 m (its rotors), 0.8 m/s,
/// 0.5 m/s^2, 3 rad/s, tilt time constant 0.25 s, flight height 0.30 m, the
/// ones the robot image has compiled in), and a drone's drift 0.005 m/s.
KindSpec DefaultKindSpec(RobotKind kind);

/// `spec` less the drift: what a robot's motion layer knows of its kind.
motion::KindLimits LimitsOf(const KindSpec& spec);

/// How far a body of this kind moving at its top speed travels before it
/// stops when commanded to: v^2 / 2a, plus v tau for a drone (its velocity
/// goes on at full speed for about one tilt time constant before braking
/// takes hold; an upper bound of the lagged body's distance, which is
/// v^2 / 2a + a tau^2 / 2 when v >= a tau, and v tau otherwise).
double StoppingDistanceM(const KindSpec& spec);

}  // namespace syrof::lab::world
