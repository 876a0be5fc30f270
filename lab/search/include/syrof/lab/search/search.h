// A search test (docs/apps.md, "Search tests"): the lab run again and again
// on one scenario, each time with another pattern of lost beacons, looking
// for a pattern that breaks the swarm. In synchronous rounds the only
// nondeterminism is which beacons are lost, and the lab is deterministic, so
// a pattern found is a counterexample anyone can replay (a scripted channel,
// docs/scenarios.md).
//
// The patterns are tried in order of how many beacons they lose (0, 1, ...
// up to max_losses), and those of one size by their earliest loss first, so
// the first pattern that breaks the run is already the smallest and then
// the earliest: no shrinking is needed.
//
// States seen are pruned. At every radio round's start a run's state has a
// fingerprint (Simulation::StateDigest: the world, the beacons in the air,
// every robot's synchronizer, estimator and safety filter, the app's call
// history, what the property checks hold). A run that reaches, with losses
// so far L, a state that another pattern reached at that round with at most
// L losses (other losses, or as many) goes on as that pattern would with
// this run's later losses: a pattern of no more losses that the search
// tries anyway. So the run stops there, if it broke nothing so far, and
// every longer pattern that adds only later losses to it is skipped without
// running. A loss that the protocol masks (the next round's beacons carry
// the same news) leaves the state as if nothing was lost, and with it every
// pattern that builds on it. The app's state is taken as what its calls
// gave it (the lab's determinism asks as much of an app). Each run is the whole scenario; the
// losses fall in its first `epochs` epochs (as the loss-free run counts
// them). A beacon the scenario already loses (a cut, a partition, a robot
// that is not running, deaf or mute) is not a slot: losing it again would
// repeat a shorter pattern.
//
// The activation search (docs/activation.md, "The schedule search") is the
// same search over SSYNC schedules instead of losses: a slot is one member
// of one epoch of the window (its epochs and members as the run with every
// robot active has them), a pattern leaves those members inactive, and a
// pattern that leaves an epoch with no active member, or a robot inactive
// in `fair_within` epochs in a row, is not a schedule and is not run. The
// fewest inactive robot-epochs first, the earliest first among as many. The
// schedule after the window activates every member; the scenario's channel
// is kept (its losses are the seed's, the same in every run). Nothing is
// pruned: the state holds each app's call history, and two schedules differ
// in which robots were called in which epoch, so no two ever meet in a
// state; every schedule runs to its end.
//
// Under ASYNC (activation_model kAsync) a pattern times robots' cycles
// instead: each look a robot makes in the window (the first epoch start
// after its previous cycle) gets a cycle, sync::AsyncCycle{start_delay
// 0..D, move_epochs 1..D+1, cut where min_move_m > 0}, and a *deviating
// cycle* is any but FSYNC's (a one-epoch uncut move). Which looks a robot
// makes depends on its earlier cycles, so the patterns are walked as a
// tree: look by look in (epoch, robot) order, each deviating choice before
// leaving the look at FSYNC's. The fewest deviating cycles first, and among
// as many the earliest first (then the shortest cycle: AsyncChoices'
// order). Looks after the window (and unlisted ones) are one-epoch moves.
// Nothing is pruned, for the same reason as under SSYNC: two schedules
// call the apps at other epochs (and a robot's pending move is in its
// state), so no two meet in a state.
//
// Usage:
//   SearchOptions options{.max_losses = 2, .epochs = 4, .jobs = 2};
//   SearchResult result = Search(scenario, options);
//   if (result.counterexample) ... WithLosses(scenario, result.counterexample->lost)
#pragma once

#include <compare>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/lab/apps/app_supply.h"
#include "syrof/lab/base/error.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/world/channel.h"
#include "syrof/sync/activation.h"

namespace syrof::lab::search {

/// Most beacons a searched pattern may lose.
inline constexpr int kMaxSearchLosses = 8;
/// Most epochs the losses may span.
inline constexpr int kMaxSearchEpochs = 1000;
/// Most threads running patterns side by side.
inline constexpr int kMaxSearchJobs = 64;
/// Most beacon slots a window may hold (robots x robots x rounds): a search
/// is for a small swarm over a few epochs.
inline constexpr int64_t kMaxSearchSlots = 1'000'000;

/// Most inactive robot-epochs an activation search's pattern may hold.
inline constexpr int kMaxSearchInactive = 64;
/// Most deviating cycles an ASYNC schedule may hold.
inline constexpr int kMaxSearchDeviations = 64;
/// Most looks (robot-epochs of the window) an ASYNC search walks.
inline constexpr int64_t kMaxAsyncSearchLooks = 4096;

struct SearchOptions {
  int max_losses = 1;         ///< 0 .. kMaxSearchLosses (not with `activations`)
  /// Search SSYNC schedules instead of losses (above): patterns of up to
  /// max_inactive inactive robot-epochs in the first `epochs` epochs.
  bool activations = false;
  int max_inactive = kMaxSearchInactive;  ///< 1 .. kMaxSearchInactive
  /// Activation search: no robot inactive in this many epochs of the window
  /// in a row (1 .. kMaxSearchEpochs); 0: no bound.
  int fair_within = 0;
  /// Activation search: the model searched, kSsync (the schedules above) or
  /// kAsync (cycle timings, above); kFsync is not a search.
  sync::ActivationModel activation_model = sync::ActivationModel::kSsync;
  /// ASYNC: most deviating cycles a schedule holds (1 .. kMaxSearchDeviations).
  int max_deviations = kMaxSearchDeviations;
  /// ASYNC: the delay bound D (1 .. sync::kMaxAsyncDelayEpochs); 0: the
  /// scenario's activation.max_delay_epochs, which must then be ASYNC's.
  int max_delay_epochs = 0;
  /// ASYNC: moves may be cut once they covered this (non-rigid); none: the
  /// scenario's min_move_m under ASYNC, else 0 (rigid, no cuts).
  std::optional<double> min_move_m;
  int epochs = 3;             ///< 1 .. kMaxSearchEpochs: the losses fall in the first this many epochs
  int jobs = 1;               ///< 1 .. kMaxSearchJobs: runs side by side (the result does not depend on it)
  double time_limit_s = 0;    ///< stop after this much wall time; 0: no limit
  /// The robots' apps, as the runs' SimulationOptions::apps (a library
  /// through app_host::AppsFor); default: the scenario's built-in app. The
  /// factory is called from `jobs` threads at once.
  lab::apps::AppSupply apps;
  /// Prune states seen (above); false runs every pattern to its end.
  bool prune = true;
  /// A self-test of the pruning, for tests: each pattern pruned is also run
  /// to its end, with the pattern it stood for, and the two must end in the
  /// same state and break the same properties (SearchResult::pruning_mismatches).
  bool check_pruning = false;
  /// Called after each batch of runs with the runs done and the pattern
  /// size being searched (for a progress line).
  std::function<void(int64_t runs, int losses)> progress;
};

/// A property a run broke, in the words of the run's summary.
struct Violation {
  std::string property;  ///< "common knowledge", "agreement", "collision", "app fault", "goal"
  std::string detail;
};

/// What a run broke: P3, the app's agreement, a collision, an app fault
/// (or invalid command or refused payload), and the goal when the scenario
/// declares one (`goal:`; a built-in app's own goal is not held against it).
std::vector<Violation> ViolationsOf(const metrics::Metrics& metrics, bool goal_declared);

/// One robot left out of one epoch by an activation search's pattern.
struct Inactivation {
  int64_t round = 0;   ///< the radio round the epoch starts in (the run with every robot active)
  uint16_t epoch = 0;  ///< the epoch's number (sync::ActivationConfig's)
  uint16_t robot = 0;
  auto operator<=>(const Inactivation&) const = default;
};

/// An epoch of an activation search's window: its number, the round it
/// starts in and its members, as the run with every robot active has them.
struct WindowEpoch {
  uint16_t epoch = 0;
  int64_t round = 0;
  std::vector<uint16_t> members;  ///< increasing
};

struct Counterexample {
  std::vector<world::LostBeacon> lost;  ///< sorted by round, sender, receiver
  /// Activation search: the robots left out (sorted), and the window's
  /// epochs they fall in (for WithInactivations).
  std::vector<Inactivation> inactive;
  std::vector<WindowEpoch> window_epochs;
  std::vector<Violation> violations;
  metrics::Metrics metrics;
  /// ASYNC search: the deviating cycles (sorted by epoch, then robot) and
  /// the bounds they were chosen under (for WithCycles).
  std::vector<sync::ScriptedCycle> cycles{};
  int max_delay_epochs = 0;
  double min_move_m = 0;
};

struct SearchResult {
  int64_t slots = 0;              ///< beacons a pattern may lose (round, sender, receiver), or robot-epochs it may leave out (ASYNC: may look in)
  /// Activation search: the schedules of up to max_inactive inactive
  /// robot-epochs the window holds (without the fairness bound; capped at
  /// INT64_MAX), the loss search's PatternCount. ASYNC: of up to
  /// max_deviations deviating cycles (AsyncScheduleCount).
  int64_t patterns_in_all = 0;
  /// Activation search: patterns of the sizes tried that are no schedule
  /// (an epoch with no active member, or unfair), not run and not in `runs`.
  int64_t not_schedules = 0;
  int64_t window_rounds = 0;      ///< radio rounds the losses fall in
  int64_t epochs_in_window = 0;   ///< epochs the loss-free run started in that window (< epochs: the run is shorter)
  int64_t runs = 0;               ///< patterns run, the loss-free one included, in search order up to the counterexample
  /// Runs whose metrics.json differ (the loss-free one included): how many
  /// of the patterns changed anything the metrics see (up to the
  /// counterexample, when one was found; the same for any --jobs).
  int64_t distinct_outcomes = 0;
  /// Of `runs`: patterns skipped without running (a shorter pattern, their
  /// losses up to some round, reached a state seen before), and runs stopped
  /// at a state seen before. The rest ran to their end.
  int64_t skipped = 0;
  int64_t stopped_early = 0;
  /// Distinct states seen (a state at one round's start counts once), and
  /// round starts run in all.
  int64_t distinct_states = 0;
  int64_t round_starts = 0;
  /// With check_pruning: the pruned patterns checked, and those whose end
  /// differed from the pattern they stood for (0 unless the fingerprint
  /// misses something).
  int64_t pruning_checked = 0;
  int64_t pruning_mismatches = 0;
  std::string first_mismatch;     ///< the first such pattern, described
  /// Every pattern of up to this many losses (inactive robot-epochs,
  /// deviating cycles) was run (-1: not even the loss-free one).
  int complete_losses = -1;
  bool stopped_by_time = false;   ///< the time limit ended the search
  double seconds = 0;             ///< wall time
  /// Set when the search could not start: the window holds more than
  /// kMaxSearchSlots slots, or (ASYNC) more than kMaxAsyncSearchLooks
  /// robot-epochs, or no delay bound was given (the message says how many
  /// and what to change).
  std::string error;
  /// The first pattern in search order that broke the run; none if no
  /// pattern within the budget did. A loss-free run that breaks is one, with
  /// no lost beacons.
  std::optional<Counterexample> counterexample;
};

/// The scenario with its channel replaced by a scripted one losing exactly
/// `lost` (its cuts and partitions kept): the run a pattern stands for.
scenario::Scenario WithLosses(const scenario::Scenario& base, std::span<const world::LostBeacon> lost);

/// The scenario under SSYNC with a scripted schedule leaving exactly
/// `inactive` out of `epochs` (each listed epoch activates its other
/// members; every other epoch, all): the run an activation pattern stands
/// for. Its channel is kept.
scenario::Scenario WithInactivations(const scenario::Scenario& base, std::span<const WindowEpoch> epochs,
                                     std::span<const Inactivation> inactive);

/// The scenario under ASYNC with a scripted schedule timing exactly
/// `cycles` (every other look a one-epoch uncut move), delays up to
/// `max_delay_epochs`, cuts at `min_move_m`: the run an ASYNC pattern
/// stands for. No cycle: FSYNC. Its channel is kept.
scenario::Scenario WithCycles(const scenario::Scenario& base, std::span<const sync::ScriptedCycle> cycles,
                              int max_delay_epochs, double min_move_m);

/// ASYNC: the cycles a look may get other than FSYNC's, in search order:
/// the shortest (start_delay + move_epochs) first, then the smaller delay,
/// then uncut before cut; cuts only when `cuts`.
std::vector<sync::AsyncCycle> AsyncChoices(int max_delay_epochs, bool cuts);

/// ASYNC: how many schedules of up to `most` deviating cycles the window's
/// `epochs` hold (each robot's looks follow its own cycles), capped at
/// INT64_MAX.
int64_t AsyncScheduleCount(const std::vector<WindowEpoch>& epochs, int max_delay_epochs, bool cuts, int most);

/// Runs the search. The options must be in range (the command checks them).
SearchResult Search(const scenario::Scenario& scenario, const SearchOptions& options);

/// How a counterexample's scenario file is written: the file that was
/// searched, and what the command line put in its place.
struct CounterexampleSource {
  std::string scenario_path;                 ///< the scenario file searched
  std::optional<std::string> app;            ///< an app given instead of the file's (as typed)
  std::optional<double> duration_s;          ///< a duration given instead of the file's
};

/// Writes `dir`/counterexample.yaml: the scenario file again (comments
/// dropped) with its channel scripted to lose exactly `found.lost` (cuts,
/// partitions and links kept), the resolved seed and the overrides written
/// in, and a library's path made absolute, so it runs from any folder. Then
/// runs that file (with `options`' app) into `dir`/replay and
/// `dir`/metrics.json, so the outputs are what `syrof run` of it gives.
/// Returns what went wrong (where: the file or folder), or nothing (a rerun
/// whose metrics differ from `found`'s is an error: the file would not
/// reproduce the pattern).
std::optional<Error> WriteCounterexample(const std::string& dir, const scenario::Scenario& resolved,
                                         const CounterexampleSource& source, const Counterexample& found,
                                         const SearchOptions& options);

/// How many patterns of 0 .. `losses` losses `slots` slots give, capped at
/// INT64_MAX.
int64_t PatternCount(int64_t slots, int losses);

}  // namespace syrof::lab::search
