// The metrics of one simulated-lab run, as the grader scores them, and their
// JSON form (metrics.json). docs/metrics.md defines every field; this file
// mirrors that document's order.
//
// Counts are int64_t. A value that may be undefined (a mean over no samples,
// an infinite separation) is std::optional or a double that may be
// non-finite; both print as JSON null, so NaN and infinities never reach the
// file.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace syrof::lab::metrics {

/// Version of the metrics.json layout; raised when a field changes meaning or
/// is removed (adding a field does not raise it).
/// Version 2: `app` became an object (name, source, faults, invalid
/// commands, refused payloads); in version 1 it was the app's source string.
/// The top-level `round_start_skew_us` (DDS and the emulated firmware) was
/// an addition: a DDS run keeps `dds.round_start_skew_us`, the same figure,
/// for readers of the version-2 layout, so the version stays.
inline constexpr int kSchemaVersion = 2;

/// Skew histogram size: entries 0 .. kSkewHistogramBins - 2 count epochs of
/// exactly that skew in rounds; the last entry counts every larger skew.
inline constexpr size_t kSkewHistogramBins = 11;

/// At most this many P3 violations are listed (all are counted).
inline constexpr size_t kMaxListedViolations = 10;
/// At most this many collisions are listed, the first ones (all are counted).
inline constexpr size_t kMaxListedCollisions = 100;
/// At most this many wall contacts are listed, the first ones (all are counted).
inline constexpr size_t kMaxListedWallContacts = 100;

/// At most this many safety interventions are listed, the first ones (all are counted).
inline constexpr size_t kMaxListedInterventions = 10;

/// One declarative goal check of the scenario (lab/goals), as judged.
struct GoalCheckResult {
  std::string name;
  std::string check;        ///< "slots", "shape", "line", "gathered", "circle", "coverage"
  std::string when;         ///< "final" or "every_epoch"
  bool passed = false;
  double value = 0;         ///< the measured value; non-finite prints null
  double limit = 0;         ///< what it is compared with
  std::string unit;         ///< "m", "rad" or "fraction"
  std::string reason;       ///< one line a student understands
  int64_t samples = 0;      ///< epoch samples judged
  std::optional<double> deadline_s;
  std::optional<int64_t> held_from_epoch;  ///< deadline checks: the epoch it held from to the end
  std::optional<double> held_from_s;
};

/// The assignment's own goal: the scenario's declared checks when it has
/// any (`source` "scenario", every check in `checks`), else the built-in
/// app's goal checker ("builtin").
struct GoalResult {
  std::string app;     ///< the app whose goal was checked
  bool reached = false;
  double error_m = 0;  ///< distance from the goal, metres; non-finite prints null
  std::string detail;  ///< one human-readable line
  std::string source = "builtin";       ///< "builtin" or "scenario"
  std::vector<GoalCheckResult> checks{};  ///< the scenario's checks, in file order
};

/// The first call whose global state differed from its group's reference.
struct Disagreement {
  uint16_t epoch = 0;
  int64_t round = 0;
  std::string callback;         ///< "new_round" or "end_of_round"
  uint16_t robot = 0;
  uint8_t state = 0;
  uint16_t reference_robot = 0;  ///< the robot whose state came first for that epoch and map
  uint8_t reference_state = 0;
};

/// ASYNC's part of ActivationMetrics: the cycles' moves, counted with
/// sync::AsyncTracker from each robot's epoch starts, as the robot did.
struct AsyncActivationMetrics {
  int64_t max_delay_epochs = 0;   ///< the schedule's bound
  double min_move_m = 0;          ///< non-rigid moves' least cover (0: rigid)
  int64_t move_epochs = 0;        ///< robot-epochs in which a move ran (or held after a cut)
  int64_t stale_move_epochs = 0;  ///< of those, epochs after the look's: a move on a map no longer the newest
  int64_t moves_cut = 0;          ///< moves the scheduler cut (each stops once it covered min_move_m)
};

/// The activation schedule under SSYNC or ASYNC (docs/activation.md),
/// counted over robot-epoch starts. SSYNC: the schedule decides from each
/// start's map (sync::IsActive), as the robot did; ASYNC: "active" is a
/// start in which the robot looked (began a cycle).
struct ActivationMetrics {
  std::string model;      ///< "ssync" or "async"
  std::string schedule;   ///< "random", "round_robin" or "scripted"
  std::optional<int64_t> fair_within;  ///< the random schedule's bound; unset for the others
  int64_t active_starts = 0;    ///< robot-epoch starts the robot was active in (newRound called)
  int64_t inactive_starts = 0;  ///< robot-epoch starts the schedule left the robot out of
  /// The smallest bound the run met: 1 + the most consecutive epoch starts
  /// any robot was left out of (1: every start active).
  int64_t fair_within_achieved = 1;
  std::optional<AsyncActivationMetrics> async;  ///< ASYNC only
};

/// App-level agreement over COOPERATIVE epochs (AgreementTracker).
struct AgreementMetrics {
  int64_t cooperative_epochs = 0;          ///< epochs with at least one COOPERATIVE call reported
  int64_t agreed_epochs = 0;               ///< of those, epochs where every state agreed within its map
  std::optional<double> agreed_fraction;   ///< agreed / cooperative; none without epochs
  int64_t split_epochs = 0;                ///< epochs whose COOPERATIVE robots held more than one map
  int64_t new_round_calls = 0;             ///< COOPERATIVE newRound returns compared
  int64_t end_of_round_calls = 0;          ///< COOPERATIVE endOfRound returns compared
  int64_t disagreeing_calls = 0;           ///< returns that differed from their reference
  int64_t unchecked_calls = 0;             ///< too far behind, or beyond kMaxMapGroups maps
  std::optional<Disagreement> first_disagreement;
};

/// What the simulator knows about the run as a whole, handed to Finish().
struct RunFacts {
  uint64_t seed = 0;
  uint16_t robots = 0;
  double sim_seconds = 0;   ///< simulated time
  double wall_seconds = 0;  ///< host time the run took; the one field that varies between identical runs
  int64_t radio_rounds = 0;
  /// Smallest surface gap between two bodies over the run, metres (negative
  /// while overlapping); +infinity when no two bodies were ever compared.
  double min_separation_m = 0;
  GoalResult goal;
  std::string app_name;    ///< the app's own name, e.g. "circle"
  std::string app_source;  ///< "builtin:NAME" or the path of the student's library
  /// A library's app host: what its sandbox could not apply on this machine,
  /// one line each (empty: everything applied). Unset for a built-in app.
  std::optional<std::vector<std::string>> app_sandbox;
  std::string scenario;    ///< scenario name or file
  bool safety_enabled = true;  ///< the scenario's `safety` (docs/safety.md)
};

/// One P3 breach: `robot` started `epoch` COOPERATIVE with a map that is not
/// SameKnowledge with the first COOPERATIVE map of that epoch (`first_robot`'s).
struct Violation {
  uint16_t epoch = 0;
  uint16_t robot = 0;
  int64_t round = 0;
  uint16_t first_robot = 0;
};

/// One body-body contact start; a < b.
struct CollisionEvent {
  int64_t time_ns = 0;
  uint16_t a = 0;
  uint16_t b = 0;
};

struct WallContactEvent {
  int64_t time_ns = 0;
  uint16_t robot = 0;
};

/// One app call that failed (the robot then stopped as if crashed).
struct AppFault {
  uint16_t robot = 0;
  std::string callback;  ///< "init", "new_round" or "end_of_round"
  uint16_t epoch = 0;    ///< the robot's epoch (0 for init)
  int64_t time_ns = 0;
  std::string verdict;   ///< "crashed", "timeout", ... (docs/apps.md)
  std::string detail;
};

/// Where an app misbehaved without faulting.
struct AppIncident {
  uint16_t robot = 0;
  uint16_t epoch = 0;
  std::string what;  ///< e.g. "MOVE_TO x_m is not finite", "10 bytes"
};

/// How often one kind of misbehaviour happened, and its first occurrence.
struct AppIncidents {
  int64_t count = 0;
  std::optional<AppIncident> first;
};

struct AppMetrics {
  std::string name;                  ///< from RunFacts
  std::string source;                ///< from RunFacts
  std::vector<AppFault> faults;      ///< in the order they happened; at most one per robot
  AppIncidents invalid_commands;     ///< newRound commands refused (the robot held still)
  AppIncidents payload_refused;      ///< sendMessageData calls over the limit
  std::optional<std::vector<std::string>> sandbox;  ///< from RunFacts; null in JSON for a built-in app
};

struct SynchronyMetrics {
  int64_t max_start_skew_rounds = 0;        ///< 0 when no epoch started
  std::optional<uint16_t> max_skew_epoch;   ///< the first epoch (in start order) with the max skew
  std::optional<double> mean_start_skew_rounds;
  int64_t epochs_measured = 0;              ///< epochs whose skew is counted (every epoch started)
  int64_t epochs_with_skew = 0;             ///< epochs with skew > 0
  std::array<int64_t, kSkewHistogramBins> skew_histogram{};
  int64_t stale_starts = 0;                 ///< starts too far behind to be matched (docs/metrics.md)
  int64_t repeated_starts = 0;              ///< a robot starting an epoch it already started
  double max_start_skew_ms = 0;             ///< the same skews in true time: last start - first start
  std::optional<double> mean_start_skew_ms;
};

/// Percentiles of the pairwise round-phase errors in a set of rounds.
struct PhaseErrorStats {
  int64_t samples = 0;  ///< robot pairs x rounds
  double p50_ms = 0;
  double p99_ms = 0;
  double max_ms = 0;
};

/// How far apart the robots' radio-round boundaries are (docs/clocks.md):
/// at every round end, for every pair of running members, the distance
/// between their latest boundaries modulo a round, in true time.
struct RoundPhaseMetrics {
  double threshold_ms = 1.0;              ///< "aligned": every pair within this
  int64_t rounds_measured = 0;            ///< round ends with two or more members running
  std::optional<double> converged_s;      ///< start of the final stretch of aligned rounds; null if the last was not
  PhaseErrorStats run;                    ///< every round measured
  PhaseErrorStats residual;               ///< the rounds since converged_s (samples 0 when null)
};

struct CommonKnowledgeMetrics {
  int64_t violations = 0;                   ///< P3 breaches, robot-epoch starts
  std::vector<Violation> first_violations;  ///< at most kMaxListedViolations
  std::optional<double> cooperative_fraction;  ///< none when no epoch started
  int64_t cooperative_starts = 0;
  int64_t autonomous_starts = 0;
  int64_t cooperative_epochs = 0;           ///< epochs with at least one COOPERATIVE start
  int64_t unchecked_cooperative_starts = 0; ///< COOPERATIVE stale starts, not compared
  int64_t max_mode_disagreement_rounds = 0;
  int64_t mode_disagreement_rounds = 0;     ///< all rounds with a disagreement
  int64_t mixed_mode_epochs = 0;            ///< P4 per epoch: epochs started in both modes
  int64_t mixed_mode_robot_epochs = 0;      ///< the starts (robot-epochs) of those epochs
  std::vector<int64_t> starts_by_robot;     ///< epoch starts of each robot, by id
  std::vector<int64_t> cooperative_starts_by_robot;  ///< COOPERATIVE ones, by id
};

struct CollisionMetrics {
  int64_t count = 0;
  double min_separation_m = 0;              ///< from RunFacts; non-finite prints null
  int64_t robots_involved = 0;              ///< distinct robots in at least one collision
  std::vector<CollisionEvent> pairs;        ///< the first kMaxListedCollisions
};

struct WallMetrics {
  int64_t contacts = 0;
  int64_t robots_involved = 0;
  std::vector<WallContactEvent> first_contacts;  ///< the first kMaxListedWallContacts
};

/// One safety intervention start: `robot`'s command was limited against
/// `other` (a robot id, or none for a wall).
struct SafetyIntervention {
  int64_t time_ns = 0;
  uint16_t robot = 0;
  std::optional<uint16_t> other;
};

/// A robot's intervention count (robots with none are not listed).
struct RobotInterventions {
  uint16_t robot = 0;
  int64_t interventions = 0;
};

/// A joiner that waited for its start disc to clear.
struct JoinWait {
  uint16_t robot = 0;
  int64_t from_ns = 0;                  ///< when it was due to join and found its disc occupied
  std::optional<int64_t> joined_ns;     ///< when it was switched on; unset: it never was
};

struct SafetyMetrics {
  bool enabled = true;                          ///< from RunFacts
  int64_t interventions = 0;                    ///< intervention starts, all robots (charged: assignments grade them)
  /// Precaution starts, all robots: the filter held a command that kept the
  /// rule the app is held to, only for its wider cover (motion::SafetyOutcome;
  /// not charged, not in the replay).
  int64_t precautions = 0;
  int64_t robots_involved = 0;                  ///< robots with at least one
  std::vector<RobotInterventions> per_robot;    ///< by robot id, robots with at least one
  std::vector<SafetyIntervention> first;        ///< the first kMaxListedInterventions
  int64_t join_waits = 0;                       ///< joiners that waited for their start disc to clear
  std::vector<JoinWait> joiner_waits;           ///< each wait, in the order they began
};

struct EstimationMetrics {
  std::optional<double> position_rmse_m;
  std::optional<double> max_error_m;
  std::optional<uint16_t> max_error_robot;
  std::optional<int64_t> max_error_round;
  int64_t samples = 0;                      ///< robot-rounds with a valid, finite estimate
  int64_t non_finite_samples = 0;           ///< valid estimates with a NaN or infinite error, excluded
};

struct MembershipMetrics {
  int64_t removals = 0;                     ///< summed over observers
  int64_t joins = 0;                        ///< summed over observers
  int64_t robots_removed = 0;               ///< distinct robots removed by someone
  int64_t robots_joined = 0;                ///< distinct robots added by someone
  int64_t removals_of_running_robots = 0;   ///< removed while running (losses, partitions)
  std::optional<int64_t> max_removal_latency_rounds;
  std::optional<double> mean_removal_latency_rounds;
  int64_t completed_joins = 0;              ///< robots that went from joining to member
  std::optional<int64_t> max_join_latency_rounds;
  std::optional<double> mean_join_latency_rounds;
};

/// Round-start skew outside the lab (metrics.json `round_start_skew_us`,
/// docs/metrics.md): how far apart the robots' round boundaries lay. One
/// sample a round, in every runtime: the spread (latest minus earliest) of
/// the round's boundaries over the robots that marked it, on one clock, for
/// a round two or more robots marked (lab::sim::RemoteWorld). A DDS robot
/// marks a boundary with its round task's activation; an emulated robot
/// with its beacon of the round, as it reached the host (docs/firmware.md).
struct SkewStats {
  int64_t samples = 0;
  double p50_us = 0;
  double p99_us = 0;
  double max_us = 0;
};

/// The figures of `skews_ns` (in any order; nanoseconds). A percentile p is
/// the nearest rank: the smallest sample with at least the fraction p of
/// the samples at or below it (of 200 samples, p50 is the 100th smallest and
/// p99 the 198th); max is the largest. All 0 without samples.
SkewStats SkewOf(std::vector<int64_t> skews_ns);

/// The DDS runtime's own figures (`syrof swarm`, docs/dds.md; the fields in
/// docs/metrics.md, "dds"): only a run over DDS has them.
struct DdsMetrics {
  uint32_t domain_id = 0;
  double delivery_ratio = 0;                ///< beacons delivered within their round / beacons the channel passed
  std::vector<double> cpu_seconds_per_robot;  ///< per robot process (0 for one never started)
  int64_t reports_rejected = 0;             ///< robot reports that failed their checks
  int64_t reports_late = 0;                 ///< reports for a round already closed
  int64_t reports_other_runs = 0;           ///< reports of another run on the same domain
  int64_t drives_other_runs = 0;            ///< drive commands of another run on the same domain
  bool stopped_early = false;               ///< a signal ended the run
  /// Per robot: its exit code, or minus the signal that ended it; unset for
  /// a robot never started.
  std::vector<std::optional<int>> robot_exits;
};

struct Diagnostics {
  int64_t rounds_observed = 0;      ///< OnRoundEnd calls
  int64_t ignored_observations = 0; ///< observations naming a robot id >= robots
};

/// Everything metrics.json holds, in its order.
struct Metrics {
  /// Where the robots ran: "lab" (`syrof run`), "dds" (`syrof swarm`) or
  /// "firmware" (`syrof-firmware-swarm`).
  std::string runtime = "lab";
  std::string scenario;
  AppMetrics app;
  uint64_t seed = 0;
  uint16_t robots = 0;
  double sim_seconds = 0;
  double wall_seconds = 0;
  int64_t radio_rounds = 0;
  int64_t radio_round_ns = 0;
  int64_t epochs_started = 0;  ///< distinct epochs (docs/metrics.md)
  int64_t epoch_starts = 0;    ///< robot-epoch starts
  GoalResult goal;
  std::optional<ActivationMetrics> activation;  ///< only under SSYNC and ASYNC; the file has no `activation` key otherwise
  SynchronyMetrics synchrony;
  RoundPhaseMetrics round_phase;
  /// Only outside the lab (RemoteWorld), the file has no key otherwise:
  /// the lab's robots share the engine's boundary, a skew of nothing.
  std::optional<SkewStats> round_start_skew;
  CommonKnowledgeMetrics common_knowledge;
  /// Filled by the runtime from its AgreementTracker; unset (null in the
  /// file) where the runtime cannot see the app's returns (the firmware).
  std::optional<AgreementMetrics> agreement;
  CollisionMetrics collisions;
  WallMetrics walls;
  SafetyMetrics safety;
  EstimationMetrics estimation;
  MembershipMetrics membership;
  Diagnostics diagnostics;
  std::optional<DdsMetrics> dds;  ///< only over DDS; the file has no `dds` key otherwise
};

/// metrics.json: pretty-printed with a 2-space indent and a trailing newline,
/// fields in a fixed order (docs/metrics.md). Equal metrics give equal bytes;
/// NaN and infinities print as null; invalid UTF-8 in strings is replaced.
std::string ToJson(const Metrics& metrics);

/// Each joiner that never joined because its start disc stayed occupied, in
/// the words the grade's reasons and `syrof run`'s summary use: "robot 2
/// never joined: it waited 38.0 s for a clear start disc (from 12.0 s to the
/// end)", one per wait left open at the end of the run, in the order they
/// began. Empty when every joiner joined.
std::vector<std::string> UnjoinedJoiners(const Metrics& metrics);

}  // namespace syrof::lab::metrics
