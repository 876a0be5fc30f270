// `syrof search SCENARIO.yaml --max-losses F [--epochs E] [--jobs N]
// [--time-limit S] [--app lib.so] --out DIR`: a search test
// (lab/search, docs/apps.md "Search tests"). Runs the scenario with every
// pattern of up to F lost beacons in its first E epochs, fewest losses and
// earliest first, and stops at the first pattern that breaks P3, the app's
// agreement, the no-collision rule, the app (a fault) or the scenario's
// declared goal. It then writes DIR/counterexample.yaml (the scenario with
// a scripted channel losing exactly those beacons), DIR/replay,
// DIR/metrics.json and DIR/replay.html, all from a rerun of that file, and
// prints the commands that reproduce it.
//
// `syrof search SCENARIO.yaml --activations ssync [--max-inactive K]
// [--fair-within F] [--epochs E] ...`: the same over SSYNC schedules
// (docs/activation.md, "The schedule search"): every schedule of the first
// E epochs, fewest inactive robot-epochs and earliest first; the
// counterexample is the scenario with a scripted schedule.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

namespace syrof::cli {

struct SearchOptions {
  std::string scenario_path;
  std::optional<std::string> app;  ///< "builtin:NAME" or a library's path
  std::optional<uint64_t> seed;
  std::optional<double> duration_s;
  int max_losses = -1;             ///< required, unless activations
  std::string activations;         ///< "ssync" or "async": search schedules instead of losses
  int max_inactive = -1;           ///< -1: every schedule
  int fair_within = 0;             ///< 0: no bound
  int max_deviations = -1;         ///< async: -1: every schedule
  int max_delay = 0;               ///< async: 0: the scenario's max_delay_epochs
  std::optional<double> min_move_m;  ///< async: none: the scenario's
  int epochs = 3;
  int jobs = 1;
  double time_limit_s = 0;         ///< 0: none
  std::string out_dir;             ///< default: out/<scenario name>-search
  bool quiet = false;              ///< no progress line
  bool no_prune = false;           ///< run every pattern to its end
  bool check_pruning = false;      ///< rerun each pruned pattern against the one it stood for
};

CLI::App* SetupSearchCommand(CLI::App& app, SearchOptions& options);

/// Returns 0 when no pattern within the budget broke the run, 1 when one did
/// (the counterexample is written) or on an internal error, 2 on bad input
/// (a bad scenario, a library that does not load, an output folder that
/// cannot be made, a window with more beacon slots than a search can try).
/// Progress goes to `err` when `err_is_terminal`.
int RunSearchCommand(const SearchOptions& options, std::ostream& out, std::ostream& err, bool err_is_terminal);

}  // namespace syrof::cli
