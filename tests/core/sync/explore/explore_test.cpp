// Exhaustive exploration of the synchronizer on its real step function:
// breadth-first over the global states of a small swarm, every per-link loss
// pattern in every round, with a visited set. Built with
// SYROF_MAX_SWARM_SIZE=4 (like the firmware is built with 32), so a state is a
// few hundred bytes.
//
// Adversaries (docs/protocol.md, "Verification"):
//   a) every link loses fewer than K beacons in a row; maneuvers last D or
//      D + 1 rounds, chosen per robot and epoch: checks P1 and P3, and that
//      epochs keep starting;
//   b) any loss at all, up to a depth: checks P3, reports the largest start
//      skew and mode disagreement reached;
//   c) as (a), plus one robot crashing at any round, or one robot switched
//      on at any round: checks P3 and P6;
//   d) as (a), plus one robot paused at any round for any number of rounds,
//      then resumed: after a short pause as it is, or as after a pause so
//      long that the others' 16-bit epochs have come round to the same
//      numbers (every later snapshot differs from every earlier one, so a
//      robot holding an old snapshot shows): checks P3;
//   e) (a) and (b) starting at epoch 65533, with no reduction of epochs, so
//      the wrap to 0 happens inside the explored space: checks P1 and P3;
//   f) as (a), plus robot 0 turning deaf (hears nobody, is heard) or mute
//      (hears, is not heard) at any round: checks P3 and that the others
//      start COOPERATIVE epochs again within a bound;
//   g) dead directed links: every link starts dead or alive (every pattern);
//      then links change, each at most once, one a round (any number of
//      them with three robots, one with four), at any round; no
//      other loss, maneuvers of D rounds: checks P3 and that, within a bound
//      of the last change, some
//      robot starts a COOPERATIVE epoch on a quorum whose members all hear
//      each other, whenever the connectivity rule applied to the true links
//      keeps a quorum;
//   h) timing: a robot's round task runs 1 to L rounds late, as a stopped
//      process's or a late QEMU guest's does, any robot, any number of
//      times, one at a time. While late it neither steps nor sends (its
//      last beacon went out after its last step) but still receives; its
//      late step is told the rounds that passed and gets everything that
//      arrived meanwhile, oldest first (the synchronizer keeps the first
//      beacon of each sender), either at once or, as when every arrival is
//      stamped after the late release, with the next round's beacons;
//      with loss < K (three robots) or no loss (four): checks P3.
// A violation prints the shortest round-by-round trace that reaches it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdio>
#include <cstring>
#include <deque>
#include <string>
#include <unordered_map>
#include <vector>

#include "syrof/sync/synchronizer.h"

namespace syrof::sync {
namespace {

static_assert(wire::kMaxSwarmSize == 4, "the exploration is built for swarms of at most 4");

constexpr uint16_t kMaxRobots = 4;
constexpr uint8_t kCap = 15;  // counters in the global state saturate here
// g) Rounds after the last change of the links by which robots that hear
// each other must start a COOPERATIVE epoch (about four epochs of D = 2).
constexpr uint8_t kDeadLinkBound = 30;

// `era` counts pauses that spanned a wrap of the epoch numbers: snapshots
// taken after one differ from every snapshot taken before.
wire::Snapshot SnapshotFor(uint16_t id, uint16_t epoch, uint8_t era = 0) {
  wire::Snapshot snapshot;
  snapshot.x_mm = static_cast<int16_t>(100 * id + 10 * era + epoch % 3);
  return snapshot;
}

enum class Adversary { kBoundedLoss, kAnyLoss, kCrash, kJoin, kPause, kDeaf, kMute, kDeadLinks, kLate, kLateNoLoss };

// h) Beacons a late robot may hold: L late rounds, the round it catches up
// and the next one (when carried), from each of three others.
constexpr size_t kLateBuffer = 16;

// A pause long enough for the others' epochs to wrap to the same numbers.
constexpr uint32_t kWrapPauseRounds = 2u * 65536u * 8u;

struct Params {
  Adversary adversary;
  uint16_t robots;
  uint8_t vote_rounds;       // K
  uint16_t silence_rounds;   // F
  uint16_t maneuver_rounds;  // D
  int max_depth;             // rounds; 0 = until no new state
  uint16_t first_epoch = 0;  // where the initial members start (e: near the wrap)
  int max_link_changes = 0;  // g) links that may change after the first round
  uint8_t max_late_rounds = 0;  // h) L: how late a round task may run
};

// What the checks remember about one epoch.
struct EpochRecord {
  bool used = false;
  uint16_t epoch = 0;
  uint8_t age = 0;              // rounds since its first start (saturating)
  bool cooperative_seen = false;
  uint8_t members = 0;          // of the first COOPERATIVE map
  std::array<int16_t, kMaxRobots> x_mm{};  // its snapshots (the harness's encoding)
};

struct Robot {
  SyncState state;
  bool alive = true;
  bool present = true;
  bool paused = false;
  bool resuming = false;       // resumed this round: listens, steps, has nothing to send yet
  uint8_t paused_rounds = 0;   // saturating
  uint8_t progress_rounds = 0;
  // h) Timing: late (its task has not run for late_rounds rounds), and the
  // beacons that arrived meanwhile; `carried`: they wait for the next step.
  bool late = false;
  bool carried = false;
  uint8_t late_rounds = 0;
  uint8_t buffered = 0;
  std::array<wire::Beacon, kLateBuffer> buffer{};
};

struct Global {
  std::array<Robot, kMaxRobots> robots;
  std::array<std::array<uint8_t, kMaxRobots>, kMaxRobots> consecutive_losses{};  // [from][to]
  std::array<EpochRecord, 6> records{};
  uint8_t rounds_without_start = 0;
  uint8_t disagreement_rounds = 0;
  bool fault_used = false;
  int8_t crashed = -1;
  uint8_t since_fault = 0;
  int8_t joiner = -1;
  uint16_t joiner_first_epoch = 0;
  bool joiner_started = false;
  uint8_t era = 0;             // d) pauses that spanned a wrap
  bool deaf = false;           // f) robot 0 hears nobody
  bool mute = false;           // f) nobody hears robot 0
  uint8_t since_cooperative = 0;  // f) rounds since the others' last COOPERATIVE start (saturating)
  bool links_chosen = false;   // g) the first round chose which links start dead
  uint16_t dead = 0;           // g) bit from * robots + to: never delivered
  uint16_t flipped = 0;        // g) links that have changed once
};

// One round's choices: the delivered links, which robots' maneuvers end,
// and the fault injected at the start of the round.
struct Choice {
  uint16_t delivered = 0;   // bit from * robots + to
  uint8_t finishing = 0;    // robots whose maneuver ends this round (if allowed)
  int8_t crash = -1;
  int8_t switch_on = -1;
  int8_t pause = -1;
  int8_t resume = -1;
  bool wrapped = false;     // the resume comes after a pause spanning a wrap
  bool silence = false;     // f) robot 0 turns deaf or mute
  int32_t initial_dead = -1;  // g) the links dead from the start
  int8_t flip = -1;          // g) the link that changes this round
  int8_t late = -1;          // h) this robot's round task starts running late
  int8_t catch_up = -1;      // h) the late robot's task runs now
  bool defer = false;        // h) ... and what arrived meanwhile waits for its next step
};

struct Outcome {
  std::string violation;  // empty when the successor is fine
  int skew = 0;
  int disagreement = 0;
  int epochs_started = 0;
  int back_to_cooperative = 0;  // f) rounds the others went without a COOPERATIVE start after the fault
};

class Explorer {
 public:
  explicit Explorer(const Params& params) : params_(params) {
    for (uint16_t id = 0; id < params.robots; ++id) {
      SyncConfig config = SyncConfig::ForSwarm(params.robots, id);
      config.vote_rounds = params.vote_rounds;
      config.silence_rounds = params.silence_rounds;
      if (params.adversary == Adversary::kJoin) config.initial_members.reset(params.robots - 1);
      configs_[id] = config;
    }
    for (uint16_t id = 0; id < params.robots; ++id) {
      initial_.robots[id].state = InitialState(configs_[id], SnapshotFor(id, params.first_epoch));
      initial_.robots[id].state.epoch = params.first_epoch;
    }
    if (params.adversary == Adversary::kJoin) {
      initial_.robots[params.robots - 1].present = false;
      initial_.joiner = static_cast<int8_t>(params.robots - 1);
    }
  }

  struct Report {
    size_t states = 0;
    size_t transitions = 0;
    int depth = 0;
    bool exhausted = false;  // no new state: the whole reachable space was seen
    int max_skew = 0;
    int max_disagreement = 0;
    int max_back_to_cooperative = 0;
    std::string violation;
  };

  Report Run() {
    Report report;
    // Visited states by the hash of their canonical form, each with the
    // state it was first reached from and how: the shortest path back.
    struct Seen {
      uint64_t parent;
      Choice choice;
    };
    std::unordered_map<uint64_t, Seen> seen;
    std::vector<Global> frontier{initial_};
    const uint64_t initial_key = Key(initial_);
    seen.emplace(initial_key, Seen{initial_key, Choice{}});
    std::vector<Choice> choices;
    for (int depth = 0; params_.max_depth == 0 || depth < params_.max_depth; ++depth) {
      std::vector<Global> next;
      for (const Global& global : frontier) {
        const uint64_t key = Key(global);
        Choices(global, choices);
        for (uint32_t index = 0; index < choices.size(); ++index) {
          Global successor = global;
          const Outcome outcome = Apply(successor, choices[index]);
          ++report.transitions;
          report.max_skew = std::max(report.max_skew, outcome.skew);
          report.max_disagreement = std::max(report.max_disagreement, outcome.disagreement);
          report.max_back_to_cooperative = std::max(report.max_back_to_cooperative, outcome.back_to_cooperative);
          const uint64_t successor_key = Key(successor);
          const bool fresh = seen.emplace(successor_key, Seen{key, choices[index]}).second;
          if (!outcome.violation.empty()) {
            std::vector<Choice> path{choices[index]};
            for (uint64_t at = key; at != initial_key; at = seen.at(at).parent) {
              path.push_back(seen.at(at).choice);
            }
            std::reverse(path.begin(), path.end());
            report.violation = outcome.violation + "\n" + Trace(path);
            report.states = seen.size();
            report.depth = depth + 1;
            return report;
          }
          if (fresh) next.push_back(std::move(successor));
        }
      }
      report.depth = depth + 1;
      if (next.empty()) {
        report.exhausted = true;
        break;
      }
      frontier = std::move(next);
    }
    report.states = seen.size();
    return report;
  }

 private:
  void Choices(const Global& global, std::vector<Choice>& out) const {
    out.clear();
    const uint16_t n = params_.robots;
    // Links that carry a beacon this round, and whether each may be lost.
    std::vector<uint16_t> links;
    std::vector<bool> may_lose;
    uint16_t must = 0;
    for (uint16_t from = 0; from < n; ++from) {
      const Robot& sender = global.robots[from];
      if (!Sends(sender)) continue;
      for (uint16_t to = 0; to < n; ++to) {
        if (to == from || !Listens(global.robots[to])) continue;
        if ((global.deaf && to == 0) || (global.mute && from == 0)) continue;  // never delivered
        const uint16_t bit = static_cast<uint16_t>(1u << (from * n + to));
        if (params_.adversary == Adversary::kDeadLinks) {
          if ((global.dead & bit) == 0) must |= bit;  // no loss but the dead links
          continue;
        }
        const bool bounded = params_.adversary != Adversary::kAnyLoss;
        if (params_.adversary == Adversary::kLateNoLoss ||
            (bounded && global.consecutive_losses[from][to] + 1 >= params_.vote_rounds)) {
          must |= bit;
        } else {
          links.push_back(bit);
        }
      }
    }
    // Maneuvers: after D rounds a robot may finish; after D + 1 it must.
    std::vector<uint8_t> optional_finish;
    uint8_t forced = 0;
    for (uint16_t id = 0; id < n; ++id) {
      const Robot& robot = global.robots[id];
      if (!InProgress(robot)) continue;
      if (robot.progress_rounds + 1 >= params_.maneuver_rounds + 1) {
        forced |= static_cast<uint8_t>(1u << id);
      } else if (robot.progress_rounds + 1 >= params_.maneuver_rounds && VariableManeuvers()) {
        optional_finish.push_back(static_cast<uint8_t>(1u << id));
      }
    }
    // Faults: at most one per run, at the start of any round.
    std::vector<Choice> faults{Choice{}};
    auto fault = [&faults](auto set) {
      Choice choice;
      set(choice);
      faults.push_back(choice);
    };
    if (!global.fault_used && params_.adversary == Adversary::kCrash) {
      for (int8_t id = 0; id < static_cast<int8_t>(n); ++id) fault([id](Choice& c) { c.crash = id; });
    }
    if (!global.fault_used && params_.adversary == Adversary::kJoin) {
      fault([&global](Choice& c) { c.switch_on = global.joiner; });
    }
    if (params_.adversary == Adversary::kPause) {
      for (int8_t id = 0; id < static_cast<int8_t>(n); ++id) {
        const Robot& robot = global.robots[id];
        if (!global.fault_used) fault([id](Choice& c) { c.pause = id; });
        if (robot.paused) {
          fault([id](Choice& c) { c.resume = id; });
          if (global.era == 0) {
            fault([id](Choice& c) {
              c.resume = id;
              c.wrapped = true;
            });
          }
        }
      }
    }
    if (!global.fault_used && (params_.adversary == Adversary::kDeaf || params_.adversary == Adversary::kMute)) {
      fault([](Choice& c) { c.silence = true; });
    }
    if (params_.adversary == Adversary::kDeadLinks) {
      if (!global.links_chosen) {
        // Every pattern of dead links, from the first round.
        faults.clear();
        for (int32_t mask = 0; mask < (1 << (n * n)); ++mask) {
          if ((mask & DiagonalLinks()) != 0) continue;
          fault([mask](Choice& c) { c.initial_dead = mask; });
        }
      } else if (std::popcount(static_cast<unsigned>(global.flipped)) < params_.max_link_changes) {
        for (int8_t link = 0; link < static_cast<int8_t>(n * n); ++link) {
          if (((DiagonalLinks() | global.flipped) >> link) & 1u) continue;
          fault([link](Choice& c) { c.flip = link; });
        }
      }
    }
    if (LateAdversary()) {
      int8_t late = -1;
      for (int8_t id = 0; id < static_cast<int8_t>(n); ++id) {
        if (global.robots[id].late) late = id;
      }
      if (late < 0) {
        for (int8_t id = 0; id < static_cast<int8_t>(n); ++id) {
          if (!global.robots[id].carried) fault([id](Choice& c) { c.late = id; });
        }
      } else {
        // It may stay late up to L rounds, then must run.
        if (global.robots[late].late_rounds >= params_.max_late_rounds) faults.clear();
        fault([late](Choice& c) { c.catch_up = late; });
        fault([late](Choice& c) {
          c.catch_up = late;
          c.defer = true;
        });
      }
    }
    for (const Choice& injected : faults) {
      for (uint32_t finish_mask = 0; finish_mask < (1u << optional_finish.size()); ++finish_mask) {
        uint8_t finishing = forced;
        for (size_t i = 0; i < optional_finish.size(); ++i) {
          if ((finish_mask >> i) & 1u) finishing |= optional_finish[i];
        }
        for (uint32_t loss_mask = 0; loss_mask < (1u << links.size()); ++loss_mask) {
          uint16_t delivered = must;
          for (size_t i = 0; i < links.size(); ++i) {
            if (((loss_mask >> i) & 1u) == 0) delivered |= links[i];
          }
          Choice choice = injected;
          choice.delivered = delivered;
          choice.finishing = finishing;
          out.push_back(choice);
        }
      }
    }
  }

  bool LateAdversary() const {
    return params_.adversary == Adversary::kLate || params_.adversary == Adversary::kLateNoLoss;
  }
  bool VariableManeuvers() const {
    return params_.adversary != Adversary::kAnyLoss && params_.adversary != Adversary::kDeadLinks;
  }
  // Bits of the links from a robot to itself, which do not exist.
  uint16_t DiagonalLinks() const {
    uint16_t bits = 0;
    for (uint16_t id = 0; id < params_.robots; ++id) bits |= static_cast<uint16_t>(1u << (id * params_.robots + id));
    return bits;
  }
  bool Hears(const Global& global, uint16_t to, uint16_t from) const {
    return ((global.dead >> (from * params_.robots + to)) & 1u) == 0;
  }
  // g) The connectivity rule (docs/protocol.md) on the true links: while
  // some pair does not hear each other both ways, leave out the robot with
  // the most such partners, the higher id on a tie.
  uint8_t RuleOnTrueLinks(const Global& global) const {
    uint8_t kept = static_cast<uint8_t>((1u << params_.robots) - 1);
    while (true) {
      int worst = -1;
      int worst_count = 0;
      for (uint16_t c = 0; c < params_.robots; ++c) {
        if (((kept >> c) & 1u) == 0) continue;
        int count = 0;
        for (uint16_t p = 0; p < params_.robots; ++p) {
          if (p != c && ((kept >> p) & 1u) && (!Hears(global, c, p) || !Hears(global, p, c))) ++count;
        }
        if (count > 0 && count >= worst_count) {
          worst = c;
          worst_count = count;
        }
      }
      if (worst < 0) return kept;
      kept = static_cast<uint8_t>(kept & ~(1u << worst));
    }
  }
  bool AllHearEachOther(const Global& global, const MemberSet& members) const {
    for (const uint16_t a : members) {
      for (const uint16_t b : members) {
        if (a != b && !Hears(global, a, b)) return false;
      }
    }
    return true;
  }
  // A late robot sends the beacon of its last step in the round it falls
  // late, then nothing until it has stepped again.
  static bool Sends(const Robot& robot) {
    return robot.alive && robot.present && !robot.paused && !robot.resuming &&
           !(robot.late && robot.late_rounds > 0) && robot.state.status == Status::kMember;
  }
  static bool Listens(const Robot& robot) { return robot.alive && robot.present && !robot.paused; }
  static bool InProgress(const Robot& robot) {
    return Listens(robot) && robot.state.status == Status::kMember &&
           robot.state.phase == Phase::kProgress;
  }

  EpochRecord* Record(Global& global, uint16_t epoch) {
    for (EpochRecord& record : global.records) {
      if (record.used && record.epoch == epoch) return &record;
    }
    for (EpochRecord& record : global.records) {
      if (!record.used) {
        record = EpochRecord{};
        record.used = true;
        record.epoch = epoch;
        return &record;
      }
    }
    return nullptr;
  }

  Outcome Apply(Global& global, const Choice& choice, std::string* trace = nullptr) {
    Outcome outcome;
    const uint16_t n = params_.robots;
    for (EpochRecord& record : global.records) {
      if (record.used) record.age = static_cast<uint8_t>(std::min<int>(kCap, record.age + 1));
    }
    if (choice.crash >= 0) {
      global.robots[choice.crash].alive = false;
      global.fault_used = true;
      global.crashed = choice.crash;
      global.since_fault = 0;
    }
    if (choice.switch_on >= 0) {
      global.robots[choice.switch_on].present = true;
      global.fault_used = true;
      global.since_fault = 0;
    }
    if (choice.pause >= 0) {
      Robot& robot = global.robots[choice.pause];
      robot.paused = true;
      robot.paused_rounds = 0;
      global.fault_used = true;
    }
    uint32_t resume_elapsed = 1;
    if (choice.resume >= 0) {
      Robot& robot = global.robots[choice.resume];
      robot.paused = false;
      robot.resuming = true;
      resume_elapsed = robot.paused_rounds + 1u;
      if (choice.wrapped) {
        // The others ran ~65,536 epochs meanwhile and read the same numbers
        // now: nothing seen before is the same epoch any more.
        resume_elapsed += kWrapPauseRounds;
        global.era = 1;
        for (EpochRecord& record : global.records) record.used = false;
        // What the others hold now was frozen in the new era too.
        for (uint16_t other = 0; other < params_.robots; ++other) {
          if (other == choice.resume) continue;
          SyncState& state = global.robots[other].state;
          for (const uint16_t holder : state.held) state.snapshots[holder].x_mm = static_cast<int16_t>(state.snapshots[holder].x_mm + 10);
        }
      }
    }
    if (choice.late >= 0) {
      Robot& robot = global.robots[choice.late];
      robot.late = true;
      robot.late_rounds = 0;
    }
    for (Robot& robot : global.robots) {
      if (robot.paused) robot.paused_rounds = static_cast<uint8_t>(std::min<int>(kCap, robot.paused_rounds + 1));
    }
    if (choice.initial_dead >= 0) {
      global.links_chosen = true;
      global.dead = static_cast<uint16_t>(choice.initial_dead);
      global.since_cooperative = 0;
    }
    if (choice.flip >= 0) {
      global.dead ^= static_cast<uint16_t>(1u << choice.flip);
      global.flipped |= static_cast<uint16_t>(1u << choice.flip);
      global.since_cooperative = 0;
    }
    if (choice.silence) {
      global.deaf = params_.adversary == Adversary::kDeaf;
      global.mute = params_.adversary == Adversary::kMute;
      global.fault_used = true;
      global.since_cooperative = 0;
    }
    // The radio.
    std::array<wire::Beacon, kMaxRobots> beacons{};
    std::array<bool, kMaxRobots> sent{};
    for (uint16_t id = 0; id < n; ++id) {
      sent[id] = Sends(global.robots[id]);
      if (sent[id]) beacons[id] = MakeBeacon(configs_[id], global.robots[id].state);
    }
    std::array<std::array<wire::Beacon, kMaxRobots>, kMaxRobots> inbox{};
    std::array<size_t, kMaxRobots> inbox_size{};
    for (uint16_t from = 0; from < n; ++from) {
      if (!sent[from]) continue;
      for (uint16_t to = 0; to < n; ++to) {
        if (to == from || !Listens(global.robots[to])) continue;
        if ((choice.delivered >> (from * n + to)) & 1u) {
          inbox[to][inbox_size[to]++] = beacons[from];
          global.consecutive_losses[from][to] = 0;
        } else {
          global.consecutive_losses[from][to] =
              static_cast<uint8_t>(std::min<int>(kCap, global.consecutive_losses[from][to] + 1));
        }
      }
    }
    if (trace != nullptr) {
      *trace += "  heard:";
      for (uint16_t to = 0; to < n; ++to) {
        *trace += " " + std::to_string(to) + "<-{";
        for (size_t i = 0; i < inbox_size[to]; ++i) {
          *trace += (i ? "," : "") + std::to_string(inbox[to][i].robot_id);
        }
        *trace += "}";
      }
      *trace += "\n";
    }
    // Every live robot steps.
    std::array<bool, kMaxRobots> started{};
    std::array<LDMap, kMaxRobots> maps{};
    bool anyone_started = false;
    for (uint16_t id = 0; id < n; ++id) {
      Robot& robot = global.robots[id];
      if (!Listens(robot)) continue;
      StepInput input;
      // h) What this step hears: the round's beacons, after any that
      // arrived while the task was late (oldest first).
      std::span<const wire::Beacon> heard(inbox[id].data(), inbox_size[id]);
      std::array<wire::Beacon, kLateBuffer> late_inbox{};
      if (robot.late || robot.carried) {
        for (size_t i = 0; i < inbox_size[id] && robot.buffered < kLateBuffer; ++i) robot.buffer[robot.buffered++] = inbox[id][i];
        if (robot.late && choice.catch_up != id) {
          robot.late_rounds = static_cast<uint8_t>(robot.late_rounds + 1);
          continue;  // its task does not run this round
        }
        if (robot.late) input.rounds_elapsed = robot.late_rounds + 1u;
        const bool defer = robot.late && choice.defer;
        robot.late = false;
        robot.late_rounds = 0;
        robot.carried = defer;
        if (defer) {
          heard = {};
        } else {
          std::copy(robot.buffer.begin(), robot.buffer.begin() + robot.buffered, late_inbox.begin());
          heard = std::span<const wire::Beacon>(late_inbox.data(), robot.buffered);
          robot.buffered = 0;
          robot.buffer = {};
        }
      }
      input.own_snapshot = SnapshotFor(id, robot.state.epoch, global.era);
      if (robot.resuming) input.rounds_elapsed = resume_elapsed;
      robot.resuming = false;
      input.maneuver_finished = InProgress(robot) && ((choice.finishing >> id) & 1u);
      if (InProgress(robot)) robot.progress_rounds = static_cast<uint8_t>(std::min<int>(kCap, robot.progress_rounds + 1));
      StepOutput out;
      Step(configs_[id], robot.state, heard, input, out, maps[id]);
      if (out.epoch_started) {
        robot.progress_rounds = 0;
        started[id] = true;
        anyone_started = true;
        ++outcome.epochs_started;
      }
    }
    for (uint16_t id = 0; id < n; ++id) {
      if (!started[id]) continue;
      const LDMap& map = maps[id];
      EpochRecord* record = Record(global, map.epoch);
      if (record == nullptr) {
        outcome.violation = "harness: too many epochs in flight";
        return outcome;
      }
      outcome.skew = std::max<int>(outcome.skew, record->age);
      if (map.mode == Mode::kCooperative) {
        uint8_t members = 0;
        std::array<int16_t, kMaxRobots> x{};
        for (const uint16_t member : map.members) {
          members |= static_cast<uint8_t>(1u << member);
          x[member] = map.snapshots[member].x_mm;
        }
        if (!record->cooperative_seen) {
          record->cooperative_seen = true;
          record->members = members;
          record->x_mm = x;
        } else if (record->members != members || record->x_mm != x) {
          outcome.violation = "P3: robot " + std::to_string(id) + " started epoch " +
                              std::to_string(map.epoch) + " COOPERATIVE with another map";
        }
      }
      if (trace != nullptr) {
        *trace += "  robot " + std::to_string(id) + " starts epoch " + std::to_string(map.epoch) + " " +
                  wire::ToString(map.mode) + " with members {";
        for (const uint16_t member : map.members) *trace += " " + std::to_string(member);
        *trace += " }\n";
      }
    }
    // Forget epochs every live robot is past.
    for (EpochRecord& record : global.records) {
      if (!record.used) continue;
      bool someone_before_or_at = false;
      for (uint16_t id = 0; id < n; ++id) {
        const Robot& robot = global.robots[id];
        // A member paused for fewer than F rounds may resume and start the
        // epoch after its own (after F or more it rejoins).
        const bool may_resume = robot.alive && robot.paused && robot.paused_rounds < params_.silence_rounds;
        if (!Listens(robot) && !may_resume) continue;
        if (robot.state.status == Status::kMember && EpochDifference(robot.state.epoch, record.epoch) <= 0) {
          someone_before_or_at = true;
        }
      }
      if (!someone_before_or_at) record.used = false;
    }
    global.rounds_without_start =
        anyone_started ? 0 : static_cast<uint8_t>(std::min<int>(kCap, global.rounds_without_start + 1));

    // Mode disagreement: live members in the same epoch with different modes.
    bool disagree = false;
    for (uint16_t a = 0; a < n; ++a) {
      for (uint16_t b = static_cast<uint16_t>(a + 1); b < n; ++b) {
        const Robot& ra = global.robots[a];
        const Robot& rb = global.robots[b];
        if (!Sends(ra) || !Sends(rb)) continue;
        if (ra.state.epoch == rb.state.epoch && ra.state.epoch_mode != rb.state.epoch_mode) disagree = true;
      }
    }
    if (params_.adversary == Adversary::kAnyLoss) {
      global.disagreement_rounds =
          disagree ? static_cast<uint8_t>(std::min<int>(kCap, global.disagreement_rounds + 1)) : 0;
      outcome.disagreement = global.disagreement_rounds;
    }
    if (!outcome.violation.empty()) return outcome;

    const bool bounded = params_.adversary != Adversary::kAnyLoss && !LateAdversary();
    // P1 (bounded loss, no failure): everyone starts, or nobody, and in one epoch.
    if (params_.adversary == Adversary::kBoundedLoss && anyone_started) {
      for (uint16_t id = 0; id < n; ++id) {
        if (!started[id] || maps[id].epoch != maps[0].epoch) {
          outcome.violation = "P1: robot " + std::to_string(id) + " did not start epoch " +
                              std::to_string(maps[0].epoch) + " with robot 0";
          return outcome;
        }
      }
    }
    // Liveness under bounded loss: epochs keep starting.
    const int longest_epoch = params_.maneuver_rounds + 1 + params_.silence_rounds + 2 * params_.vote_rounds + 2;
    if (bounded && global.rounds_without_start > longest_epoch) {
      outcome.violation = "progress: no epoch started for " + std::to_string(global.rounds_without_start) + " rounds";
      return outcome;
    }
    // f) The others (a quorum) start COOPERATIVE epochs again: the rounds
    // since the fault, or since their last COOPERATIVE start, stay bounded.
    if (global.deaf || global.mute) {
      bool cooperative = false;
      for (uint16_t id = 1; id < n; ++id) cooperative = cooperative || (started[id] && maps[id].mode == Mode::kCooperative);
      global.since_cooperative =
          cooperative ? 0 : static_cast<uint8_t>(std::min<int>(kCap * 4, global.since_cooperative + 1));
      outcome.back_to_cooperative = global.since_cooperative;
      if (global.since_cooperative >= kCap * 4) {
        outcome.violation = "liveness: no COOPERATIVE start by the others for " +
                            std::to_string(global.since_cooperative) + " rounds with robot 0 " +
                            (global.deaf ? "deaf" : "mute");
        return outcome;
      }
    }
    // g) Within a bound of the last change of the links, some robot starts
    // a COOPERATIVE epoch on a quorum whose members all hear each other,
    // when the rule on the true links keeps a quorum.
    if (params_.adversary == Adversary::kDeadLinks) {
      const int quorum = params_.robots / 2 + 1;
      if (std::popcount(static_cast<unsigned>(RuleOnTrueLinks(global))) < quorum) {
        global.since_cooperative = 0;
      } else {
        bool cooperative = false;
        for (uint16_t id = 0; id < n; ++id) {
          if (started[id] && maps[id].mode == Mode::kCooperative && maps[id].members.count() >= quorum &&
              AllHearEachOther(global, maps[id].members)) {
            cooperative = true;
          }
        }
        global.since_cooperative =
            cooperative ? 0 : static_cast<uint8_t>(std::min<int>(kDeadLinkBound, global.since_cooperative + 1));
        outcome.back_to_cooperative = global.since_cooperative;
        if (global.since_cooperative >= kDeadLinkBound) {
          outcome.violation = "liveness: no COOPERATIVE start on robots that hear each other for " +
                              std::to_string(global.since_cooperative) + " rounds after the last change of links";
          return outcome;
        }
      }
    }
    // P6: a crashed robot leaves every member set within F rounds.
    if (global.crashed >= 0) {
      global.since_fault = static_cast<uint8_t>(std::min<int>(kCap, global.since_fault + 1));
      if (global.since_fault >= params_.silence_rounds) {
        for (uint16_t id = 0; id < n; ++id) {
          const Robot& robot = global.robots[id];
          if (Listens(robot) && robot.state.members.test(static_cast<uint16_t>(global.crashed))) {
            outcome.violation = "P6: robot " + std::to_string(id) + " still lists crashed robot " +
                                std::to_string(global.crashed) + " after F rounds";
            return outcome;
          }
        }
      }
    }
    // P6: a joiner is in every map from the second epoch after its first.
    if (global.joiner >= 0) {
      const uint16_t joiner = static_cast<uint16_t>(global.joiner);
      if (started[joiner] && !global.joiner_started) {
        global.joiner_started = true;
        global.joiner_first_epoch = maps[joiner].epoch;
      }
      for (uint16_t id = 0; id < n; ++id) {
        if (!started[id] || !global.joiner_started) continue;
        if (EpochDifference(maps[id].epoch, global.joiner_first_epoch) >= 2 &&
            !maps[id].members.test(joiner)) {
          outcome.violation = "P6: robot " + std::to_string(id) + " started epoch " +
                              std::to_string(maps[id].epoch) + " without the joiner";
          return outcome;
        }
      }
    }
    return outcome;
  }

  // The canonical form of a global state: epochs shifted by a multiple of 6
  // (snapshots encode epoch modulo 3, so the shift preserves them), and only
  // the fields that influence future behaviour.
  uint64_t Key(const Global& global) const {
    int base = 0x7fffffff;
    for (uint16_t id = 0; id < params_.robots; ++id) {
      const Robot& robot = global.robots[id];
      // A joiner's epoch only bounds which groups it may join from below,
      // and every member is past it, so it does not set the base.
      if (Listens(robot) && robot.state.status == Status::kMember) base = std::min<int>(base, robot.state.epoch);
    }
    if (base == 0x7fffffff) base = 0;
    base -= base % 6;
    if (params_.first_epoch != 0) base = 0;  // e) no reduction: the wrap stays visible
    std::string bytes;
    auto put = [&bytes](uint64_t value, int size) {
      for (int i = 0; i < size; ++i) bytes.push_back(static_cast<char>(value >> (8 * i)));
    };
    auto set_bits = [](const MemberSet& set) { return set.byte_at(0); };
    for (uint16_t id = 0; id < params_.robots; ++id) {
      const Robot& robot = global.robots[id];
      const SyncState& s = robot.state;
      put(robot.alive | (robot.present << 1) | (robot.paused << 2) | (robot.late << 3) | (robot.carried << 4), 1);
      if (robot.paused) put(robot.paused_rounds, 1);
      if (robot.late) put(robot.late_rounds, 1);
      put(robot.buffered, 1);
      for (size_t i = 0; i < robot.buffered; ++i) {
        const wire::Beacon& b = robot.buffer[i];
        put(b.robot_id | (static_cast<uint8_t>(b.phase) << 2) | (static_cast<uint8_t>(b.mode) << 4), 1);
        put(static_cast<uint16_t>(b.epoch - base), 2);
        put(b.vote_counter | (set_bits(b.waiting) << 4), 1);
        put(static_cast<uint16_t>(b.snapshot.x_mm), 2);
      }
      if (!Listens(robot) && !robot.paused) continue;
      put(robot.progress_rounds, 1);
      put(static_cast<uint8_t>(s.status), 1);
      const int relative_epoch = EpochDifference(s.epoch, static_cast<uint16_t>(base));
      put(s.status == Status::kJoining && relative_epoch < 0 ? 0xFFFFu : static_cast<uint16_t>(relative_epoch), 2);
      put(static_cast<uint8_t>(s.phase), 1);
      put(s.vote, 1);
      put(static_cast<uint8_t>(s.epoch_mode) | (s.veto << 1) | (s.join_target_known << 2), 1);
      put(set_bits(s.members), 1);
      put(set_bits(s.waiting), 1);
      put(set_bits(s.view), 1);
      put(set_bits(s.votes_matched), 1);
      put(set_bits(s.held), 1);
      // "Connectivity": `pruned` is a cache of these (recomputed before use).
      put(set_bits(s.flaky_current) | (set_bits(s.flaky_previous) << 4), 1);
      put(set_bits(s.flaky), 1);
      for (const uint16_t removed : s.flaky_current) {
        // How long a removed robot has been silent matters up to 2F.
        if (!s.members.test(removed)) put(std::min<int>(s.silent_rounds[removed], 2 * params_.silence_rounds), 1);
      }
      for (size_t i = 0; i < s.report_count; ++i) {
        put(s.reports[i].reporter | (set_bits(s.reports[i].heard) << 4), 1);
      }
      put(0xFF, 1);
      if (s.status == Status::kJoining) {  // stale in members
        put(set_bits(s.join_group), 1);
        put(s.join_rounds_left, 1);
        put(static_cast<uint16_t>(s.join_epoch - base), 2);
        put(s.rounds_alone, 2);
      }
      for (const uint16_t member : s.members) put(s.silent_rounds[member], 1);
      for (const uint16_t holder : s.held) put(static_cast<uint16_t>(s.snapshots[holder].x_mm), 2);
    }
    for (uint16_t from = 0; from < params_.robots; ++from) {
      for (uint16_t to = 0; to < params_.robots; ++to) put(global.consecutive_losses[from][to], 1);
    }
    // Records, in epoch order so their slots do not matter.
    std::vector<const EpochRecord*> records;
    for (const EpochRecord& record : global.records) {
      if (record.used) records.push_back(&record);
    }
    std::sort(records.begin(), records.end(),
              [](const EpochRecord* a, const EpochRecord* b) { return a->epoch < b->epoch; });
    for (const EpochRecord* record : records) {
      put(static_cast<uint16_t>(record->epoch - base), 2);
      put(record->cooperative_seen | (record->members << 1), 1);
      if (params_.adversary == Adversary::kAnyLoss) put(record->age, 1);
      for (const int16_t x : record->x_mm) put(static_cast<uint16_t>(x), 2);
    }
    put(global.rounds_without_start, 1);
    put(global.disagreement_rounds, 1);
    put(global.fault_used | (global.joiner_started << 1) | (global.era << 2) | (global.deaf << 3) | (global.mute << 4), 1);
    put(global.since_cooperative, 1);
    put(global.links_chosen, 1);
    put(global.dead, 2);
    put(global.flipped, 2);
    put(static_cast<uint8_t>(global.crashed), 1);
    put(global.since_fault, 1);
    if (global.joiner_started) put(static_cast<uint16_t>(global.joiner_first_epoch - base), 2);
    // FNV-1a 64 over the canonical bytes.
    uint64_t hash = 1469598103934665603ull;
    for (const char c : bytes) {
      hash ^= static_cast<uint8_t>(c);
      hash *= 1099511628211ull;
    }
    return hash;
  }

  // Replays `path` from the initial state, printing each round.
  std::string Trace(const std::vector<Choice>& path) {
    std::string trace;
    Global global = initial_;
    for (size_t round = 0; round < path.size(); ++round) {
      trace += "round " + std::to_string(round);
      if (path[round].crash >= 0) trace += " (robot " + std::to_string(path[round].crash) + " crashes)";
      if (path[round].switch_on >= 0) trace += " (robot " + std::to_string(path[round].switch_on) + " switched on)";
      if (path[round].pause >= 0) trace += " (robot " + std::to_string(path[round].pause) + " paused)";
      if (path[round].resume >= 0) {
        trace += " (robot " + std::to_string(path[round].resume) + " resumed" +
                 (path[round].wrapped ? " after a pause spanning the wrap)" : ")");
      }
      if (path[round].silence) trace += " (robot 0 turns deaf or mute)";
      if (path[round].initial_dead >= 0) trace += " (dead links " + std::to_string(path[round].initial_dead) + ", bit from*n+to)";
      if (path[round].flip >= 0) trace += " (link " + std::to_string(path[round].flip) + " changes)";
      if (path[round].late >= 0) trace += " (robot " + std::to_string(path[round].late) + "'s task runs late)";
      if (path[round].catch_up >= 0) {
        trace += " (robot " + std::to_string(path[round].catch_up) + "'s task runs" +
                 (path[round].defer ? ", what arrived meanwhile waits for its next step)" : ")");
      }
      trace += ":\n";
      Apply(global, path[round], &trace);
      for (uint16_t id = 0; id < params_.robots; ++id) {
        const SyncState& s = global.robots[id].state;
        trace += "  robot " + std::to_string(id) + ": " + ToString(s.status) + " epoch " +
                 std::to_string(s.epoch) + " " + wire::ToString(s.phase) + " vote " + std::to_string(s.vote) +
                 " members " + std::to_string(s.members.byte_at(0)) + " view " +
                 std::to_string(s.view.byte_at(0)) + (s.veto ? " veto" : "") + "\n";
      }
    }
    return trace;
  }

  Params params_;
  std::array<SyncConfig, kMaxRobots> configs_{};
  Global initial_;
};

void RunAndReport(const char* name, const Params& params) {
  Explorer explorer(params);
  const Explorer::Report report = explorer.Run();
  std::printf("[ explore ] %-40s n=%u K=%u F=%u D=%u: %zu states, %zu transitions, depth %d%s, "
              "max skew %d rounds, max mode disagreement %d rounds, longest wait for COOPERATIVE %d rounds\n",
              name, params.robots, params.vote_rounds, params.silence_rounds, params.maneuver_rounds,
              report.states, report.transitions, report.depth,
              report.exhausted ? " (exhausted)" : " (depth bound)", report.max_skew, report.max_disagreement,
              report.max_back_to_cooperative);
  EXPECT_TRUE(report.violation.empty()) << report.violation;
  if (params.max_depth == 0) {
    EXPECT_TRUE(report.exhausted);
  }
}

TEST(SyncExploreTest, BoundedLossTwoRobots) {
  RunAndReport("a) loss < K per link", {Adversary::kBoundedLoss, 2, 2, 3, 2, 0});
}

TEST(SyncExploreTest, BoundedLossThreeRobots) {
  RunAndReport("a) loss < K per link", {Adversary::kBoundedLoss, 3, 2, 3, 2, 0});
}

// 4.6 million states and about 90 s: run with --gtest_also_run_disabled_tests.
TEST(SyncExploreTest, DISABLED_BoundedLossThreeRobotsK3) {
  RunAndReport("a) loss < K per link", {Adversary::kBoundedLoss, 3, 3, 4, 3, 0});
}

TEST(SyncExploreTest, AnyLossTwoRobots) {
  RunAndReport("b) any loss", {Adversary::kAnyLoss, 2, 2, 3, 2, 40});
}

// Depth 4 in the CI (4 s); depth 5 takes about 45 s: the DISABLED_ variant.
TEST(SyncExploreTest, AnyLossThreeRobots) {
  RunAndReport("b) any loss", {Adversary::kAnyLoss, 3, 2, 3, 2, 4});
}

TEST(SyncExploreTest, DISABLED_AnyLossThreeRobotsDeep) {
  RunAndReport("b) any loss", {Adversary::kAnyLoss, 3, 2, 3, 2, 5});
}

TEST(SyncExploreTest, CrashThreeRobots) {
  RunAndReport("c) loss < K, one crash", {Adversary::kCrash, 3, 2, 3, 2, 0});
}

TEST(SyncExploreTest, JoinThreeRobots) {
  RunAndReport("c) loss < K, one join", {Adversary::kJoin, 3, 2, 3, 2, 30});
}

// The pause, deaf and mute adversaries let one robot's epoch drift from the
// others' without bound, so they run to a depth. The CI runs the depths
// below; the DISABLED_ variants are the full runs (--gtest_also_run_disabled_tests).
TEST(SyncExploreTest, PauseTwoRobots) {
  RunAndReport("d) loss < K, one pause", {Adversary::kPause, 2, 2, 3, 2, 30});
}

TEST(SyncExploreTest, PauseThreeRobots) {
  RunAndReport("d) loss < K, one pause", {Adversary::kPause, 3, 2, 3, 2, 8});
}

TEST(SyncExploreTest, DISABLED_PauseThreeRobotsDeep) {
  RunAndReport("d) loss < K, one pause", {Adversary::kPause, 3, 2, 3, 2, 16});
}

TEST(SyncExploreTest, NearTheWrapThreeRobots) {
  RunAndReport("e) loss < K from epoch 65533", {Adversary::kBoundedLoss, 3, 2, 3, 2, 40, 65533});
}

TEST(SyncExploreTest, NearTheWrapAnyLossTwoRobots) {
  RunAndReport("e) any loss from epoch 65533", {Adversary::kAnyLoss, 2, 2, 3, 2, 30, 65533});
}

TEST(SyncExploreTest, DeafRobotThreeRobots) {
  RunAndReport("f) loss < K, robot 0 turns deaf", {Adversary::kDeaf, 3, 2, 3, 2, 30});
}

// Depth 20 in the CI: the others' longest wait (11 rounds) is inside it.
TEST(SyncExploreTest, MuteRobotThreeRobots) {
  RunAndReport("f) loss < K, robot 0 turns mute", {Adversary::kMute, 3, 2, 3, 2, 20});
}

// The CI runs every starting pattern with one later change (three robots)
// or none (four); DISABLED_DeadLinksFourRobotsOneChange, 20.6 million states
// and about 6 minutes, lets one link of four robots change too.
TEST(SyncExploreTest, DeadLinksThreeRobots) {
  RunAndReport("g) dead directed links, 1 change", {Adversary::kDeadLinks, 3, 2, 3, 2, 45, 0, 1});
}

TEST(SyncExploreTest, DeadLinksFourRobots) {
  RunAndReport("g) dead directed links", {Adversary::kDeadLinks, 4, 2, 3, 2, 45, 0, 0});
}

TEST(SyncExploreTest, DISABLED_DeadLinksFourRobotsOneChange) {
  RunAndReport("g) dead directed links, 1 change", {Adversary::kDeadLinks, 4, 2, 3, 2, 45, 0, 1});
}

// h) A round task 1 to 3 rounds late (F = 3: the longest lateness is a
// gap, and the robot rejoins), any robot, again and again. Depth 4 with
// three robots in the CI; depth 5, 2.2 million states and about 2 minutes,
// is the DISABLED_ variant.
TEST(SyncExploreTest, LateRoundTaskThreeRobots) {
  Params params{Adversary::kLate, 3, 2, 3, 2, 4};
  params.max_late_rounds = 3;
  RunAndReport("h) loss < K, a task up to 3 rounds late", params);
}

TEST(SyncExploreTest, DISABLED_LateRoundTaskThreeRobotsDeep) {
  Params params{Adversary::kLate, 3, 2, 3, 2, 5};
  params.max_late_rounds = 3;
  RunAndReport("h) loss < K, a task up to 3 rounds late", params);
}

TEST(SyncExploreTest, LateRoundTaskFourRobots) {
  Params params{Adversary::kLateNoLoss, 4, 2, 3, 2, 8};
  params.max_late_rounds = 3;
  RunAndReport("h) no loss, a task up to 3 rounds late", params);
}

TEST(SyncExploreTest, DISABLED_DeafAndMuteDeep) {
  RunAndReport("f) loss < K, robot 0 turns deaf", {Adversary::kDeaf, 3, 2, 3, 2, 60});
  RunAndReport("f) loss < K, robot 0 turns mute", {Adversary::kMute, 3, 2, 3, 2, 60});
}

}  // namespace
}  // namespace syrof::sync
