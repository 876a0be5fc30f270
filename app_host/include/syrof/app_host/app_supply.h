// The one place a run's apps are set up, for every runtime: `syrof run`,
// `syrof search`, the grader's runs and search tests, and the DDS robot
// process all ask AppsFor, so a robot gets the same app, parameters,
// inputs and limits (HostLimits::ForBudgets) whichever of them runs it.
//
// Usage:
//   AppRequest request;
//   request.log_directory = "out/run/robots";
//   request.check_first = true;
//   const AppsResult apps = AppsFor(scenario, request);
//   if (!apps.ok()) ... apps.error->ToString()
//   simulation_options.apps = apps.supply;
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/apps/app_supply.h"
#include "syrof/lab/base/error.h"
#include "syrof/lab/scenario/scenario.h"

namespace syrof::app_host {

/// What a run asks beyond the scenario's `app:` section.
struct AppRequest {
  /// Libraries in the scenario app's place: robot `id` runs
  /// libraries[id % size] (a mixed swarm). Empty: the scenario's app, a
  /// built-in one or its library.
  std::vector<std::string> libraries;
  /// How the outputs name `libraries`, one each (the grader's paths inside
  /// its output folder); joined with " + " into AppSupply::source. Empty:
  /// the libraries' paths.
  std::vector<std::string> shown_libraries;
  /// A library's CPU time and wall time per callback instead of the
  /// scenario's (`syrof run --cpu-budget-ms`, `--wall-cap-ms`); refused for
  /// a built-in app.
  std::optional<uint32_t> cpu_budget_ms;
  std::optional<uint32_t> wall_cap_ms;
  /// Where each robot's <id>.log goes; empty: the output is discarded.
  std::string log_directory;
  /// Load each library once in a sandboxed host (CheckLibrary) and refuse
  /// one that fails, before any robot starts. Also fills SandboxNotes.
  bool check_first = false;
  /// Load each library once in a held host and give each robot of each
  /// run a fresh copy of it (LoadOnce, the fork server): for a search or
  /// anything else that runs the library many times. The same results as
  /// a fresh host per robot; the first host starts from the caller's
  /// thread, which must outlive the apps.
  bool load_once = false;
};

/// A run's apps, or what is wrong with the request.
struct AppsResult {
  lab::apps::AppSupply supply;     ///< when ok: a factory always, source and sandbox for libraries
  std::vector<HostOptions> hosts;  ///< how each library is hosted (as `libraries`); empty for a built-in app
  /// What is wrong, naming the option or the file: a budget for a built-in
  /// app, a wall cap below the CPU budget, a library CheckLibrary refused.
  std::optional<lab::Error> error;

  bool ok() const { return !error.has_value(); }
};

/// The apps of a run of `scenario` (resolved and validated by the loader).
/// A built-in app: a factory making it (apps::MakeBuiltinApp), no source,
/// no sandbox. Libraries: each robot's app in its own sandboxed host
/// (MakeHostedApp) with the scenario's params and the robot's inputs,
/// limits HostLimits::ForBudgets(the request's budgets over the
/// scenario's), the source as shown, the sandbox as SandboxNotes() says
/// once the checks (if any) ran.
AppsResult AppsFor(const lab::scenario::Scenario& scenario, const AppRequest& request);

}  // namespace syrof::app_host
