// The synchronizer: membership, failure detector, PROGRESS / WAIT / VOTE
// rounds and the operation mode, as one pure step function per radio round.
//
// docs/protocol.md is the specification; this file follows it section by
// section (the section names appear in the comments of synchronizer.cpp).
//
// Usage, once per radio round on every live robot:
//   1. broadcast the beacon of the previous StepOutput (unless `send` is false);
//   2. collect the beacons received during the round;
//   3. call Step() with them and whether the maneuver has finished.
// Step() has no clock, I/O or allocation; its cost is linear in the swarm
// size plus the number of beacons received.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "syrof/sync/config.h"
#include "syrof/sync/ldmap.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"

namespace syrof::sync {

using wire::MemberSet;
using wire::Mode;
using wire::Phase;

/// Whether the robot belongs to a group (a member) or is looking for one.
enum class Status : uint8_t {
  kMember = 0,   // runs epochs with the group it believes in
  kJoining = 1,  // silent; waits for a group's next epoch boundary
};

/// "MEMBER" or "JOINING"; "?" for a value outside the enum.
const char* ToString(Status status);

/// Why a received beacon was not used. Counted in SyncStats; the beacon is
/// dropped and everything else in the round is processed.
enum class BeaconIssue : uint8_t {
  kNone = 0,
  kFromSelf,          // carries this robot's own id
  kIdOutOfRange,      // robot id >= swarm size
  kDuplicate,         // second beacon from the same robot in one round
  kBadVoteCounter,    // VOTE with a counter outside 1..K, or another phase with one
  kMemberOutOfRange,  // waiting set names an id >= swarm size
};

/// The enumerator's name without the k; "?" for an unknown value.
const char* ToString(BeaconIssue issue);

/// Counters for diagnostics; never read by the protocol.
struct SyncStats {
  uint32_t beacons_used = 0;
  uint32_t beacons_rejected = 0;
  BeaconIssue last_issue = BeaconIssue::kNone;
  uint32_t epochs_started = 0;
  uint32_t epochs_cooperative = 0;
  uint32_t catch_ups = 0;  // epochs started late because a member was already in the next one
  uint32_t joins_started = 0;
  uint32_t restarts_after_gap = 0;   // rejoined: missed F or more rounds (a pause)
  uint32_t restarts_long_stay = 0;   // rejoined: kMaxStayRounds in one epoch
  uint32_t prunings = 0;             // times the connectivity rule changed whom it leaves out
  uint32_t late_votes = 0;           // VOTE entered when a member was already voting (fewer than K own votes)

  bool operator==(const SyncStats&) const = default;
};

/// A heard set another robot sent in a PROGRESS beacon ("Connectivity").
struct Report {
  uint16_t reporter = 0;
  MemberSet heard;  // the reporter itself and the members it hears well

  bool operator==(const Report&) const = default;
};

/// Reports a robot keeps: only those that differ from its own member set
/// (in a swarm where everyone hears everyone there are none). Beyond this,
/// the reports of the highest ids are not kept.
inline constexpr size_t kMaxReports = wire::kMaxSwarmSize < 16 ? wire::kMaxSwarmSize : 16;

/// One robot's synchronizer state: plain data, copyable, so tests can store
/// and compare global states. Fields follow docs/protocol.md, "State".
struct SyncState {
  Status status = Status::kMember;
  uint16_t epoch = 0;          // current epoch, compared with serial arithmetic
  Phase phase = Phase::kWait;  // meaningful for members
  uint8_t vote = 0;            // VOTE: counter carried by the next beacon, 1..K
  Mode epoch_mode = Mode::kAutonomous;  // mode the current epoch started in
  bool veto = false;           // VOTE: this robot cannot start the next epoch COOPERATIVE

  MemberSet members;        // M: the robots this one believes in, itself included
  MemberSet waiting;        // W: members known to have finished this epoch's maneuver
  MemberSet view;           // L: M frozen when entering VOTE; sent in VOTE beacons
  MemberSet votes_matched;  // members of L heard voting with exactly L this epoch
  MemberSet held;           // whose snapshot for this epoch this robot holds
  MemberSet join_group;     // joining: robots heard voting for join_epoch - 1

  // Joining: the round countdown to the group's boundary, if one was heard.
  bool join_target_known = false;
  uint8_t join_rounds_left = 0;   // rounds until the group starts join_epoch
  uint16_t join_epoch = 0;        // epoch the joiner will start with the group
  uint16_t rounds_alone = 0;      // joining: consecutive rounds with no beacon heard

  // Epoch numbers (docs/protocol.md, "Epoch numbers").
  uint16_t stay_rounds = 0;       // member: rounds in the current epoch, missed ones included (saturates)
  uint16_t rounds_joining = 0;    // joining: rounds since it was last a member (saturates)
  uint16_t join_credit = kMaxJoinCredit;  // epochs a join may still skip forward

  // "Connectivity" (docs/protocol.md): whom this robot hears well, what the
  // others report hearing, and the members left out so that every pair of
  // the rest hears each other both ways.
  MemberSet flaky_current;   // members the failure detector removed in this epoch
  MemberSet flaky_previous;  // ... and in the previous one
  MemberSet flaky;           // removed in two epochs in a row, and in every epoch since
  MemberSet reported;        // whose report is in `reports` (sorted pool)
  std::array<Report, kMaxReports> reports{};  // reports that differ from `members`
  uint8_t report_count = 0;
  MemberSet pruned;          // left out by the rule; may include this robot
  bool pruned_stale = true;  // the inputs of `pruned` changed since it was computed
  MemberSet pruned_members;  // `members` when `pruned` was computed
  MemberSet pruned_heard;    // this robot's heard set then

  std::array<uint16_t, wire::kMaxSwarmSize> silent_rounds{};  // per member, consecutive
  std::array<wire::Snapshot, wire::kMaxSwarmSize> snapshots{};      // valid where `held`
  std::array<Phase, wire::kMaxSwarmSize> last_phase{};         // phase each member was last heard in
  wire::Snapshot live;  // the robot's own current state, sent in PROGRESS beacons

  SyncStats stats;

  bool operator==(const SyncState&) const = default;
};

/// What the robot did this round, besides the radio.
struct StepInput {
  bool maneuver_finished = false;  // the maneuver of the current epoch is over
  wire::Snapshot own_snapshot;           // the robot's state now; frozen when PROGRESS ends
  // Radio rounds since the previous Step() of this robot: 1 when it missed
  // none; more after a pause (its round task did not run). 0 counts as 1. A
  // member that missed F or more rounds restarts as a joiner.
  uint32_t rounds_elapsed = 1;
};

/// What Step() produced. `ldmap` is filled only when `epoch_started`.
struct StepOutput {
  bool send = false;   // false while joining: a joiner is silent
  wire::Beacon beacon; // to broadcast in the next round

  bool epoch_started = false;  // call newRound with `ldmap`
  MemberSet removed;           // members the failure detector removed this round
  MemberSet joined;            // robots added to the members this round
  bool became_joiner = false;  // this robot lost its group and is rejoining
};

/// The state a robot starts in. An initial member (config.initial_members)
/// begins in WAIT of epoch 0 with `initial_snapshot` frozen and believes in
/// every initial member; the first epoch start hands it the swarm's initial
/// LDMap. Any other robot begins joining. The config must be valid (checked).
SyncState InitialState(const SyncConfig& config, const wire::Snapshot& initial_snapshot);

/// The beacon a robot in `state` broadcasts (docs/protocol.md, "Beacon").
wire::Beacon MakeBeacon(const SyncConfig& config, const SyncState& state);

/// Processes one radio round: the beacons received during it (any order,
/// from any robot; malformed ones are counted and dropped) and the robot's own
/// input. Updates `state` and fills `out` (and `ldmap` when an epoch starts).
/// The config must be valid (checked).
void Step(const SyncConfig& config, SyncState& state, std::span<const wire::Beacon> received,
          const StepInput& input, StepOutput& out, LDMap& ldmap);

/// The same, with the round's beacons given by address: a runtime that
/// delivers one decoded beacon to many robots (the lab) passes pointers
/// instead of copying each beacon into every receiver's array. Identical
/// results for the same beacons in the same order.
void Step(const SyncConfig& config, SyncState& state, std::span<const wire::Beacon* const> received,
          const StepInput& input, StepOutput& out, LDMap& ldmap);

/// Serial-number difference a - b of two 16-bit epochs, in -32768 .. 32767:
/// positive when `a` is ahead of `b`, across the wrap from 65535 to 0.
int16_t EpochDifference(uint16_t a, uint16_t b);

}  // namespace syrof::sync
