// `syrof run SCENARIO.yaml`: runs a scenario in the simulated lab and writes
// DIR/metrics.json and DIR/replay.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

namespace syrof::cli {

struct RunOptions {
  std::string scenario_path;
  std::optional<std::string> app;
  std::optional<uint64_t> seed;
  std::optional<int> robots;
  std::optional<double> duration_s;
  std::string out_dir;        ///< default: out/<scenario name>
  bool no_replay = false;
  bool reproducible = false;  ///< wall_seconds written as 0, so identical runs give identical files
  bool quiet = false;         ///< no progress line, no summary
};

/// Declares the subcommand's arguments on `app`.
CLI::App* SetupRunCommand(CLI::App& app, RunOptions& options);

/// Runs it. Returns 0 on success, 2 on bad input (message on `err`), 1 on an
/// internal error. Progress goes to `err` when `err_is_terminal`.
int RunRunCommand(const RunOptions& options, std::ostream& out, std::ostream& err, bool err_is_terminal);

}  // namespace syrof::cli
