// What a world is made of: the arena (walls and UWB anchors) and the robot
// kinds (body and kinematic limits). A scenario (lab/scenario) holds these;
// the world is built from them.
//
// Units are in the names. Arena frame: origin at the arena's lower-left
// corner, x right, y up, z up from the floor.
#pragma once

#include <cstdint>
#include <vector>

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

enum class RobotKind : uint8_t {
  kOmni = 0,   ///< omnidirectional (the paper's robots): commanded by a velocity vector
  kRover = 1,  ///< differential drive: commanded by wheel speeds
};

/// "omni" or "rover"; "?" otherwise.
const char* ToString(RobotKind kind);

/// The body and kinematic limits of a robot kind. Defaults per kind come from
/// DefaultKindSpec(); a scenario may override any field.
struct KindSpec {
  double body_radius_m = 0.1;          ///< bodies are discs
  double max_speed_mps = 0.5;          ///< omni: |v|; rover: each wheel's ground speed
  double max_accel_mps2 = 1.0;         ///< omni: |dv/dt|; rover: each wheel's
  double max_turn_rate_radps = 3.0;    ///< omni: yaw rate limit
  double wheel_base_m = 0.16;          ///< rover only: distance between the wheels
};

/// The defaults: omni radius 0.10 m, 0.5 m/s, 1.0 m/s^2, 3 rad/s; rover
/// radius 0.12 m, 0.4 m/s, 0.8 m/s^2, wheel base 0.16 m.
KindSpec DefaultKindSpec(RobotKind kind);

}  // namespace syrof::lab::world
