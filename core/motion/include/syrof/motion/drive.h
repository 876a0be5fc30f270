// The drive command: what a robot's motion controller asks of its actuators,
// published on kDriveTopic at the motion task's rate. The firmware's motor
// driver and the lab's simulated bodies subscribe to it, so the controller
// cannot tell which runtime it runs in.
#pragma once

#include <cstdint>

#include "syrof/pubsub/topic.h"
#include "syrof/registry/topics.h"

namespace syrof::motion {

/// How the actuators are commanded; one per robot kind.
enum class DriveKind : uint8_t {
  kOmni = 0,   ///< a velocity vector and a yaw rate (omnidirectional wheels)
  kWheels = 1, ///< left and right wheel ground speeds (differential drive)
};

/// One actuator command. Arena frame for the omni velocity; wheel speeds are
/// ground speeds, positive forward. The fields of the other kind are zero.
struct DriveCommand {
  int64_t timestamp_ns = 0;     ///< port clock when computed
  DriveKind kind = DriveKind::kOmni;
  uint8_t reserved[3] = {};
  float vx_mps = 0;             ///< omni: velocity setpoint, arena frame, m/s
  float vy_mps = 0;
  float yaw_rate_radps = 0;     ///< omni: yaw rate setpoint, rad/s, counter-clockwise
  float left_mps = 0;           ///< wheels: left wheel ground speed setpoint, m/s
  float right_mps = 0;          ///< wheels: right wheel ground speed setpoint, m/s
};

static_assert(sizeof(DriveCommand) == 8 + 4 + 5 * 4, "DriveCommand has no padding");

/// Id and name from the robot's topic list (syrof/registry/topics.h).
inline constexpr pubsub::Topic<DriveCommand> kDriveTopic{registry::topics::kDrive.id, registry::topics::kDrive.name};

}  // namespace syrof::motion
