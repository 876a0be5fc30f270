// Enum names, the per-kind defaults and error formatting.
#include "syrof/lab/scenario/scenario.h"
#include "syrof/wire/member_set.h"

namespace syrof::lab::scenario {

const char* ToString(RobotKind kind) {
  switch (kind) {
    case RobotKind::kOmni:
      return "omni";
    case RobotKind::kRover:
      return "rover";
  }
  return "?";
}

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

const char* ToString(ChannelModel model) {
  switch (model) {
    case ChannelModel::kIid:
      return "iid";
    case ChannelModel::kGilbertElliott:
      return "gilbert_elliott";
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

int MaxRobots() { return wire::kMaxSwarmSize; }

std::string ScenarioError::ToString() const {
  if (line <= 0) return file + ": " + message;
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
}

}  // namespace syrof::lab::scenario
