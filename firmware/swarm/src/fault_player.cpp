#include "syrof/firmware/swarm/fault_player.h"

#include <algorithm>

namespace syrof::firmware::swarm {

const char* ToString(Presence presence) {
  switch (presence) {
    case Presence::kAbsent: return "absent";
    case Presence::kRunning: return "running";
    case Presence::kPaused: return "paused";
    case Presence::kCrashed: return "crashed";
  }
  return "?";
}

const char* ToString(HostAction::Kind kind) {
  switch (kind) {
    case HostAction::Kind::kLaunch: return "launch";
    case HostAction::Kind::kKill: return "kill";
    case HostAction::Kind::kStop: return "stop";
    case HostAction::Kind::kContinue: return "continue";
  }
  return "?";
}

FaultPlayer::FaultPlayer(const lab::scenario::Scenario& scenario, int64_t radio_round_ns)
    : schedule_(scenario.faults, radio_round_ns) {
  for (const lab::scenario::RobotSpec& robot : scenario.robots) {
    presence_.push_back(robot.present_at_start ? Presence::kRunning : Presence::kAbsent);
  }
  for (const lab::scenario::FaultSpec& fault : scenario.faults) {
    if (lab::scenario::IsRadioFault(fault.kind)) radio_faults_.push_back(fault);
  }
}

std::vector<HostAction> FaultPlayer::Advance(int64_t world_ns) {
  using Kind = lab::sim::FaultAction::Kind;
  std::vector<HostAction> actions;
  for (const lab::sim::FaultAction& fault : schedule_.Due(world_ns)) {
    if (fault.robot >= presence_.size()) continue;
    Presence& presence = presence_[fault.robot];
    switch (fault.kind) {
      case Kind::kCrash:
        // A robot not switched on yet cannot be crashed (the loader refuses
        // a crash before a join); a paused one is killed as it is.
        if (presence == Presence::kRunning || presence == Presence::kPaused) {
          actions.push_back({HostAction::Kind::kKill, fault.robot});
          presence = Presence::kCrashed;
        }
        break;
      case Kind::kPause:
        if (presence == Presence::kRunning) {
          actions.push_back({HostAction::Kind::kStop, fault.robot});
          presence = Presence::kPaused;
        }
        break;
      case Kind::kResume:
        if (presence == Presence::kPaused) {
          actions.push_back({HostAction::Kind::kContinue, fault.robot});
          presence = Presence::kRunning;
        }
        break;
      case Kind::kJoin:
        if (presence == Presence::kAbsent) {
          actions.push_back({HostAction::Kind::kLaunch, fault.robot});
          presence = Presence::kRunning;
        }
        break;
    }
  }
  return actions;
}

bool FaultPlayer::Blocked(uint16_t from, uint16_t to, double time_s) const {
  return std::any_of(radio_faults_.begin(), radio_faults_.end(), [&](const lab::scenario::FaultSpec& fault) {
    const uint16_t robot = fault.kind == lab::scenario::FaultKind::kMute ? from : to;
    return fault.robot == robot && fault.at_s <= time_s && time_s < fault.until_s;
  });
}

int FaultPlayer::RemainingSeconds(int run_seconds, int64_t launch_ns) {
  const int64_t left_ns = int64_t{run_seconds} * 1'000'000'000 - launch_ns;
  return static_cast<int>(std::max<int64_t>(1, (left_ns + 999'999'999) / 1'000'000'000));
}

}  // namespace syrof::firmware::swarm
