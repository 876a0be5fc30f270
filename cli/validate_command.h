// `syrof validate SCENARIO.yaml`: loads and checks a scenario and prints what
// it resolved to.
#pragma once

#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

namespace syrof::cli {

struct ValidateOptions {
  std::string scenario_path;
};

/// Declares the subcommand's arguments on `app`.
CLI::App* SetupValidateCommand(CLI::App& app, ValidateOptions& options);

/// Runs it. Returns 0 when the scenario is valid, 2 when it is not (the
/// message, with file, line and column, on `err`). A library app is loaded
/// once in the sandboxed app host, so a library `syrof run` would refuse
/// (no syrof_app_entry, another ABI version, fails to load) is refused here.
int RunValidateCommand(const ValidateOptions& options, std::ostream& out, std::ostream& err);

}  // namespace syrof::cli
