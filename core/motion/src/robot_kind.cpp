#include "syrof/motion/robot_kind.h"

#include <algorithm>
#include <cstring>

namespace syrof::motion {

namespace {

constexpr const char* kKindNames[kRobotKindCount] = {"omni", "rover", "drone"};  // RobotKind's order

}  // namespace

const char* ToString(RobotKind kind) {
  const auto index = static_cast<size_t>(kind);
  return index < kRobotKindCount ? kKindNames[index] : "?";
}

bool ParseRobotKind(const char* name, RobotKind& kind) {
  for (size_t i = 0; i < kRobotKindCount; ++i) {
    if (std::strcmp(name, kKindNames[i]) == 0) {
      kind = static_cast<RobotKind>(i);
      return true;
    }
  }
  return false;
}

ControllerConfig ControllerConfigFor(RobotKind kind, const KindLimits& limits) {
  ControllerConfig config;
  config.kind = DriveKindFor(kind);
  config.limits.max_speed_mps = static_cast<float>(limits.max_speed_mps);
  config.limits.max_accel_mps2 = static_cast<float>(limits.max_accel_mps2);
  config.limits.max_turn_rate_radps = static_cast<float>(limits.max_turn_rate_radps);
  config.limits.wheel_base_m = static_cast<float>(limits.wheel_base_m);
  config.limits.body_radius_m = static_cast<float>(limits.body_radius_m);
  if (kind == RobotKind::kDrone) {
    config.limits.response_lag_s = static_cast<float>(limits.tilt_time_constant_s);
    // Position loop k over a velocity lag tau: damping 1 / (2 sqrt(k tau)),
    // 0.5 at the omni's 4/s with 0.25 s; 2/s gives 0.71 and no overshoot
    // worth the name.
    config.position_gain_per_s = kDronePositionGainPerS;
    config.hold_position = true;  // it drifts: hover in place rather than let go
  }
  return config;
}

void SetOthers(SafetyConfig& safety, std::span<const SwarmKind> swarm) {
  bool first = true;
  for (const SwarmKind& present : swarm) {
    const ControllerConfig controller = ControllerConfigFor(present.kind, present.limits);
    const float braking = controller.braking_fraction * controller.limits.max_accel_mps2;
    safety.others_max_speed_mps =
        first ? controller.limits.max_speed_mps : std::max(safety.others_max_speed_mps, controller.limits.max_speed_mps);
    safety.others_radius_m =
        first ? controller.limits.body_radius_m : std::max(safety.others_radius_m, controller.limits.body_radius_m);
    safety.others_braking_mps2 = first ? braking : std::min(safety.others_braking_mps2, braking);
    safety.others_lag_s = std::max(safety.others_lag_s, controller.limits.response_lag_s);
    first = false;
  }
}

}  // namespace syrof::motion
