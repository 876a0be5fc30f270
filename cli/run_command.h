// `syrof run SCENARIO.yaml [--app builtin:NAME | --app path/to/libmyapp.so]`:
// runs a scenario in the simulated lab and writes DIR/metrics.json and
// DIR/replay (and, with --html, DIR/replay.html); with a student's library also DIR/robots/<id>.log, each
// robot's app host's output. `--realtime` paces the run to the wall clock;
// `--live` (which implies it) serves the live page while it runs.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

#include "syrof/lab/apps/app_supply.h"
#include "syrof/lab/live/live_command.h"

namespace syrof::cli {

struct RunOptions {
  std::string scenario_path;
  std::optional<std::string> app;  ///< "builtin:NAME" or a library's path (lab::scenario::IsLibraryPath)
  std::optional<uint32_t> cpu_budget_ms;  ///< a library's CPU time per callback instead of the scenario's
  std::optional<uint32_t> wall_cap_ms;    ///< a library's wall time per callback instead of the scenario's
  std::optional<uint64_t> seed;
  std::optional<int> robots;
  std::optional<double> duration_s;
  std::string out_dir;        ///< default: out/<scenario name>
  int threads = 1;            ///< threads stepping robots (lab::sim::SimulationOptions::threads)
  bool no_replay = false;
  bool html = false;          ///< also write OUT/replay.html, the replay's page (syrof view)
  bool reproducible = false;  ///< wall_seconds written as 0, so identical runs give identical files
  bool quiet = false;         ///< no progress line, no summary
  bool strict = false;        ///< exit 3 when the app faulted, returned an invalid command or had a payload refused
  /// Paces the lab's virtual time to the wall clock (a radio round of world
  /// time takes one of the host's); every output is the same bytes as
  /// without it.
  bool realtime = false;
  lab::live::LiveCommandOptions live;    ///< the live page (implies `realtime`)
  /// Not a command-line option: with a factory, the robots' apps instead
  /// of the scenario's (tests), used as given (no budgets, no library
  /// check). `syrof` itself never sets it: its apps come from
  /// app_host::AppsFor.
  lab::apps::AppSupply apps;
};

/// Declares the subcommand's arguments on `app`.
CLI::App* SetupRunCommand(CLI::App& app, RunOptions& options);

/// Runs it. Returns 0 on success, 2 on bad input (message on `err`: a bad
/// scenario, a library that is missing, has no syrof_app_entry, was built
/// for another ABI or does not load, or budgets for a built-in app), 1 on an
/// internal error, 3 with `strict` when the app misbehaved (a fault, an
/// invalid command or a refused payload; metrics.json and the replay are
/// written first). Progress goes to `err` when `err_is_terminal`.
int RunRunCommand(const RunOptions& options, std::ostream& out, std::ostream& err, bool err_is_terminal);

}  // namespace syrof::cli
