#include "syrof/lab/world/arena.h"

namespace syrof::lab::world {

KindSpec DefaultKindSpec(RobotKind kind) {
  const motion::KindLimits limits = motion::DefaultKindLimits(kind);
  KindSpec spec;
  spec.body_radius_m = limits.body_radius_m;
  spec.max_speed_mps = limits.max_speed_mps;
  spec.max_accel_mps2 = limits.max_accel_mps2;
  spec.max_turn_rate_radps = limits.max_turn_rate_radps;
  spec.wheel_base_m = limits.wheel_base_m;
  spec.tilt_time_constant_s = limits.tilt_time_constant_s;
  spec.flight_height_m = limits.flight_height_m;
  if (kind == RobotKind::kDrone) spec.drift_sigma_mps = 0.005;
  return spec;
}

motion::KindLimits LimitsOf(const KindSpec& spec) {
  motion::KindLimits limits;
  limits.body_radius_m = spec.body_radius_m;
  limits.max_speed_mps = spec.max_speed_mps;
  limits.max_accel_mps2 = spec.max_accel_mps2;
  limits.max_turn_rate_radps = spec.max_turn_rate_radps;
  limits.wheel_base_m = spec.wheel_base_m;
  limits.tilt_time_constant_s = spec.tilt_time_constant_s;
  limits.flight_height_m = spec.flight_height_m;
  return limits;
}

double StoppingDistanceM(const KindSpec& spec) {
  const double v = spec.max_speed_mps;
  return v * v / (2 * spec.max_accel_mps2) + v * spec.tilt_time_constant_s;
}

}  // namespace syrof::lab::world
