// App-level agreement: in an epoch that robots start COOPERATIVE they hold
// the same map, so a correct app's global state (what newRound returns, and
// endOfRound's after it) must be the same on every one of them. The tracker
// compares each robot's returned state with the first one returned for the
// same epoch and the same map, and reports per epoch; an app that calls
// rand(), reads the clock or its own id into its state is caught here.
//
// Robots with different maps in one epoch number (two sides of a
// partition, a P3 breach: the platform's fault, not the app's) form
// separate groups, each compared within itself; the map is known by a
// fingerprint the caller computes (MapFingerprint in lab/sim) of everything
// the app sees except self_id and the members' phases (which P3 does not
// compare either).
//
// Bounded memory: a window of the kAgreementEpochWindow newest epochs, each with at
// most kMaxMapGroups groups of a few numbers; an epoch's verdict is final
// when it leaves the window or at Finish. Deterministic: the same calls give
// the same result.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/metrics/metrics.h"
#include "syrof/base/state_digest.h"

namespace syrof::lab::metrics {

/// Epochs compared while fewer than this many epochs behind the newest
/// epoch a call was recorded for; a call further behind is not compared
/// (AgreementMetrics::unchecked_calls).
inline constexpr int kAgreementEpochWindow = 32;

/// Distinct maps compared within one epoch; further ones are not compared
/// (AgreementMetrics::unchecked_calls).
inline constexpr size_t kMaxMapGroups = 8;

class AgreementTracker {
 public:
  enum class Call : uint8_t { kNewRound, kEndOfRound };

  /// `robot`'s `call` for `epoch` returned `state` (a callback that
  /// faulted is not reported). Only COOPERATIVE calls count: `cooperative`
  /// is the map's mode. `map_fingerprint` identifies the map the app saw.
  /// `round` is the radio round of the call (for the report).
  void OnAppState(uint16_t robot, int64_t round, Call call, uint16_t epoch, bool cooperative, uint64_t map_fingerprint,
                  uint8_t state);

  /// The metrics of everything so far; does not change the tracker.
  AgreementMetrics Finish() const;

  /// The epochs still open, whose later calls are compared with what they
  /// hold, into `digest` (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest) const;
  /// Calls that disagreed so far.
  int64_t disagreeing_calls() const { return disagreeing_calls_; }

 private:
  struct Group {
    uint64_t fingerprint = 0;
    bool has_new_round = false;
    uint16_t new_round_robot = 0;
    uint8_t new_round_state = 0;
    bool has_end = false;
    uint16_t end_robot = 0;
    uint8_t end_state = 0;
  };
  struct EpochRecord {
    uint16_t epoch = 0;
    bool disagreed = false;
    std::vector<Group> groups;
  };

  EpochRecord* Find(uint16_t epoch);
  void Close(const EpochRecord& record);
  void Disagree(EpochRecord& record, uint16_t robot, int64_t round, Call call, uint8_t state, uint16_t reference_robot,
                uint8_t reference_state);

  std::vector<EpochRecord> open_;  // in the order opened
  bool any_ = false;
  uint16_t newest_ = 0;
  int64_t epochs_ = 0;
  int64_t agreed_closed_ = 0;
  int64_t split_epochs_closed_ = 0;
  int64_t new_round_calls_ = 0;
  int64_t end_of_round_calls_ = 0;
  int64_t unchecked_calls_ = 0;
  int64_t disagreeing_calls_ = 0;
  std::optional<Disagreement> first_;
};

}  // namespace syrof::lab::metrics
