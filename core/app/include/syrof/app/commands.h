// Builders for the app's command (syrof_car_command, syrof/app.h) from C++:
// one call per command, every field the kind does not use left zero, which
// is what app::CheckCommand and the motion controllers expect.
#pragma once

#include "syrof/app.h"

namespace syrof::app {

/// Go to (x_m, y_m), arena frame, at up to `speed_mps` (> 0), then stop.
constexpr syrof_car_command MoveToCommand(float x_m, float y_m, float speed_mps) {
  syrof_car_command command{};
  command.kind = SYROF_COMMAND_MOVE_TO;
  command.x_m = x_m;
  command.y_m = y_m;
  command.speed_mps = speed_mps;
  return command;
}

/// Move with (vx_mps, vy_mps), arena frame.
constexpr syrof_car_command VelocityCommand(float vx_mps, float vy_mps) {
  syrof_car_command command{};
  command.kind = SYROF_COMMAND_VELOCITY;
  command.vx_mps = vx_mps;
  command.vy_mps = vy_mps;
  return command;
}

/// Turn in place to `heading_rad`.
constexpr syrof_car_command TurnToCommand(float heading_rad) {
  syrof_car_command command{};
  command.kind = SYROF_COMMAND_TURN_TO;
  command.heading_rad = heading_rad;
  return command;
}

}  // namespace syrof::app
