#include "syrof/firmware/swarm/fault_outcomes.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace syrof::firmware::swarm {
namespace {

std::string Seconds(int64_t ns) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f s", static_cast<double>(ns) * 1e-9);
  return text;
}

bool Holds(const sync::LDMap& map, uint16_t robot) { return map.members.test(robot); }

}  // namespace

FaultOutcomes::FaultOutcomes(uint16_t robots) : robots_(robots), latest_(robots), latest_ns_(robots, 0) {}

void FaultOutcomes::OnAction(const HostAction& action, int64_t world_ns) {
  if (action.robot >= robots_) return;
  switch (action.kind) {
    case HostAction::Kind::kKill:
      crashes_.push_back(Crash{action.robot, world_ns, std::vector<std::optional<bool>>(robots_), std::nullopt});
      order_.push_back({action.kind, crashes_.size() - 1});
      break;
    case HostAction::Kind::kStop: {
      Pause pause{};
      pause.robot = action.robot;
      pause.stop_ns = world_ns;
      pause.last_before = latest_[action.robot];
      pause.last_before_ns = latest_ns_[action.robot];
      pauses_.push_back(pause);
      order_.push_back({action.kind, pauses_.size() - 1});
      break;
    }
    case HostAction::Kind::kContinue:
      for (auto it = pauses_.rbegin(); it != pauses_.rend(); ++it) {
        if (it->robot == action.robot && !it->continue_ns) {
          it->continue_ns = world_ns;
          break;
        }
      }
      break;
    case HostAction::Kind::kSwitchOn:
      joins_.push_back(Join{action.robot, world_ns, std::nullopt, std::nullopt});
      order_.push_back({action.kind, joins_.size() - 1});
      break;
  }
}

void FaultOutcomes::OnRoundLine(const RoundLine& line, int64_t world_ns) {
  if (line.robot >= robots_) return;
  latest_[line.robot] = line;
  latest_ns_[line.robot] = world_ns;
  for (Pause& pause : pauses_) {
    if (pause.robot != line.robot || !pause.continue_ns) continue;
    if (!pause.first_after) {
      pause.first_after = line;
      pause.first_after_ns = world_ns;
    }
    if (!line.member) pause.saw_non_member = true;
    if (line.member && !pause.member_again_ns) pause.member_again_ns = world_ns;
  }
  for (Join& join : joins_) {
    if (join.robot == line.robot && line.member && !join.member_ns) join.member_ns = world_ns;
  }
}

void FaultOutcomes::OnEpochLine(const EpochLine& line, int64_t world_ns) {
  if (line.robot >= robots_) return;
  for (Join& join : joins_) {
    if (join.robot != line.robot && !join.in_map_ns && Holds(line.map, join.robot)) join.in_map_ns = world_ns;
  }
  for (Crash& crash : crashes_) {
    if (line.robot == crash.robot) continue;
    const bool holds = Holds(line.map, crash.robot);
    crash.last_holds[line.robot] = holds;
    if (!holds && !crash.first_without_ns) crash.first_without_ns = world_ns;
  }
}

std::vector<FaultOutcome> FaultOutcomes::Finish(const std::vector<lab::sim::Lifecycle>& final_presence) const {
  std::vector<FaultOutcome> outcomes;
  for (const Event& event : order_) {
    FaultOutcome outcome;
    outcome.kind = event.kind;
    if (event.kind == HostAction::Kind::kKill) {
      const Crash& crash = crashes_[event.index];
      outcome.robot = crash.robot;
      outcome.at_ns = crash.at_ns;
      int judged = 0;
      std::string holding;
      for (uint16_t id = 0; id < robots_; ++id) {
        const bool running = id < final_presence.size() && final_presence[id] == lab::sim::Lifecycle::kRunning;
        if (id == crash.robot || !running || !crash.last_holds[id]) continue;
        ++judged;
        if (*crash.last_holds[id]) holding += (holding.empty() ? "" : ", ") + std::to_string(id);
      }
      outcome.ok = judged > 0 && holding.empty();
      if (outcome.ok && crash.first_without_ns) outcome.done_ns = crash.first_without_ns;
      outcome.detail = "crash of " + std::to_string(crash.robot) + " at " + Seconds(crash.at_ns) + ": " +
                       (judged == 0 ? "no running robot started an epoch after it"
                        : !holding.empty()
                            ? "still in the latest epoch map of robot(s) " + holding
                            : "removed by the others (first epoch without it at " +
                                  Seconds(crash.first_without_ns.value_or(0)) + ")");
    } else if (event.kind == HostAction::Kind::kStop) {
      const Pause& pause = pauses_[event.index];
      outcome.robot = pause.robot;
      outcome.at_ns = pause.stop_ns;
      outcome.ok = pause.continue_ns.has_value() && pause.member_again_ns.has_value();
      outcome.done_ns = pause.member_again_ns;
      outcome.rejoined_as_joiner = pause.saw_non_member;
      if (pause.last_before && pause.first_after) {
        outcome.guest_gap_ms = pause.first_after->t_ms - pause.last_before->t_ms;
        outcome.world_gap_ms = (pause.first_after_ns - pause.last_before_ns) / 1'000'000;
      }
      std::string text = "pause of " + std::to_string(pause.robot) + " at " + Seconds(pause.stop_ns);
      if (!pause.continue_ns) {
        text += ": not resumed before the end";
      } else if (!pause.first_after) {
        text += ", resumed at " + Seconds(*pause.continue_ns) + ": no report since";
      } else if (!pause.member_again_ns) {
        text += ", resumed at " + Seconds(*pause.continue_ns) + ": reports again, never MEMBER since";
      } else {
        text += ", resumed at " + Seconds(*pause.continue_ns) + ": MEMBER again at " + Seconds(*pause.member_again_ns) +
                (pause.saw_non_member ? " (rejoined as a joiner)" : " (stayed a member)");
      }
      if (outcome.guest_gap_ms) {
        text += "; its clock moved " + std::to_string(*outcome.guest_gap_ms) + " ms across " +
                std::to_string(*outcome.world_gap_ms) + " ms of world time";
      }
      outcome.detail = text;
    } else {
      const Join& join = joins_[event.index];
      outcome.robot = join.robot;
      outcome.at_ns = join.at_ns;
      outcome.ok = join.member_ns.has_value() && join.in_map_ns.has_value();
      if (outcome.ok) outcome.done_ns = std::max(*join.member_ns, *join.in_map_ns);
      outcome.detail = "join of " + std::to_string(join.robot) + " at " + Seconds(join.at_ns) + ": " +
                       (outcome.ok ? "MEMBER at " + Seconds(*join.member_ns) + ", in another robot's epoch map at " +
                                         Seconds(*join.in_map_ns)
                        : !join.member_ns ? "never reported MEMBER"
                                          : "in no other robot's epoch map");
    }
    outcomes.push_back(std::move(outcome));
  }
  return outcomes;
}

}  // namespace syrof::firmware::swarm
