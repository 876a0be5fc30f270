// The world of a DDS swarm (docs/dds.md, "Running a swarm on one machine"):
// one syrof-robot process per scenario robot, and this process as the world.
//
// The world owns what the lab's engine owns, in wall-clock time:
//   - bodies (lab/world's World) and each robot's sensors (lab/sensors'
//     SensorBank), whose readings go out as Imu_/Flow_/Uwb_ samples;
//   - the robots' Drive_ commands, applied to their bodies;
//   - the scenario's faults as real ones: a crash is SIGKILL, a pause
//     SIGSTOP and later SIGCONT, a join a process started late;
//   - metrics through lab/metrics' Collector, fed from the robots' Report_
//     samples (report_codec.h), so P3 is checked exactly as in the lab, and a
//     replay the viewer reads (lab/replay).
// Rounds follow a grid from the start time the world publishes on
// rt/syrof/control (CLOCK_MONOTONIC: one host).
//
// Processes: robots are started with fork + exec in a process group of
// their own, die with the world (PR_SET_PDEATHSIG) and are stopped by
// Control_ then SIGKILL of the group and reaped with wait4 (whose rusage is
// each robot's CPU time). No robot outlives RunSwarm.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/stress.h"

namespace syrof::sim_dds {

struct SwarmOptions {
  std::string scenario_path;
  lab::scenario::Overrides overrides;
  std::string out_dir;                   ///< metrics.json and replay go here (created)
  bool replay = true;
  /// Readers of the rounds as the world records them (the live page,
  /// lab/live): each gets what the replay gets, with or without a replay
  /// (lab::sim::RoundRecorder::AddSink). Each outlives RunSwarm.
  std::vector<lab::replay::RoundSink*> sinks;
  /// The robot binary; empty: $SYROF_ROBOT_BINARY, else syrof-robot next to
  /// this executable.
  std::string robot_binary;
  std::string interface = "lo";
  /// RobotProcessOptions::realtime for every robot; the world's own loop
  /// (faults, physics, sensors) and its network threads at SCHED_FIFO above
  /// them, so that a crash or a join falls on the round it is due in.
  bool realtime = false;
  bool align_rounds = false;  ///< RobotProcessOptions::align_rounds for every robot
  bool realtime_start = false;  ///< RobotProcessOptions::realtime_start for every robot
  /// Where each robot runs, by robot id (missing or empty entries: beside
  /// the world). `netns_path` is a network namespace (/var/run/netns/NAME)
  /// the robot's process joins before exec (setns; needs CAP_SYS_ADMIN);
  /// `interface` its DDS interface there. How one machine stands in for
  /// several hosts (two namespaces joined by a veth pair).
  struct RobotNetwork {
    std::string netns_path;
    std::string interface;
  };
  std::vector<RobotNetwork> robot_networks;
  /// RobotProcessOptions::clock_offset_us by robot id (missing entries: 0):
  /// hosts whose clocks disagree, on one machine.
  std::vector<int64_t> robot_clock_offsets_us;
  std::optional<uint32_t> domain_id;     ///< unset: SYROF_DDS_DOMAIN or one derived from the run id
  double discovery_timeout_s = 30;       ///< robots must report attached within this
  /// Set (by a signal handler) to end the run early and cleanly.
  const std::atomic<bool>* stop = nullptr;
  /// Called about once a second of run time.
  std::function<void(double run_seconds)> progress;
  /// Seeded stress (lab/sim/stress.h, docs/dds.md "Stress"): SIGSTOP bursts
  /// of robots and the world, beacons and readings delivered late, a CPU
  /// quota. Off unless stress.seed is set.
  lab::sim::StressOptions stress;
};

struct SwarmResult {
  int exit_code = 0;            ///< 0 done, 1 failed inside, 2 bad input (error says)
  std::optional<lab::Error> error;  ///< set with a non-zero exit_code
  lab::metrics::Metrics metrics;  ///< runtime "dds", with the dds object
  std::string metrics_json;       ///< ToJson(metrics): what metrics.json holds
  double delivery_ratio = 0;
  /// Round-start skew (metrics.round_start_skew, lab::metrics::SkewStats):
  /// one sample per round, its spread (latest minus earliest) of the round
  /// task activations of the robots that ran it.
  lab::metrics::SkewStats skew;
  std::vector<double> cpu_seconds;  ///< per robot process (0 for one never started)
  std::vector<int> robot_pids;      ///< every robot process started (for tests: none may be left)
  /// Per robot: its exit code, or minus the signal that ended it (-9: a
  /// crash fault's SIGKILL, or one that did not stop in time); unset for
  /// a robot never started.
  std::vector<std::optional<int>> robot_exits;
  bool stopped_early = false;
  uint64_t stress_seed = 0;  ///< the stress's seed (0: none): rerun with it
  int64_t stalls = 0;        ///< SIGSTOP bursts applied (robots and world)
};

/// Runs the scenario as a DDS swarm. Blocks for about its duration.
SwarmResult RunSwarm(const SwarmOptions& options, std::ostream& log);

/// syrof-robot's path when SwarmOptions::robot_binary is empty.
std::string DefaultRobotBinary();

}  // namespace syrof::sim_dds
