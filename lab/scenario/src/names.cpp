// Enum names and the robot-count limit.
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
    case FaultKind::kDeaf:
      return "deaf";
    case FaultKind::kMute:
      return "mute";
  }
  return "?";
}

int MaxRobots() { return wire::kMaxSwarmSize; }

}  // namespace syrof::lab::scenario
