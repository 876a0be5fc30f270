// A swarm of synchronizers driven round by round in memory, for the scripted
// scenario tests, the exhaustive exploration and the step benchmark. It plays
// the radio (who hears whom each round), the maneuvers (each lasts a fixed
// number of rounds) and the checks of docs/protocol.md's properties.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "syrof/sync/synchronizer.h"

namespace syrof::sync::testing {

/// The snapshot robot `id` freezes at the end of `epoch`'s maneuver: distinct
/// per robot and per epoch (modulo 3), so a stale or foreign snapshot shows.
inline wire::Snapshot SnapshotFor(uint16_t id, uint16_t epoch) {
  wire::Snapshot snapshot;
  snapshot.x_mm = static_cast<int16_t>(100 * id + epoch % 3);
  snapshot.y_mm = static_cast<int16_t>(-7 * id);
  snapshot.payload_length = 1;
  snapshot.payload[0] = static_cast<uint8_t>(id);
  return snapshot;
}

struct Robot {
  SyncConfig config;
  SyncState state;
  StepOutput out;
  bool alive = true;
  bool present = true;        // false until a joiner is switched on
  uint16_t progress_rounds = 0;  // rounds spent in PROGRESS of the current epoch
};

/// One epoch start as the checks see it.
struct EpochStart {
  uint16_t robot = 0;
  int round = 0;
  LDMap ldmap;
};

class Swarm {
 public:
  /// `n` robots, ids 0..n-1, all initial members unless listed in `late`.
  Swarm(uint16_t n, uint8_t vote_rounds, uint16_t silence_rounds, uint16_t maneuver_rounds,
        std::vector<uint16_t> late = {})
      : maneuver_rounds_(maneuver_rounds) {
    for (uint16_t id = 0; id < n; ++id) {
      Robot robot;
      robot.config = SyncConfig::ForSwarm(n, id);
      robot.config.vote_rounds = vote_rounds;
      robot.config.silence_rounds = silence_rounds;
      for (const uint16_t later : late) robot.config.initial_members.reset(later);
      robot.state = InitialState(robot.config, SnapshotFor(id, 0));
      robot.out.beacon = MakeBeacon(robot.config, robot.state);
      robot.out.send = robot.state.status == Status::kMember;
      for (const uint16_t later : late) {
        if (later == id) robot.present = false;
      }
      robots_.push_back(robot);
    }
  }

  /// Whether robot `to` hears robot `from` in round `round`.
  using Link = std::function<bool(uint16_t from, uint16_t to, int round)>;

  /// Runs one radio round: every live robot's beacon goes to every other live
  /// robot the link lets through; then every live robot steps.
  void RunRound(const Link& link) {
    const size_t n = robots_.size();
    std::vector<std::vector<wire::Beacon>> inbox(n);
    for (uint16_t from = 0; from < n; ++from) {
      const Robot& sender = robots_[from];
      if (!sender.alive || !sender.present || !sender.out.send) continue;
      for (uint16_t to = 0; to < n; ++to) {
        if (to == from || !robots_[to].alive || !robots_[to].present) continue;
        if (link(from, to, round_)) inbox[to].push_back(sender.out.beacon);
      }
    }
    for (uint16_t id = 0; id < n; ++id) {
      Robot& robot = robots_[id];
      if (!robot.alive || !robot.present) continue;
      StepInput input;
      input.own_snapshot = SnapshotFor(id, robot.state.epoch);
      input.maneuver_finished = robot.state.status == Status::kMember &&
                                robot.state.phase == Phase::kProgress &&
                                robot.progress_rounds >= maneuver_rounds_;
      if (robot.state.status == Status::kMember && robot.state.phase == Phase::kProgress) {
        ++robot.progress_rounds;
      }
      Step(robot.config, robot.state, inbox[id], input, robot.out, ldmap_);
      if (robot.out.epoch_started) {
        robot.progress_rounds = 0;
        starts_[ldmap_.epoch].push_back(EpochStart{id, round_, ldmap_});
      }
      for (const uint16_t gone : robot.out.removed) removals_.push_back({id, gone, round_});
      for (const uint16_t added : robot.out.joined) joins_.push_back({id, added, round_});
    }
    ++round_;
  }

  void Run(int rounds, const Link& link) {
    for (int i = 0; i < rounds; ++i) RunRound(link);
  }

  /// Every robot hears every other.
  static bool Lossless(uint16_t, uint16_t, int) { return true; }

  void Crash(uint16_t id) { robots_[id].alive = false; }
  void SwitchOn(uint16_t id) { robots_[id].present = true; }

  const Robot& robot(uint16_t id) const { return robots_[id]; }
  int round() const { return round_; }
  const std::map<uint16_t, std::vector<EpochStart>>& starts() const { return starts_; }

  struct MembershipEvent {
    uint16_t observer;
    uint16_t subject;
    int round;
  };
  const std::vector<MembershipEvent>& removals() const { return removals_; }
  const std::vector<MembershipEvent>& joins() const { return joins_; }

  /// P3: epochs in which two robots started COOPERATIVE with different maps.
  int CommonKnowledgeViolations() const {
    int violations = 0;
    for (const auto& [epoch, list] : starts_) {
      const LDMap* first = nullptr;
      for (const EpochStart& start : list) {
        if (start.ldmap.mode != Mode::kCooperative) continue;
        if (first == nullptr) {
          first = &start.ldmap;
        } else if (!first->SameKnowledge(start.ldmap)) {
          ++violations;
          break;
        }
      }
    }
    return violations;
  }

  /// P2: the largest difference in start round among robots starting one epoch.
  int MaxStartSkew() const {
    int worst = 0;
    for (const auto& [epoch, list] : starts_) {
      int low = list.front().round;
      int high = low;
      for (const EpochStart& start : list) {
        low = std::min(low, start.round);
        high = std::max(high, start.round);
      }
      worst = std::max(worst, high - low);
    }
    return worst;
  }

  /// Epochs started by `id`, and how many of them COOPERATIVE.
  std::pair<int, int> EpochsOf(uint16_t id) const {
    int started = 0;
    int cooperative = 0;
    for (const auto& [epoch, list] : starts_) {
      for (const EpochStart& start : list) {
        if (start.robot != id) continue;
        ++started;
        if (start.ldmap.mode == Mode::kCooperative) ++cooperative;
      }
    }
    return {started, cooperative};
  }

 private:
  std::vector<Robot> robots_;
  uint16_t maneuver_rounds_;
  int round_ = 0;
  LDMap ldmap_;
  std::map<uint16_t, std::vector<EpochStart>> starts_;
  std::vector<MembershipEvent> removals_;
  std::vector<MembershipEvent> joins_;
};

}  // namespace syrof::sync::testing
