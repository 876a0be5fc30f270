// Round alignment: how a robot lines its radio rounds up with the group's,
// from where in its own round each beacon arrives (docs/clocks.md).
//
// Every robot broadcasts its beacon at the end of its round (the send slot
// is the round boundary), so when two robots' rounds are aligned a beacon
// arrives at the receiver's boundary plus the link's delay. A beacon that
// arrives x nanoseconds into the receiver's round says the sender's boundary
// is x - delay later than the receiver's, modulo a round: the phase error,
// wrapped into [-round/2, round/2).
//
// Usage, once per radio round, after the synchronizer's step:
//   1. collect the senders and arrival offsets (arrival time - start of the
//      round now ending, local clock) of the round's synchronizer beacons;
//   2. call Align() with them and whether the robot is a member;
//   3. move the round task's next boundary by `correction_ns` (later when
//      positive).
// The decision, in order:
//   - a joiner (silent, so nobody follows it) steps onto the median error at
//     once: it is aligned long before the group's next epoch lets it vote;
//   - a member whose errors are scattered (the middle half of them wider
//     than lock_spread_ns: robots that booted anywhere in a round) steps
//     onto the lowest-id robot it hears, if that id is below its own, and
//     otherwise stays: the swarm gathers on one robot's phase in a round or
//     two, where averaging phases on a circle can stall with robots spread
//     evenly round it;
//   - otherwise a member moves a quarter of the median error, at most
//     max_slew_ns per round. The median ignores any minority of bad clocks
//     or late beacons; a robot whose crystal is off by 1000 ppm (50 us per
//     50 ms round) tracks the group with an error of about five times that.
//
// The errors are a round old. A beacon heard in the round now ending left
// its sender at the boundary that started this round, and the correction
// this robot decided at that boundary moved the one now passing: the
// samples cannot show it yet, so Align takes it off (`unseen_correction_ns`).
// Without that a joiner jumped twice, and a pair of robots each moving half
// of a round-old error swung between +-10 ms every six rounds for good (the
// firmware swarm, docs/clocks.md). The peers' own last corrections stay
// unseen; a quarter keeps the loop damped despite them.
//
// Pure: no clock, I/O or allocation; at most kMaxAlignmentSamples samples
// are used (the rest ignored); time bounded by an insertion sort of them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace syrof::sync {

/// Most arrival offsets one Align() call uses (two beacons per robot of the
/// largest swarm: a misaligned round may hold two from one sender).
inline constexpr size_t kMaxAlignmentSamples = 64;

struct AlignmentConfig {
  int64_t round_ns = 50'000'000;     ///< alpha, the radio round (> 0)
  int64_t expected_delay_ns = 0;     ///< send slot to arrival on an aligned link
  int64_t max_slew_ns = 12'500'000;  ///< a member's largest gradual correction per round (>= 0)
  int64_t lock_spread_ns = 6'250'000; ///< errors scattered wider than this: follow the lowest id
  uint16_t self_id = 0;              ///< this robot's id
  bool enabled = true;               ///< off: corrections are always 0 (errors still measured)

  /// Defaults for a round of `round_ns`: max slew a quarter round, lock
  /// spread an eighth.
  static AlignmentConfig ForRound(int64_t round_ns, uint16_t self_id = 0);
};

/// One synchronizer beacon heard this round.
struct AlignmentSample {
  uint16_t sender = 0;
  int64_t offset_ns = 0;  ///< arrival - start of the round now ending, local clock
};

/// What one Align() call found and decided.
struct AlignmentStep {
  int64_t correction_ns = 0;   ///< move the next boundary by this (later when positive)
  int64_t median_error_ns = 0; ///< the group's boundary relative to this robot's (0 without samples)
  uint8_t samples = 0;         ///< offsets used
  int64_t spread_ns = 0;       ///< width of the middle half of the errors
  bool jumped = false;         ///< stepped at once (a joiner, or a scattered member following)
};

/// Running figures, for metrics and tests; never read by Align's decision.
struct AlignmentStats {
  uint32_t rounds_with_samples = 0;
  uint32_t jumps = 0;
  int64_t last_error_ns = 0;
  int64_t largest_correction_ns = 0;  ///< in magnitude
};

/// `x` wrapped into [-round_ns / 2, round_ns / 2); round_ns > 0.
int64_t WrapPhase(int64_t x, int64_t round_ns);

/// The round's decision from `samples` (any order). `member`: false for a
/// robot that is joining (silent), which jumps. `unseen_correction_ns`: the
/// correction this robot made at the previous boundary (the last call's
/// `correction_ns`, if it was applied), which the samples cannot show yet
/// (below); it is taken off every error. Updates `stats`.
AlignmentStep Align(const AlignmentConfig& config, std::span<const AlignmentSample> samples, bool member,
                    AlignmentStats& stats, int64_t unseen_correction_ns = 0);

}  // namespace syrof::sync
