// `syrof apps`: the built-in apps and their parameters.
#pragma once

#include <ostream>

#include <CLI/CLI.hpp>

namespace syrof::cli {

/// `syrof apps` takes no arguments today; the struct keeps its shape the same
/// as the other subcommands'.
struct AppsOptions {};

/// Declares the subcommand on `app`.
CLI::App* SetupAppsCommand(CLI::App& app, AppsOptions& options);

/// Prints every built-in app with its parameters (default, range, meaning),
/// then how to run one's own library. Returns 0.
int RunAppsCommand(const AppsOptions& options, std::ostream& out);

}  // namespace syrof::cli
