// Activation: which members of an epoch's map look, compute and move in that
// epoch (docs/activation.md).
//
// FSYNC (the default): every member is active in every epoch. SSYNC: a
// schedule chooses a non-empty subset of the epoch's members; an inactive
// member gets no newRound (nor endOfRound) and holds its place and global
// state for the epoch, but still steps its synchronizer, beacons and stays
// a member. The app is never told; it only finds that some epochs pass it by.
//
// The decision is a pure function of the configuration (seed, schedule,
// script), the epoch number and the epoch's member set, so every robot that
// holds the same map decides the same for every member: under COOPERATIVE
// maps (common knowledge, docs/protocol.md) the members agree on the active
// set without another message. The lab, a DDS robot process and the firmware
// call the same function. No allocation, no clock, no state; O(members).
//
// Schedules (SSYNC):
//   random       each member is active with probability 1/2, drawn from the
//                seed, the epoch and its id; and, whatever the draw, in every
//                epoch e with (e + offset(id)) mod fair_within == 0, where
//                offset(id) comes from the seed: so every robot is active at
//                least once in any fair_within consecutive epoch numbers.
//   round_robin  the member at position e mod m of the ascending member list
//                (m members): one robot at a time.
//   scripted     the epochs the script lists: the listed robots that are
//                members; an epoch it does not list: every member.
// When a schedule's choice holds no member (a script naming only robots
// that are absent), the fallback is the one member at position
// (a draw from the seed and the epoch) mod m of the ascending member list.
//
// ASYNC: a robot's cycle spans epochs. At the first epoch start after its
// previous cycle ended it looks (newRound on that epoch's map) and computes;
// its move starts `start_delay` epochs later and lasts `move_epochs`
// epochs (each 1 .. max_delay_epochs + 1 apart), covering what the command
// would cover in one maneuver (its speed divided by move_epochs), so the
// others see it mid-move and it may move on a map that is no longer the
// newest; endOfRound comes when the move's last maneuver ends. With
// min_move_mm > 0 (non-rigid) the scheduler may cut a move: it stops once it
// has covered min_move_mm. The timing of one cycle is a pure function of
// the seed (or the script), the look's epoch and the robot (CycleFor);
// AsyncTracker follows one robot's cycles from its epoch starts, so the
// robot and whoever counts for it (the lab's metrics) agree.
//
// Epoch numbers are 16 bits and wrap (docs/protocol.md): the random
// schedule's fairness holds across the wrap only when fair_within divides
// 65,536; a run shorter than 65,536 epochs never wraps.
#pragma once

#include <cstdint>
#include <span>

#include "syrof/wire/member_set.h"

namespace syrof::sync {

enum class ActivationModel : uint8_t {
  kFsync = 0,  ///< every member active in every epoch
  kSsync = 1,  ///< a schedule picks a non-empty subset of the members per epoch
  kAsync = 2,  ///< a robot's look, move start and move end fall in epochs a schedule picks
};

enum class ActivationSchedule : uint8_t {
  kRandom = 0,      ///< seeded (SSYNC: with the fairness bound fair_within)
  kRoundRobin = 1,  ///< one member per epoch, in id order (SSYNC only)
  kScripted = 2,    ///< SSYNC: the listed robots in the listed epochs; ASYNC: the listed cycles
};

/// The names scenarios use ("fsync", "random", ...).
const char* ToString(ActivationModel model);
const char* ToString(ActivationSchedule schedule);

/// One (epoch, robot) pair of a scripted schedule: `robot` is active in
/// `epoch`.
struct ScriptedActivation {
  uint16_t epoch = 0;
  uint16_t robot = 0;
};

/// ASYNC: the timing of one cycle of `robot` that looks in `epoch`.
struct ScriptedCycle {
  uint16_t epoch = 0;
  uint16_t robot = 0;
  uint8_t start_delay = 0;  ///< epochs between the look and the move's first epoch
  uint8_t move_epochs = 1;  ///< epochs the move lasts, >= 1
  bool cut = false;         ///< non-rigid: stopped once it covered min_move_mm
};

/// ASYNC: when a cycle's move starts and how long it lasts.
struct AsyncCycle {
  uint8_t start_delay = 0;
  uint8_t move_epochs = 1;
  bool cut = false;
};

/// ASYNC: the longest delay bound, in epochs.
inline constexpr uint8_t kMaxAsyncDelayEpochs = 8;

/// Longest fairness bound, in epochs.
inline constexpr uint32_t kMaxFairWithinEpochs = 65535;

struct ActivationConfig {
  ActivationModel model = ActivationModel::kFsync;
  ActivationSchedule schedule = ActivationSchedule::kRandom;
  uint64_t seed = 0;
  /// Random schedule: every robot active at least once in any this many
  /// consecutive epochs; 1 .. kMaxFairWithinEpochs (1 is every member every
  /// epoch).
  uint16_t fair_within = 2;
  /// Scripted schedule: sorted by epoch, then robot, no duplicates. Not
  /// owned; must outlive every use of the config.
  std::span<const ScriptedActivation> script;
  /// ASYNC: the start delay and the move's extra epochs are each at most
  /// this (1 .. kMaxAsyncDelayEpochs; 0 makes every cycle one epoch, FSYNC).
  uint8_t max_delay_epochs = 1;
  /// ASYNC non-rigid moves: a cut move stops once it covered this many
  /// millimetres; 0: rigid, no move is cut.
  uint32_t min_move_mm = 0;
  /// ASYNC scripted: sorted by epoch, then robot, no duplicates; a look not
  /// listed starts its move at once and lasts one epoch. Not owned.
  std::span<const ScriptedCycle> cycles;
};

/// Whether `config` is usable: fair_within >= 1, the scripts sorted without
/// duplicates, ASYNC delays within max_delay_epochs.
bool IsValid(const ActivationConfig& config);

/// Whether `robot` is active in `epoch`, whose map holds `members`. A robot
/// outside `members` is never active; when `members` is empty nobody is.
/// Among the members at least one is active. Needs IsValid(config). Under
/// ASYNC whether a robot looks depends on its earlier cycles (AsyncTracker):
/// this answers as FSYNC does.
bool IsActive(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members, uint16_t robot);

/// How many of `members` are active in `epoch` (>= 1 unless `members` is empty).
uint16_t ActiveCount(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members);

/// ASYNC: the timing of the cycle `robot` starts by looking in `epoch`.
/// Needs IsValid(config); under another model, a one-epoch cycle.
AsyncCycle CycleFor(const ActivationConfig& config, uint16_t epoch, uint16_t robot);

/// ASYNC: one robot's cycles, followed from its epoch starts. The robot
/// steps one to decide; the lab's metrics step their own with the same
/// epoch starts and get the same answers. No allocation, O(1) a step.
class AsyncTracker {
 public:
  /// What the robot does in one epoch it starts.
  struct Step {
    bool looks = false;            ///< a cycle starts: newRound on this epoch's map
    bool moves = false;            ///< this epoch's maneuver is part of the cycle's move
    bool first_move_epoch = false;
    bool last_move_epoch = false;  ///< the cycle ends with this epoch's maneuver (endOfRound)
    uint16_t look_epoch = 0;       ///< the epoch whose map the move comes from
    AsyncCycle cycle{};
  };
  /// The robot started `epoch`: look when no cycle is under way.
  Step OnEpochStart(const ActivationConfig& config, uint16_t epoch, uint16_t robot);
  /// The whole state in one word (for a search's state digest).
  uint64_t Packed() const;

 private:
  bool busy_ = false;
  uint16_t look_epoch_ = 0;
  uint16_t since_look_ = 0;  // epoch starts since the look
  AsyncCycle cycle_{};
};

}  // namespace syrof::sync
