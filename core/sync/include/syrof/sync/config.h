// The synchronizer's parameters (docs/protocol.md, "Parameters").
#pragma once

#include <cstdint>

#include "syrof/wire/member_set.h"

namespace syrof::sync {

/// Why a SyncConfig was refused.
enum class [[nodiscard]] ConfigError : uint8_t {
  kOk = 0,
  kSwarmSizeOutOfRange,     // swarm_size 0 or above wire::kMaxSwarmSize
  kSelfOutOfRange,          // self_id >= swarm_size
  kVoteRoundsOutOfRange,    // vote_rounds (K) 0 or above kMaxVoteRounds
  kSilenceNotAboveVote,     // silence_rounds (F) not above vote_rounds (K)
  kSilenceTooLong,          // silence_rounds (F) above kMaxSilenceRounds
  kQuorumNotMajority,       // quorum not above swarm_size / 2, or above swarm_size
  kInitialMemberOutOfRange, // initial_members names an id >= swarm_size
};

/// The enumerator's name without the k; "?" for an unknown value.
const char* ToString(ConfigError error);

/// Largest K: the vote counter travels in one byte.
inline constexpr uint8_t kMaxVoteRounds = 200;

/// Largest F. Bounds how long a robot may legitimately stay in one epoch,
/// which the epoch-wrap argument needs (docs/protocol.md, "Epoch numbers").
inline constexpr uint16_t kMaxSilenceRounds = 4096;

/// A member that has spent this many radio rounds in one epoch (counting
/// rounds it missed while paused) restarts as a joiner: knowledge a robot
/// holds is never older than this, so it cannot outlive its epoch number
/// (docs/protocol.md, "Epoch numbers"). Far above any legitimate epoch:
/// PROGRESS (at most runtime::kMaxManeuverRounds) plus WAIT and VOTE.
inline constexpr uint16_t kMaxStayRounds = 16384;

/// A joiner may move its epoch forward by at most this many epochs in
/// total, earning one back per radio round (a token bucket), so no robot
/// can go round the 16-bit circle of epoch numbers in fewer than 21,846
/// rounds (docs/protocol.md, "Epoch numbers").
inline constexpr uint16_t kMaxJoinCredit = 32767;

/// A joiner that has not been a member for this many rounds may take any
/// epoch: its last one is far enough in the past (docs/protocol.md).
inline constexpr uint16_t kJoinFreeRounds = 32768;

/// Every robot of a swarm must use the same values (except self_id).
struct SyncConfig {
  uint16_t swarm_size = 1;     // N: robot ids are 0 .. N-1
  uint16_t self_id = 0;        // this robot's id
  uint8_t vote_rounds = 3;     // K: radio rounds in VOTE before an epoch starts
  uint16_t silence_rounds = 6; // F: a member unheard for F rounds in a row is removed (F > K)
  uint16_t quorum = 1;         // Q: fewest members of a COOPERATIVE epoch; must exceed N / 2
  wire::MemberSet initial_members;  // robots present at start; the rest join later

  /// A config for `swarm_size` robots with every robot an initial member,
  /// K = 3, F = 2K and the majority quorum N / 2 + 1.
  static SyncConfig ForSwarm(uint16_t swarm_size, uint16_t self_id);
};

/// kOk, or the first rule `config` breaks, in the order of ConfigError.
ConfigError Validate(const SyncConfig& config);

}  // namespace syrof::sync
