// `syrof swarm SCENARIO.yaml [--app builtin:NAME | --app lib.so] [--out DIR]`:
// runs a scenario as a DDS swarm, one syrof-robot process per robot and this
// process as the world, in wall-clock time (docs/dds.md), and writes
// DIR/metrics.json (runtime: dds) and DIR/replay.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

#include "syrof/lab/live/live_command.h"

namespace syrof::cli {

struct SwarmOptions {
  std::string scenario_path;
  std::optional<std::string> app;  ///< "builtin:NAME" or a library's path
  std::optional<uint64_t> seed;
  std::optional<int> robots;
  std::optional<double> duration_s;
  std::string out_dir;             ///< default: out/<scenario name>-dds
  std::string interface = "lo";
  std::optional<uint32_t> domain;  ///< default: SYROF_DDS_DOMAIN, else one per run
  bool no_replay = false;
  bool quiet = false;
  bool realtime = false;
  bool align_rounds = false;
  bool realtime_start = false;
  uint64_t stress_seed = 0;           ///< --stress SEED: seeded SIGSTOP bursts (docs/dds.md, "Stress")
  uint32_t stress_cpu_quota = 0;      ///< --stress-cpu-quota PERMILLE of one core for the robots
  double stress_rate = 4;             ///< --stress-rate: bursts a second
  double stress_late = 0.05;          ///< --stress-late: the fraction of beacons and readings delivered late
  lab::live::LiveCommandOptions live;  ///< the live page while the swarm runs
};

CLI::App* SetupSwarmCommand(CLI::App& app, SwarmOptions& options);

/// Runs it: 0 done, 2 bad input, 1 a failure (DDS, processes). SIGINT and
/// SIGTERM end the run early and cleanly (metrics of what ran are written).
int RunSwarmCommand(const SwarmOptions& options, std::ostream& out, std::ostream& err);

}  // namespace syrof::cli
