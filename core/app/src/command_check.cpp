#include "syrof/app/command_check.h"

#include <cmath>

#include "text.h"

namespace syrof::app {
namespace {

CommandCheck Fail(const syrof_car_command& command, CommandError error, const char* field) {
  return CommandCheck{error, field, command.kind};
}

const char* KindName(uint8_t kind) {
  switch (kind) {
    case SYROF_COMMAND_STOP: return "STOP";
    case SYROF_COMMAND_MOVE_TO: return "MOVE_TO";
    case SYROF_COMMAND_VELOCITY: return "VELOCITY";
    case SYROF_COMMAND_TURN_TO: return "TURN_TO";
    default: return nullptr;
  }
}

}  // namespace

const char* ToString(CommandError error) {
  switch (error) {
    case CommandError::kOk: return "ok";
    case CommandError::kUnknownKind: return "unknown_kind";
    case CommandError::kNotFinite: return "not_finite";
    case CommandError::kOutOfRange: return "out_of_range";
    case CommandError::kSpeedNotPositive: return "speed_not_positive";
  }
  return "?";
}

CommandCheck CheckCommand(const syrof_car_command& command) {
  switch (command.kind) {
    case SYROF_COMMAND_STOP:
      return CommandCheck{CommandError::kOk, "", command.kind};
    case SYROF_COMMAND_MOVE_TO:
      if (!std::isfinite(command.x_m)) return Fail(command, CommandError::kNotFinite, "x_m");
      if (!std::isfinite(command.y_m)) return Fail(command, CommandError::kNotFinite, "y_m");
      if (!std::isfinite(command.speed_mps)) return Fail(command, CommandError::kNotFinite, "speed_mps");
      if (std::fabs(command.x_m) > kMaxTargetM) return Fail(command, CommandError::kOutOfRange, "x_m");
      if (std::fabs(command.y_m) > kMaxTargetM) return Fail(command, CommandError::kOutOfRange, "y_m");
      if (!(command.speed_mps > 0.0f)) return Fail(command, CommandError::kSpeedNotPositive, "speed_mps");
      return CommandCheck{CommandError::kOk, "", command.kind};
    case SYROF_COMMAND_VELOCITY:
      if (!std::isfinite(command.vx_mps)) return Fail(command, CommandError::kNotFinite, "vx_mps");
      if (!std::isfinite(command.vy_mps)) return Fail(command, CommandError::kNotFinite, "vy_mps");
      return CommandCheck{CommandError::kOk, "", command.kind};
    case SYROF_COMMAND_TURN_TO:
      if (!std::isfinite(command.heading_rad)) return Fail(command, CommandError::kNotFinite, "heading_rad");
      return CommandCheck{CommandError::kOk, "", command.kind};
    default:
      return Fail(command, CommandError::kUnknownKind, "kind");
  }
}

char* Describe(const CommandCheck& check, char* out, size_t size) {
  detail::TextBuilder text(out, size);
  const char* kind = KindName(check.kind);
  switch (check.error) {
    case CommandError::kOk:
      text.Append(kind != nullptr ? kind : "?").Append(" is valid");
      break;
    case CommandError::kUnknownKind:
      text.Append("kind ").Append(static_cast<uint32_t>(check.kind)).Append(" is unknown");
      break;
    case CommandError::kNotFinite:
      text.Append(kind).Append(" ").Append(check.field).Append(" is not finite");
      break;
    case CommandError::kOutOfRange:
      text.Append(kind).Append(" ").Append(check.field).Append(" is beyond 32.767 m");
      break;
    case CommandError::kSpeedNotPositive:
      text.Append(kind).Append(" ").Append(check.field).Append(" is not > 0");
      break;
  }
  return out;
}

}  // namespace syrof::app
