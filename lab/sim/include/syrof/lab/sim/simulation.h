// The simulated lab: a swarm of robots, each running the real robot software
// (core/runtime: estimator, synchronizer, app, motion controller) on its own
// simulation port, all on one virtual clock, in a world with bodies, walls,
// UWB anchors and a lossy radio.
//
// One instant of virtual time runs in this order (task priorities):
//   9 faults due now (crash, pause, resume, join)
//   8 physics: bodies move under their drive commands; contacts recorded
//   6 the simulated hardware, robot by robot: drive command to the body,
//     sensor readings out (lab code: one world task, not one per robot)
//   5, 4 each robot's state and Kalman tasks
//   3 radio: the beacons sent in the previous round reach their receivers
//   2 each robot's round task (synchronizer step, app callbacks, broadcast)
//   1 each robot's motion task (controller -> drive command)
//   0 the recorder: metrics and the replay frame of the round
// Ties between robots go by robot id. Nothing depends on wall-clock time or
// on memory addresses, so the same scenario and seed give the same bytes.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/lab/apps/app_supply.h"
#include "syrof/lab/base/error.h"
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/world/world.h"
#include "syrof/runtime/robot.h"

namespace syrof::lab::sim {

/// The most threads SimulationOptions::threads (`syrof run --threads`) takes.
inline constexpr int kMaxThreads = 64;

struct SimulationOptions {
  std::ostream* replay = nullptr;    ///< where to write the replay (docs/replay.md); none if null
  /// Readers of the rounds as they are recorded (the live page, lab/live):
  /// each gets what the replay gets (RoundRecorder::AddSink), with or
  /// without a replay. Each outlives the run's Finish.
  std::vector<replay::RoundSink*> sinks;
  /// Called about every `progress_period_s` of simulated time (and at the end).
  std::function<void(double sim_seconds)> progress;
  double progress_period_s = 1.0;
  /// Where the robots' apps come from and how the outputs name them
  /// (app_host::AppsFor for a scenario's app or a student's library; tests
  /// supply their own). Default: the scenario's built-in app from lab/apps.
  lab::apps::AppSupply apps;
  /// For tests and tools: adjusts each robot's start-up config after the
  /// scenario's (RobotConfigFor), before the robot is built. Empty: none.
  std::function<void(runtime::RobotConfig&)> configure_robot;
  /// Threads that step robots (`syrof run --threads`, docs/lab.md
  /// "Threads"): the robots' tasks due at one instant with one priority run
  /// side by side on this many threads (a pool made once, robots in
  /// contiguous chunks that the threads take as they go), and every output
  /// is byte-identical to a run with 1.
  /// 1 .. kMaxThreads (SYROF_CHECK); capped at the robot count; with clocks (scenario `clocks:`) the
  /// run is serial whatever this says. With more than 1, the apps that
  /// `apps.factory` makes are called from several threads at once, each app
  /// from one thread at a time: an app must touch only its own state.
  int threads = 1;
  /// Keeps what Simulation::StateDigest needs beyond the run's own state:
  /// each app's call history (lab/search turns it on). Off, StateDigest
  /// must not be called, and the run spares hashing every call's map
  /// (about 2% of a 100-robot run's instructions).
  bool state_digests = false;
};

/// What a finished run reports.
struct RunReport {
  metrics::Metrics metrics;
  std::string metrics_json;  ///< ToJson(metrics)
  /// Why the replay writer stopped (a value the format cannot hold, a
  /// failing stream); empty when the replay was written whole or not at all.
  /// The file then ends early and reads as truncated, so a caller must not
  /// present it as the run's record.
  std::optional<Error> replay_error;
};

class Simulation {
 public:
  /// Builds the world, the robots and their software from a resolved,
  /// validated scenario. Everything is allocated here.
  explicit Simulation(const scenario::Scenario& scenario, const SimulationOptions& options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// Runs until `end_s` of simulated time (at most the scenario's duration).
  void RunUntil(double end_s);
  /// Runs through the instant radio round `round` starts (its beacons of
  /// round - 1 delivered, its own broadcast), at most to the scenario's end.
  void RunThroughRoundStart(int64_t round);

  /// Runs the whole scenario and reports. `wall_seconds` is recorded as given
  /// (the caller measures it; pass 0 for byte-identical metrics).
  RunReport Finish(double wall_seconds);

  /// Simulated seconds so far.
  double now_s() const;

  /// A fingerprint of everything the rest of the run depends on, between
  /// RunUntil calls (lab/search: two runs of one scenario whose fingerprints
  /// are equal at one instant go on alike, and break the same properties
  /// from then on). Its parts: the event queue, the world, the beacons in
  /// the air, every robot's hardware, software and app call history, the
  /// faults' lifecycle, and what the property checks still hold; not the
  /// metrics' counts. Runs with clocks (`clocks:`) have none: nullopt.
  /// Needs SimulationOptions::state_digests (SYROF_CHECK).
  std::optional<base::StateDigest::Value> StateDigest() const;
  /// How many times the run broke a property so far (P3, the app's
  /// agreement, a collision, an app fault, an invalid command, a refused
  /// payload); the goal is judged at the end.
  int64_t PropertyBreaks() const;

  // For tests and tools.
  size_t robot_count() const;
  const runtime::Robot& robot(uint16_t id) const;
  const scenario::Scenario& scenario() const;
  const world::World& world() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

/// Runs `scenario` from start to end: Simulation + RunUntil(duration) + Finish.
RunReport Run(const scenario::Scenario& scenario, const SimulationOptions& options, double wall_seconds = 0);

}  // namespace syrof::lab::sim
