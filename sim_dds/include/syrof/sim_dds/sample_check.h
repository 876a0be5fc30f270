// The checks every received Beacon_ sample passes before its bytes reach a
// robot (docs/dds.md, "Sample checks"). Anyone on the domain can write to
// rt/syrof/beacon, so a sample is untrusted input: its wire bytes, its
// sender and its round are checked against each other and against the
// receiver, and a rejected sample is counted by its reason.
//
// Pure code on explicit state, no DDS header, so tests and the fuzz target
// (tests/fuzz/beacon_sample_fuzz.cpp) run it without a participant.
//
// The checks, in this order (the first that fails is the reason):
//   kOtherRun         the sample's run is not the receiver's (CheckRun; a
//                     radio checks it on arrival, before anything else):
//                     two runs that land on one domain hear each other
//   kOversized        more wire bytes than this swarm's beacon
//                     (wire::EncodedSize(swarm_size))
//   kSenderOutOfSwarm the sample's sender >= swarm size
//   kFromSelf         the sample's sender is the receiver (its own beacon
//                     comes back through DDS, or someone forges it)
//   kMalformed        wire::Decode fails (truncated, wrong version, a field
//                     out of range, ...)
//   kSenderMismatch   the sample's sender is not the beacon's robot_id
//   kRoundOutOfWindow the sample's round is more than kRoundWindow rounds
//                     before or after the receiver's current round (replays
//                     of old rounds, or a writer far ahead)
//   kDuplicate        the sender's round is not after the last round
//                     accepted from that sender (a replay within the window,
//                     or a reordered sample)
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "syrof/wire/beacon.h"
#include "syrof/wire/beacon_layout.h"

namespace syrof::sim_dds {

/// The largest swarm over DDS: every beacon of it fits the IDL's
/// BEACON_MAX_BYTES (beacon_radio.cpp checks at compile time).
inline constexpr uint16_t kMaxDdsSwarm = wire::kMaxSwarmSize;

/// Rounds a sample's round may lie before or after the receiver's round.
/// Robots follow one grid from the world's start time, so a fresh beacon is
/// of the receiver's round or, at a boundary, one off; two rounds leave room
/// for a late process without accepting replays of older rounds.
inline constexpr int64_t kRoundWindow = 2;

enum class SampleVerdict : uint8_t {
  kAccepted = 0,
  kOversized,
  kSenderOutOfSwarm,
  kFromSelf,
  kMalformed,
  kSenderMismatch,
  kRoundOutOfWindow,
  kDuplicate,
  kOtherRun,  // checked first (CheckRun); last here so the others keep their values
};
inline constexpr int kSampleVerdicts = 9;

/// "accepted", "oversized", "sender_out_of_swarm", ... (the names metrics
/// and logs use); "?" for an unknown value.
const char* ToString(SampleVerdict verdict);

/// What the receiver knows when it checks a sample.
struct ReceiverView {
  uint16_t self = 0;
  uint16_t swarm_size = 0;     ///< 1 .. kMaxDdsSwarm
  int64_t current_round = -1;  ///< the receiver's round; < 0: not started, no window check
  /// The last round accepted from the sample's sender; < 0: none yet.
  int64_t last_round_from_sender = -1;
};

/// One sender's round count against a receiver's, from its latest sample.
struct SenderRoundOffset {
  int64_t heard_in = -1;  ///< the receiver's expected round when it arrived; < 0: none
  int64_t offset = 0;     ///< the sample's round minus that round
};

/// By how many rounds the senders heard since `since_round` number their
/// rounds ahead of the receiver: m > 0 when more than half of them are m
/// ahead, m < 0 when at least two were heard and all of them are m behind,
/// 0 otherwise. A robot that numbers its own rounds (round alignment) adds it
/// to its count, so a late joiner, or a robot whose count started from a
/// grid the swarm has drifted off, takes the swarm's count. The asymmetry
/// keeps two halves that disagree from swapping counts: the half behind
/// moves, the half ahead does not.
int64_t AgreedRoundOffset(std::span<const SenderRoundOffset> offsets, int64_t since_round);

/// Checks one sample (sender, round and wire bytes as they arrived) for the
/// receiver; on kAccepted writes the decoded beacon to `beacon` (otherwise
/// leaves it unspecified). Never reads past `wire`; any input is allowed.
SampleVerdict CheckSample(uint16_t sample_sender, uint32_t sample_round, std::span<const uint8_t> wire,
                          const ReceiverView& receiver, wire::Beacon& beacon);

/// kAccepted when the sample's run id is the receiver's, else kOtherRun.
/// Every sample of a `syrof swarm` run carries the run's id (the world's,
/// which changes every run); radios outside a run (the bridge's relayed
/// beacons, tests) use 0. Without it, a robot of one run takes the beacons
/// of another run on the same domain (1 in 231 concurrent pairs) as its
/// own swarm's: same sender ids, other epochs, views and snapshots, and two
/// COOPERATIVE robots start an epoch with different maps (issue 46).
SampleVerdict CheckRun(uint64_t sample_run, uint64_t receiver_run);

/// Counts of samples by verdict; readable from any thread while one thread
/// checks.
class SampleCounters {
 public:
  void Add(SampleVerdict verdict) { counts_[static_cast<int>(verdict)].fetch_add(1, std::memory_order_relaxed); }
  uint64_t count(SampleVerdict verdict) const { return counts_[static_cast<int>(verdict)].load(std::memory_order_relaxed); }
  uint64_t accepted() const { return count(SampleVerdict::kAccepted); }
  /// Every reason but kAccepted.
  uint64_t rejected() const;

 private:
  std::array<std::atomic<uint64_t>, kSampleVerdicts> counts_{};
};

/// A receiver's state for CheckSample: the last round accepted from each
/// sender, and the counters. One thread calls Check (the radio's reader);
/// any thread reads counters().
class SampleFilter {
 public:
  /// `self` < `swarm_size` <= kMaxDdsSwarm (SYROF_CHECK); `run_id`: the
  /// receiver's run (CheckRun).
  SampleFilter(uint16_t self, uint16_t swarm_size, uint64_t run_id = 0);

  /// CheckRun against this receiver's run; a sample of another run is
  /// counted (kOtherRun) and must go no further. An accepted one is not
  /// counted here: Check counts it.
  SampleVerdict CheckRun(uint64_t sample_run);

  /// CheckSample with the sender's last accepted round; remembers the round
  /// of an accepted sample and counts the verdict.
  SampleVerdict Check(uint16_t sample_sender, uint32_t sample_round, std::span<const uint8_t> wire,
                      int64_t current_round, wire::Beacon& beacon);

  const SampleCounters& counters() const { return counters_; }
  uint16_t self() const { return self_; }
  uint16_t swarm_size() const { return swarm_size_; }

 private:
  uint16_t self_;
  uint16_t swarm_size_;
  uint64_t run_id_;
  std::vector<int64_t> last_round_;  // per sender; -1 none
  SampleCounters counters_;
};

}  // namespace syrof::sim_dds
