// What every runtime records of its run, once (docs/architecture.md, "One
// world, three runtimes"): at each radio round's end the robots' entries to
// the metrics collector, the goal checks' samples and the replay's round;
// at the end the run's facts with the goal, and the metrics. The lab engine,
// the DDS world of `syrof swarm` and the emulated firmware swarm's host each
// record through one RoundRecorder; each builds only what comes from its
// own sources (the lab's ports, the DDS robots' reports, the qemu consoles):
// every robot's RobotRound and RobotFrame, the running members' round
// boundaries, the round's events and the maps robots started epochs with.
//
// The rules, one place for all runtimes:
//   - a round goes to the collector as its phases (OnRoundPhases), then its
//     robots (OnRoundEnd);
//   - the goal checks sample the running robots' true poses at every
//     round's end, and once more at a round's end when some robot started,
//     in that round, an epoch newer than every epoch before (wrapping epoch
//     order, sync::EpochDifference): the newest such epoch;
//   - the replay gets the round's frames, its events in the order given
//     (the order they happened), after a BEACON_LOST for each beacon a
//     scripted channel lost in the round, and its maps in robot order;
//   - the goal is the scenario's declared checks when it has any (judged at
//     the end over the robots running then), else the built-in app's own
//     goal over the final poses (run_parts.h: DeclaredGoal, BuiltinGoal).
//
// Usage, per run:
//   RoundRecorder recorder(scenario, CollectorConfigFor(scenario));
//   WorldPlayer player(scenario, world, recorder.collector());
//   recorder.AddSink(&live);                          // any readers of the rounds
//   recorder.OpenReplay(file);                        // when there is a replay
//   ... recorder.OnEpochStart(...) as robots start epochs,
//   ... recorder.collector().OnMembership(...) and the other events,
//   ... recorder.RecordRound(round) at every round's end;
//   recorder.FinishReplay();
//   metrics::Metrics metrics = recorder.Finish(recorder.Facts(end, player, world));
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <span>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/goals/goals.h"
#include "syrof/lab/metrics/agreement.h"
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/lab/replay/writer.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/world_player.h"
#include "syrof/lab/world/world.h"
#include "syrof/sync/ldmap.h"
#include "syrof/base/state_digest.h"

namespace syrof::lab::sim {

/// The collector's configuration for a run of `scenario`: its robots, its
/// radio round, its silence rounds (F).
metrics::CollectorConfig CollectorConfigFor(const scenario::Scenario& scenario);

/// One radio round as a runtime saw it, handed to RoundRecorder::RecordRound.
/// The spans are read during the call only.
struct RecordedRound {
  int64_t round = 0;    ///< the radio round's index; increases from round to round
  int64_t time_ns = 0;  ///< the round's end on world time, ns: the replay's time and the goal samples'
  std::span<const metrics::RobotRound> robots;   ///< every robot, running or not, in id order
  std::span<const int64_t> phase_boundaries_ns;  ///< each running member's latest round boundary, world time
  std::span<const replay::RobotFrame> frames;    ///< every robot, in id order
  std::span<const replay::Event> events;         ///< the round's events, in the order they happened
  /// The robots that started an epoch in the round, one map each, in any
  /// order: RecordRound sorts them by robot (stable).
  std::span<replay::RobotMap> maps;
  /// The running robots' true poses at `time_ns`, for the goal checks;
  /// called only when the scenario declares checks.
  std::function<std::vector<goals::RobotPose>()> running_poses;
};

/// What only the runtime knows of its run's end.
struct RunEnd {
  double sim_seconds = 0;   ///< world time at the end
  double wall_seconds = 0;  ///< host time the run took
  int64_t radio_rounds = 0;
};

/// Events gathered from several sources (the world's, the robots' reports or
/// console lines) in the order they happened: by time, stable among equal times.
void OrderByTime(std::span<replay::Event> events);

class RoundRecorder {
 public:
  /// `scenario` outlives the recorder; `config` is the collector's
  /// (CollectorConfigFor(scenario), or the firmware's own round).
  RoundRecorder(const scenario::Scenario& scenario, const metrics::CollectorConfig& config);
  RoundRecorder(const RoundRecorder&) = delete;
  RoundRecorder& operator=(const RoundRecorder&) = delete;

  /// The run's metrics collector, for what happens between round ends
  /// (membership, contacts, app faults, safety) and for the WorldPlayer.
  metrics::Collector& collector() { return collector_; }

  /// Names the app the runtime runs in place of the scenario's (a student's
  /// library given to the grader or `--app`; SimulationOptions::apps.source):
  /// the replay header's app_name and metrics' goal.app then say `name`, not
  /// the scenario's `app:`. Empty: the scenario's app. Before OpenReplay and
  /// AddSink.
  void NameApp(std::string name);
  /// The app the run names: NameApp's, else the scenario's app.name.
  const std::string& app_name() const { return app_name_.empty() ? scenario_.app.name : app_name_; }

  /// Starts the replay: its header (ReplayHeader(scenario), app_name()) to `out` now,
  /// a round at every RecordRound. `out` outlives the recorder. At most once.
  void OpenReplay(std::ostream& out);
  /// Adds a reader of the rounds (the live page, a bridge): it gets the
  /// header (as OpenReplay's) now, every RecordRound's round as the
  /// replay gets it (maps sorted by robot) and FinishReplay's end, whether
  /// or not a replay is written. `sink` outlives the recorder or its
  /// FinishReplay; the calls come on the recording thread.
  void AddSink(replay::RoundSink* sink);
  /// Whether rounds are recorded, to a replay or a sink (a runtime builds
  /// maps only then).
  bool replaying() const { return replay_.has_value() || !sinks_.empty(); }

  /// `robot` started epoch `ldmap.epoch` with `ldmap` at world time
  /// `time_ns`, in `round`: to the collector, and a goal sample at the
  /// round's end when it is the newest epoch yet.
  void OnEpochStart(uint16_t robot, int64_t round, int64_t time_ns, const sync::LDMap& ldmap);

  /// The end of a round: the collector, the goal checks' samples and the
  /// replay's round (see the rules above).
  void RecordRound(const RecordedRound& round);

  /// A runtime that sees the app's returns (the lab, the DDS robots'
  /// reports; not the firmware's consoles) hands each one here: metrics'
  /// `agreement` is then measured, and null for a runtime that never does.
  void OnAppState(uint16_t robot, int64_t round, metrics::AgreementTracker::Call call, uint16_t epoch,
                  bool cooperative, uint64_t map_fingerprint, uint8_t state);
  /// Says that this runtime measures agreement, before any OnAppState (a
  /// run whose apps never returned still reports 0 COOPERATIVE epochs).
  void MeasureAgreement() { agreement_.emplace(); }

  /// Ends the replay (its end marker) and tells the sinks the run ended
  /// (`complete`: it ran to its end). At most once.
  void FinishReplay(bool complete = true);
  /// Why the replay writer stopped (a value the format cannot hold, a
  /// failing stream); unset when the replay was written whole or not at all.
  std::optional<Error> replay_error() const;

  /// What the property checks still hold (the collector's open epochs, the
  /// agreement's, the goal checks') into `digest` (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest) const;
  /// Properties broken so far (Collector::PropertyBreaks, and the app's
  /// agreement when measured).
  int64_t PropertyBreaks() const;

  /// metrics.json's run facts: the scenario's (ScenarioFacts, with `world`'s
  /// smallest separation), `end`'s times and rounds, and the goal: the
  /// declared checks, judged at `end.sim_seconds` over `player`'s running
  /// robots, or the built-in app's goal from `player`'s final poses. Call
  /// once, after the last RecordRound. A runtime that knows more of the app
  /// (the lab: its own name, its source, its sandbox) sets that before Finish.
  metrics::RunFacts Facts(const RunEnd& end, const WorldPlayer& player, const world::World& world);

  /// The run's metrics with `facts` and, when measured, the app's
  /// agreement; the runtime adds its own parts (`runtime`, the DDS figures).
  metrics::Metrics Finish(const metrics::RunFacts& facts) const;

 private:
  /// The round's events with, first, a BEACON_LOST for each beacon a
  /// scripted channel lists for this round between two running robots (at
  /// most kMostLostBeaconEvents a round), so a counterexample's page shows
  /// them; `round.events` itself without a scripted loss this round.
  std::span<const replay::Event> WithLostBeacons(const RecordedRound& round);
  static constexpr size_t kMostLostBeaconEvents = 4096;

  /// The replay's header: ReplayHeader(scenario_) naming app_name().
  replay::Header Header() const;

  const scenario::Scenario& scenario_;
  std::string app_name_;  // NameApp's; empty: the scenario's
  metrics::Collector collector_;
  goals::GoalMonitor goal_monitor_;
  std::optional<replay::Writer> replay_;
  std::vector<replay::RoundSink*> sinks_;
  bool finished_ = false;
  std::optional<metrics::AgreementTracker> agreement_;
  bool any_epoch_ = false;
  uint16_t newest_epoch_ = 0;
  std::optional<uint16_t> epoch_sample_;
  std::vector<world::LostBeacon> scripted_lost_;  // a scripted channel's lost beacons, sorted
  size_t next_lost_ = 0;                          // the first of them in a round not recorded yet
  std::vector<replay::Event> round_events_;  // a newer epoch started this round: the goal samples the poses
};

}  // namespace syrof::lab::sim
