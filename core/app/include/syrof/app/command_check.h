// The rules a syrof_car_command must meet (docs/apps.md, "Commands"), as one
// pure check. The robot runtime checks every command newRound returns: a
// command that breaks a rule is reported and replaced by STOP; the motion
// controller applies the same check to whatever it is given.
#pragma once

#include <cstddef>
#include <cstdint>

#include "syrof/app.h"

namespace syrof::app {

/// Largest |x_m| and |y_m| of a MOVE_TO target: the positions a map can
/// carry (the beacon's int16 millimetres).
inline constexpr float kMaxTargetM = 32.767f;

/// What is wrong with a command.
enum class CommandError : uint8_t {
  kOk = 0,
  kUnknownKind,       ///< `kind` is no syrof_command_kind
  kNotFinite,         ///< a field the kind uses is NaN or infinite
  kOutOfRange,        ///< a MOVE_TO target beyond kMaxTargetM
  kSpeedNotPositive,  ///< a MOVE_TO speed_mps that is zero or negative
};

/// "ok", "unknown_kind", "not_finite", "out_of_range", "speed_not_positive";
/// "?" for a value outside the enum.
const char* ToString(CommandError error);

/// The first rule `command` breaks, and where.
struct CommandCheck {
  CommandError error = CommandError::kOk;
  const char* field = "";  ///< the field at fault ("kind", "x_m", ...); "" when ok
  uint8_t kind = 0;        ///< the command's kind, as given

  bool ok() const { return error == CommandError::kOk; }
};

/// Checks `command` field by field, in declaration order: the kind must be a
/// syrof_command_kind; MOVE_TO needs finite x_m and y_m within kMaxTargetM
/// and a finite speed_mps > 0; VELOCITY finite vx_mps and vy_mps (any size:
/// the robot caps its speed); TURN_TO a finite heading_rad (any angle: it is
/// wrapped). Fields the kind does not use are not looked at.
CommandCheck CheckCommand(const syrof_car_command& command);

/// Describes `check` for a report, e.g. "MOVE_TO x_m is not finite",
/// "kind 7 is unknown", into `out` (NUL-terminated, truncated to `size`).
/// Returns `out`.
char* Describe(const CommandCheck& check, char* out, size_t size);

}  // namespace syrof::app
