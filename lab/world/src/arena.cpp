#include "syrof/lab/world/arena.h"

namespace syrof::lab::world {

const char* ToString(RobotKind kind) {
  switch (kind) {
    case RobotKind::kOmni:
      return "omni";
    case RobotKind::kRover:
      return "rover";
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
  return spec;
}

}  // namespace syrof::lab::world
