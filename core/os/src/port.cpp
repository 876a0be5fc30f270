#include "syrof/os/port.h"

namespace syrof::os {

const char* ToString(PortError error) {
  switch (error) {
    case PortError::kOk: return "ok";
    case PortError::kTooManyTasks: return "too many tasks";
    case PortError::kInvalidTrigger: return "invalid trigger";
    case PortError::kAlreadyStarted: return "already started";
    case PortError::kNotStarted: return "not started";
    case PortError::kSystemError: return "system error";
    case PortError::kUnsupported: return "unsupported";
  }
  return "unknown port error";
}

PortError Validate(const Trigger& trigger) {
  if (trigger.kind == TriggerKind::kPeriodic && (trigger.period_ns <= 0 || trigger.offset_ns < 0)) {
    return PortError::kInvalidTrigger;
  }
  if (trigger.kind != TriggerKind::kPeriodic && trigger.kind != TriggerKind::kNotified) {
    return PortError::kInvalidTrigger;
  }
  return PortError::kOk;
}

}  // namespace syrof::os
