#include "syrof/firmware/swarm/fault_player.h"

#include <algorithm>

namespace syrof::firmware::swarm {

const char* ToString(HostAction::Kind kind) {
  switch (kind) {
    case HostAction::Kind::kSwitchOn: return "switch on";
    case HostAction::Kind::kKill: return "kill";
    case HostAction::Kind::kStop: return "stop";
    case HostAction::Kind::kContinue: return "continue";
  }
  return "?";
}

bool HostActions::StartRobot(uint16_t id, int64_t world_ns, bool resume) {
  return act_(HostAction{resume ? HostAction::Kind::kContinue : HostAction::Kind::kSwitchOn, id}, world_ns);
}

void HostActions::StopRobot(uint16_t id, int64_t world_ns, lab::sim::StopReason reason) {
  switch (reason) {
    case lab::sim::StopReason::kCrash: (void)act_(HostAction{HostAction::Kind::kKill, id}, world_ns); break;
    case lab::sim::StopReason::kPause: (void)act_(HostAction{HostAction::Kind::kStop, id}, world_ns); break;
    case lab::sim::StopReason::kAppFault: break;
  }
}

RadioFaults::RadioFaults(const lab::scenario::Scenario& scenario) {
  for (const lab::scenario::FaultSpec& fault : scenario.faults) {
    if (lab::scenario::IsRadioFault(fault.kind)) faults_.push_back(fault);
  }
}

bool RadioFaults::Blocked(uint16_t from, uint16_t to, double time_s) const {
  return std::any_of(faults_.begin(), faults_.end(), [&](const lab::scenario::FaultSpec& fault) {
    const uint16_t robot = fault.kind == lab::scenario::FaultKind::kMute ? from : to;
    return fault.robot == robot && fault.at_s <= time_s && time_s < fault.until_s;
  });
}

uint32_t RemainingMs(int run_seconds, int64_t start_ns) {
  const int64_t left_ms = int64_t{run_seconds} * 1000 - start_ns / 1'000'000;
  return static_cast<uint32_t>(std::clamp<int64_t>(left_ms, 1, UINT32_MAX));
}

}  // namespace syrof::firmware::swarm
