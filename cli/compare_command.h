// `syrof compare RUN_A RUN_B [--payloads] [--pose-tolerance-m X]`: do two
// runs agree on who started which epoch, in which mode, with which members
// (and, with the options, on the apps' payloads in those maps and on where
// the robots were)? Each run is an output folder (its
// `replay`) or a replay file; the comparison itself is lab/replay's
// (comparison.h, docs/replay.md "Comparing two runs").
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

namespace syrof::cli {

struct CompareOptions {
  std::string run_a;                       ///< a folder holding `replay`, or a replay file
  std::string run_b;
  std::optional<double> pose_tolerance_m;  ///< also compare true positions, allowing this many metres
  bool payloads = false;                   ///< also compare the members' payloads in the maps
};

/// Declares the subcommand on `app`.
CLI::App* SetupCompareCommand(CLI::App& app, CompareOptions& options);

/// Compares the runs and prints the outcome on `out`. Returns 0 when they
/// agree (a one-line summary, plus notes such as a run being longer); 1 when
/// they differ: the first epoch that differs as a table of both sides, the
/// first round whose positions differ by more than the tolerance, or robot
/// sets that differ; 2 when a run cannot be read (missing, not a replay,
/// damaged or cut short; `err` names the file and what is wrong) or on an
/// internal error.
int RunCompareCommand(const CompareOptions& options, std::ostream& out, std::ostream& err);

/// The replay file of a command-line argument: ARGUMENT/replay for a folder,
/// else ARGUMENT itself.
std::string ReplayPathOf(const std::string& argument);

}  // namespace syrof::cli
