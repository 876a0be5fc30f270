#include "syrof/lab/world/arena.h"

namespace syrof::lab::world {

const char* ToString(RobotKind kind) {
  switch (kind) {
    case RobotKind::kOmni:
      return "omni";
    case RobotKind::kRover:
      return "rover";
    case RobotKind::kDrone:
      return "drone";
  }
  return "?";
}

KindSpec DefaultKindSpec(RobotKind kind) {
  KindSpec spec;  // the struct's defaults are the omni robot's
  if (kind == RobotKind::kRover) {
    spec.body_radius_m = 0.12;
    spec.max_speed_mps = 0.4;
    spec.max_accel_mps2 = 0.8;
    spec.wheel_base_m = 0.16;
  }
  if (kind == RobotKind::kDrone) {
    spec.body_radius_m = 0.12;
    spec.max_speed_mps = 0.8;
    spec.max_accel_mps2 = 0.5;
    spec.tilt_time_constant_s = 0.25;
    spec.drift_sigma_mps = 0.005;
    spec.flight_height_m = 0.30;
  }
  return spec;
}

double StoppingDistanceM(const KindSpec& spec) {
  const double v = spec.max_speed_mps;
  return v * v / (2 * spec.max_accel_mps2) + v * spec.tilt_time_constant_s;
}

}  // namespace syrof::lab::world
