// Enum names, the robot-count limit and error formatting.
#include "syrof/lab/scenario/scenario.h"
#include "syrof/wire/member_set.h"

namespace syrof::lab::scenario {

const char* ToString(Placement placement) {
  switch (placement) {
    case Placement::kExplicit:
      return "explicit";
    case Placement::kGrid:
      return "grid";
    case Placement::kCircle:
      return "circle";
    case Placement::kRandom:
      return "random";
  }
  return "?";
}

const char* ToString(FaultKind kind) {
  switch (kind) {
    case FaultKind::kCrash:
      return "crash";
    case FaultKind::kPause:
      return "pause";
    case FaultKind::kJoin:
      return "join";
  }
  return "?";
}

int MaxRobots() { return wire::kMaxSwarmSize; }

std::string ScenarioError::ToString() const {
  if (line <= 0) return file + ": " + message;
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
}

}  // namespace syrof::lab::scenario
