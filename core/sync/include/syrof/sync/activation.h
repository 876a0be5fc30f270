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
};

enum class ActivationSchedule : uint8_t {
  kRandom = 0,      ///< seeded, with the fairness bound fair_within
  kRoundRobin = 1,  ///< one member per epoch, in id order
  kScripted = 2,    ///< the listed robots in the listed epochs
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
};

/// Whether `config` is usable: fair_within >= 1, the script sorted without
/// duplicates.
bool IsValid(const ActivationConfig& config);

/// Whether `robot` is active in `epoch`, whose map holds `members`. A robot
/// outside `members` is never active; when `members` is empty nobody is.
/// Among the members at least one is active. Needs IsValid(config).
bool IsActive(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members, uint16_t robot);

/// How many of `members` are active in `epoch` (>= 1 unless `members` is empty).
uint16_t ActiveCount(const ActivationConfig& config, uint16_t epoch, const wire::MemberSet& members);

}  // namespace syrof::sync
