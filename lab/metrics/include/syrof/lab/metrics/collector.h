// The metrics collector: the simulator reports what happens during a run
// (epoch starts, membership changes, every robot's state at every round end,
// contacts) and asks for the Metrics at the end. docs/metrics.md defines each
// metric; this class computes exactly that.
//
// Memory is bounded independently of the run's length: per-robot tables, the
// epochs some robot can still start (at most one per robot, plus those in
// their grace rounds), and short lists of the first events. Nothing is kept
// per round. The same sequence of calls gives the
// same Metrics, bit for bit.
//
// Call order within radio round r: OnEpochStart and OnMembership for the
// robots that stepped in r (any order among robots), then OnRoundEnd(r).
// Rounds increase from call to call. Contacts may come at any time.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <string_view>
#include <vector>

#include "syrof/lab/metrics/metrics.h"
#include "syrof/sync/activation.h"
#include "syrof/sync/ldmap.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"
#include "syrof/base/state_digest.h"

namespace syrof::lab::metrics {

/// An epoch's record (skew, P3, mode agreement) stays open while some robot
/// can still start it: a member (running, or paused for fewer than F rounds)
/// in the epoch before it, and for this many round ends after the last such
/// robot left, which covers a joiner (it starts at most K <= 200 rounds after
/// hearing a vote of the epoch before). There is no window in epochs: every
/// COOPERATIVE start is compared with every other start of its epoch by the
/// robots of its group, however far other groups have run ahead.
inline constexpr int64_t kRecordGraceRounds = 256;

/// One robot at the end of one radio round, after its synchronizer step.
struct RobotRound {
  uint16_t id = 0;
  bool running = false;         ///< switched on, not crashed, not paused
  bool member = false;          ///< running and its synchronizer status is MEMBER (not joining)
  bool paused = false;          ///< software stopped by a pause fault (its synchronizer state is kept)
  bool sync_member = false;     ///< synchronizer status is MEMBER, running or not
  uint16_t epoch = 0;
  wire::Mode epoch_mode = wire::Mode::kAutonomous;  ///< the mode its current epoch started in
  wire::Phase phase = wire::Phase::kWait;
  bool estimate_valid = false;  ///< estimator initialized and warmed up since the robot (re)started
  double true_x_m = 0;          ///< ground truth, arena frame
  double true_y_m = 0;
  double est_x_m = 0;           ///< the robot's estimate, arena frame
  double est_y_m = 0;
};

struct CollectorConfig {
  uint16_t robots = 0;         ///< robot ids are 0 .. robots - 1
  int64_t radio_round_ns = 0;  ///< alpha; converts contact times to rounds in the JSON
  /// F: a robot paused for F or more rounds restarts as a joiner, so it can
  /// no longer start the epoch after the one it was paused in.
  uint16_t silence_rounds = 6;
  /// The robots' activation schedule: under SSYNC each start is counted
  /// active or inactive (ActivationMetrics). Its script must outlive the
  /// collector.
  sync::ActivationConfig activation{};
};

/// Round phase: robots are aligned when every pair's boundaries are within
/// this (docs/clocks.md).
inline constexpr int64_t kPhaseThresholdNs = 1'000'000;

class Collector {
 public:
  /// Observations naming a robot id at or above `config.robots` (or above the
  /// build's wire::kMaxSwarmSize) are ignored and counted in diagnostics.
  explicit Collector(const CollectorConfig& config);

  /// `robot` started epoch `ldmap.epoch` at the end of `round`, handing
  /// `ldmap` (its mode and contents) to newRound.
  void OnEpochStart(uint16_t robot, int64_t round, const sync::LDMap& ldmap);
  /// The same, with the start's true time (for the skew in ms); without it
  /// the start counts as at the end of `round`.
  void OnEpochStart(uint16_t robot, int64_t round, int64_t time_ns, const sync::LDMap& ldmap);

  /// At the end of a round: the latest round boundary (true time, ns) of
  /// every running member. Feeds round_phase. Fixed memory: two histograms.
  void OnRoundPhases(std::span<const int64_t> boundaries_ns);

  /// `observer`'s failure detector removed `removed` and it added `joined`
  /// to its members in `round` (the StepOutput sets).
  void OnMembership(uint16_t observer, int64_t round, const wire::MemberSet& removed,
                    const wire::MemberSet& joined);

  /// The end of `round`: every robot of the swarm, running or not, once.
  void OnRoundEnd(int64_t round, std::span<const RobotRound> robots);

  /// Two bodies came into contact (a contact start, not every step of it).
  void OnCollision(int64_t time_ns, uint16_t a, uint16_t b);

  /// `robot`'s body came into contact with a wall (a contact start).
  void OnWallContact(int64_t time_ns, uint16_t robot);

  /// `robot`'s safety filter began to limit its command at `time_ns`,
  /// against robot `other` (none: a wall).
  void OnSafetyIntervention(int64_t time_ns, uint16_t robot, std::optional<uint16_t> other);
  /// The same for a precaution start (counted only).
  void OnSafetyPrecaution(uint16_t robot, std::optional<uint16_t> other);

  /// Joiner `robot` waits to be switched on from `time_ns`: its start disc
  /// is occupied.
  void OnJoinWait(uint16_t robot, int64_t time_ns);
  /// Joiner `robot`, which waited (OnJoinWait), was switched on at
  /// `time_ns`. A wait never ended stays open to the end of the run.
  void OnJoinWaitEnd(uint16_t robot, int64_t time_ns);

  /// `robot`'s app failed in `fault.callback`; the fault is listed as given
  /// (a robot's app faults at most once: later faults of it are ignored).
  void OnAppFault(const AppFault& fault);

  /// `robot`'s newRound returned a command the robot refused in `epoch`.
  void OnInvalidCommand(uint16_t robot, uint16_t epoch, std::string_view what);

  /// `robot`'s sendMessageData was refused in `epoch`.
  void OnPayloadRefused(uint16_t robot, uint16_t epoch, std::string_view what);

  /// The metrics of everything observed so far, with the run's facts. Epochs
  /// still in the window are measured as they stand. Does not change the
  /// collector, so it may also be called mid-run.
  Metrics Finish(const RunFacts& facts) const;

  /// What the checks of a run's properties still hold (the epochs open,
  /// whose later starts are compared with their first map) into `digest`
  /// (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest) const;
  /// How many times the run broke a property so far: P3, a collision, an
  /// app fault, an invalid command, a refused payload (lab/search prunes
  /// only runs with none).
  int64_t PropertyBreaks() const {
    return violations_ + collisions_ + static_cast<int64_t>(app_faults_.size()) + invalid_commands_.count +
           payloads_refused_.count;
  }

 private:
  // Starts of one epoch number, kept while some robot can still start it.
  struct EpochRecord {
    uint16_t epoch = 0;
    int64_t first_round = 0;
    int64_t last_round = 0;
    int64_t first_ns = 0;
    int64_t last_ns = 0;
    int64_t last_able_round = 0;  // last round end a robot could still start it
    wire::MemberSet starters;
    int64_t starts = 0;
    bool any_cooperative = false;
    bool any_autonomous = false;
    uint16_t first_cooperative_robot = 0;
    // The first COOPERATIVE map of the epoch; only COOPERATIVE epochs hold
    // one, so the window costs one map per COOPERATIVE epoch at most.
    std::unique_ptr<sync::LDMap> first_cooperative;
  };

  // Running totals of the skews of closed epochs.
  struct SkewTotals {
    int64_t epochs = 0;
    int64_t sum_rounds = 0;
    int64_t max_rounds = 0;
    bool has_max = false;
    uint16_t max_epoch = 0;
    int64_t with_skew = 0;
    std::array<int64_t, kSkewHistogramBins> histogram{};
    int64_t max_ns = 0;
    int64_t sum_ns = 0;

    void Add(uint16_t epoch, int64_t skew_rounds, int64_t skew_ns);
  };

  // Pairwise phase errors: 1 us bins below 2 ms, 100 us bins above.
  struct PhaseHistogram {
    std::vector<int64_t> bins;
    int64_t samples = 0;
    int64_t max_ns = 0;
    void Add(int64_t error_ns, int64_t count = 1);  // `count` pairs of one error
    void Clear();
    PhaseErrorStats Stats() const;
  };

  // P4 per epoch: epochs (and their starts) in which robots started in
  // different modes.
  struct MixedModeTotals {
    int64_t epochs = 0;
    int64_t robot_epochs = 0;
    void Add(const EpochRecord& record);
  };

  // Per robot, what the membership latencies need.
  struct RobotTrack {
    bool running = false;
    int64_t stopped_round = -1;    // first round end not running after running; -1 while running
    int64_t joining_since = -1;    // first round end running but not a member; -1 otherwise
    bool collided = false;
    bool touched_wall = false;
    bool removed = false;
    bool joined = false;
    bool app_faulted = false;
    int64_t paused_rounds = 0;     // consecutive round ends paused
    // Round ends [start, end) at which the robot was stopped after having
    // run (pauses, then a crash): its failure detector did not count them.
    std::vector<std::pair<int64_t, int64_t>> offline;
  };

  bool Known(uint16_t robot) const;
  EpochRecord* FindRecord(uint16_t epoch);
  void CloseRecords(int64_t round, std::span<const RobotRound> robots);
  int64_t OfflineRounds(const RobotTrack& track, int64_t after, int64_t until) const;

  CollectorConfig config_;
  std::vector<RobotTrack> tracks_;

  std::vector<EpochRecord> open_epochs_;  // in the order they were opened
  SkewTotals skews_;
  MixedModeTotals mixed_;
  PhaseHistogram phase_run_;
  PhaseHistogram phase_residual_;
  std::vector<int64_t> phase_residues_;   // OnRoundPhases' scratch: each boundary modulo the round
  struct PhaseGroup {
    int64_t residue_ns;
    int64_t count;  // boundaries with this residue
  };
  std::vector<PhaseGroup> phase_groups_;  // OnRoundPhases' scratch: the sorted residues' runs
  int64_t phase_rounds_ = 0;
  int64_t phase_round_index_ = 0;         // OnRoundPhases calls
  std::optional<int64_t> phase_converged_;  // OnRoundPhases call that began the aligned stretch
  int64_t epochs_started_ = 0;
  int64_t epoch_starts_ = 0;
  int64_t stale_starts_ = 0;
  int64_t repeated_starts_ = 0;

  int64_t violations_ = 0;
  std::vector<Violation> first_violations_;
  int64_t cooperative_starts_ = 0;
  int64_t cooperative_epochs_ = 0;
  int64_t unchecked_cooperative_starts_ = 0;

  int64_t disagreement_run_rounds_ = 0;  // the current run of disagreeing rounds
  int64_t max_disagreement_rounds_ = 0;
  int64_t disagreement_rounds_ = 0;

  int64_t collisions_ = 0;
  int64_t robots_collided_ = 0;
  std::vector<CollisionEvent> first_collisions_;
  int64_t wall_contacts_ = 0;
  int64_t robots_touched_wall_ = 0;
  std::vector<WallContactEvent> first_wall_contacts_;

  int64_t estimate_samples_ = 0;
  double squared_error_sum_m2_ = 0;
  double max_error_m_ = 0;
  uint16_t max_error_robot_ = 0;
  int64_t max_error_round_ = 0;
  int64_t non_finite_estimates_ = 0;

  int64_t removals_ = 0;
  int64_t joins_ = 0;
  int64_t robots_removed_ = 0;
  int64_t robots_joined_ = 0;
  int64_t removals_of_running_ = 0;
  int64_t removal_latency_samples_ = 0;
  int64_t removal_latency_sum_rounds_ = 0;
  int64_t removal_latency_max_rounds_ = 0;
  int64_t join_latency_samples_ = 0;
  int64_t join_latency_sum_rounds_ = 0;
  int64_t join_latency_max_rounds_ = 0;

  int64_t interventions_ = 0;
  int64_t precautions_ = 0;
  std::vector<int64_t> robot_interventions_;  // by robot id
  std::vector<int64_t> robot_starts_;         // by robot id
  // Under SSYNC: starts counted active and inactive, each robot's current
  // run of inactive starts, and the longest run seen.
  int64_t active_starts_ = 0;
  int64_t inactive_starts_ = 0;
  std::vector<int64_t> inactive_run_;         // by robot id
  int64_t longest_inactive_run_ = 0;
  // ASYNC: each robot's cycles, stepped with its epoch starts as the robot
  // steps its own (sync::AsyncTracker), and what they add up to.
  std::vector<sync::AsyncTracker> async_cycles_;  // by robot id
  int64_t move_epochs_ = 0;
  int64_t stale_move_epochs_ = 0;
  int64_t cuts_ = 0;
  std::vector<int64_t> robot_cooperative_starts_;  // by robot id
  std::vector<SafetyIntervention> first_interventions_;
  int64_t join_waits_ = 0;
  std::vector<JoinWait> joiner_waits_;  // in the order they began

  std::vector<AppFault> app_faults_;
  AppIncidents invalid_commands_;
  AppIncidents payloads_refused_;

  int64_t rounds_observed_ = 0;
  int64_t ignored_observations_ = 0;
};

}  // namespace syrof::lab::metrics
