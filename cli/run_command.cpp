#include "run_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "syrof/app_host/app_supply.h"
#include "syrof/lab/live/live_server.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/lab/view/view.h"
#include "run_summary.h"
#include "usage.h"
#include "view_command.h"

namespace syrof::cli {
namespace {

namespace scenario = lab::scenario;
namespace sim = lab::sim;

scenario::Overrides OverridesOf(const RunOptions& options) {
  scenario::Overrides overrides;
  overrides.seed = options.seed;
  overrides.robots = options.robots;
  overrides.duration_s = options.duration_s;
  overrides.app = options.app;
  return overrides;
}

// The run's apps: the test's own when RunOptions::apps has a factory, else
// the scenario's (or --app's) through the app supply. A library is loaded
// once in a sandboxed host before any output exists, so a library that
// cannot run is refused like a bad scenario.
app_host::AppsResult AppsOf(const scenario::Scenario& scenario, const RunOptions& options,
                            const std::filesystem::path& dir) {
  if (options.apps.factory) return app_host::AppsResult{options.apps, {}, std::nullopt};
  app_host::AppRequest request;
  request.cpu_budget_ms = options.cpu_budget_ms;
  request.wall_cap_ms = options.wall_cap_ms;
  request.log_directory = (dir / "robots").string();
  request.check_first = true;
  return app_host::AppsFor(scenario, request);
}

}  // namespace

CLI::App* SetupRunCommand(CLI::App& app, RunOptions& options) {
  CLI::App* run = app.add_subcommand("run", "Run a scenario in the simulated lab; write metrics.json and a replay");
  run->add_option("scenario", options.scenario_path, "Scenario file (YAML, docs/scenarios.md)")->required();
  run->add_option("--app", options.app,
                  "App to run instead of the scenario's: builtin:NAME, or your library's path (build/libmyapp.so)");
  run->add_option("--seed", options.seed, "Seed instead of the scenario's");
  run->add_option("--robots", options.robots, "Robot count instead of the scenario's")->check(RobotCountValidator());
  run->add_option("--duration", options.duration_s, "Simulated seconds instead of the scenario's")
      ->check(DurationValidator());
  run->add_option("--out", options.out_dir, "Output folder (default: out/<scenario name>)");
  run->add_option("--threads", options.threads,
                  "Threads stepping robots side by side (default 1); the outputs are the same bytes as with 1. "
                  "Meant for hundreds of robots on idle cores; serial with clocks (docs/lab.md, Threads)")
      ->check(ThreadsValidator());
  run->add_option("--cpu-budget-ms", options.cpu_budget_ms,
                  "A library app's CPU time per callback, ms, instead of the scenario's (default 100)")
      ->check(CLI::Range(uint32_t{1}, scenario::kMaxCpuBudgetMs));
  run->add_option("--wall-cap-ms", options.wall_cap_ms,
                  "A library app's wall time per callback, ms, instead of the scenario's (default 2000)")
      ->check(CLI::Range(uint32_t{1}, scenario::kMaxWallCapMs));
  CLI::Option* no_replay = run->add_flag("--no-replay", options.no_replay, "Do not write the replay");
  run->add_flag("--html", options.html, "Also write OUT/replay.html, the replay's page (as `syrof view` does)")
      ->excludes(no_replay);
  run->add_flag("--reproducible", options.reproducible,
                "Write wall_seconds as 0 so identical runs give byte-identical outputs");
  run->add_flag("--quiet", options.quiet, "No progress line and no summary");
  run->add_flag("--realtime", options.realtime,
                "Pace the run to the wall clock (a simulated second takes a second; --live implies it); the outputs are the same bytes");
  lab::live::SetupLiveOptions(*run, options.live);
  run->add_flag("--strict", options.strict,
                "Exit with status 3 if the app faulted, returned an invalid command or had a payload refused");
  return run;
}

int RunRunCommand(const RunOptions& options, std::ostream& out, std::ostream& err, bool err_is_terminal) {
  const std::string scenario_file = ScenarioArgument(options.scenario_path, "run", err, options.quiet);
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(scenario_file, OverridesOf(options));
  if (!loaded.ok()) {
    fmt::print(err, "syrof run: {}\n", loaded.error->ToString());
    return 2;
  }
  const scenario::Scenario& scenario = *loaded.scenario;
  const std::filesystem::path dir =
      options.out_dir.empty() ? std::filesystem::path("out") / scenario.name : std::filesystem::path(options.out_dir);
  const app_host::AppsResult apps = AppsOf(scenario, options, dir);
  if (!apps.ok()) {
    fmt::print(err, "syrof run: {}\n", apps.error->ToString());
    return 2;
  }
  const bool library = !apps.hosts.empty();
  if (library) {
    // Logs of an earlier run with more robots would pass for this run's.
    std::error_code ignored;
    std::filesystem::remove_all(dir / "robots", ignored);
  }
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    fmt::print(err, "syrof run: cannot create output folder {}: {}\n", dir.string(), error.message());
    return 2;
  }
  std::ofstream replay_file;
  if (!options.no_replay) {
    replay_file.open(dir / "replay", std::ios::binary | std::ios::trunc);
    if (!replay_file) {
      fmt::print(err, "syrof run: cannot write {}\n", (dir / "replay").string());
      return 2;
    }
  }
  if (!options.quiet) {
    fmt::print(out, "syrof run: {} ({}), {} robots, seed {}, {:.1f} s\n", scenario.name, scenario.app.name,
               scenario.robots.size(), scenario.seed, scenario.timing.duration_s);
    if (library) {
      fmt::print(out, "  each robot's app in its own sandboxed process: CPU budget {} ms, wall cap {} ms per callback\n",
                 apps.hosts.front().limits.cpu_budget_ms, apps.hosts.front().limits.wall_cap_ms);
    }
    if (library && apps.supply.sandbox) {
      for (const std::string& note : *apps.supply.sandbox) fmt::print(out, "  sandbox: {}\n", note);
    }
  }

  const auto started = std::chrono::steady_clock::now();
  auto elapsed_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  sim::SimulationOptions sim_options;
  sim_options.replay = options.no_replay ? nullptr : &replay_file;
  sim_options.apps = apps.supply;
  sim_options.threads = options.threads;
  if (!options.quiet && err_is_terminal) {
    const double duration_s = scenario.timing.duration_s;
    sim_options.progress = [&err, &elapsed_s, duration_s](double sim_seconds) {
      const double wall = elapsed_s();
      fmt::print(err, "\r  t = {:6.1f} / {:.1f} s   {:6.1f}x real time ", sim_seconds, duration_s,
                 wall > 0 ? sim_seconds / wall : 0.0);
      err.flush();
    };
  }
  // The live page is a sink of the rounds; with it the run is paced, so
  // that a browser watches it as it happens.
  lab::live::LiveResult started_live = lab::live::StartLive(options.live, scenario.name, out, sim_options.sinks);
  if (!started_live.ok()) {
    fmt::print(err, "syrof run: {}\n", started_live.error->ToString());
    return 2;
  }
  const std::unique_ptr<lab::live::LiveServer> live = std::move(started_live.server);
  sim::Simulation simulation(scenario, sim_options);
  if (options.realtime || live) {
    // One radio round at a time, each ending no earlier than its world time
    // after the start: the engine runs the same events in the same order,
    // only later (tests/cli: a paced run's files equal an unpaced run's).
    const double step_s = scenario.timing.radio_round_s;
    for (int64_t round = 1;; ++round) {
      const double until_s = std::min(scenario.timing.duration_s, static_cast<double>(round) * step_s);
      simulation.RunUntil(until_s);
      std::this_thread::sleep_until(started + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                  std::chrono::duration<double>(until_s)));
      if (until_s >= scenario.timing.duration_s) break;
    }
  }
  simulation.RunUntil(scenario.timing.duration_s);
  const double wall_seconds = options.reproducible ? 0.0 : elapsed_s();
  const sim::RunReport report = simulation.Finish(wall_seconds);
  if (sim_options.progress) fmt::print(err, "\n");

  std::ofstream metrics_file(dir / "metrics.json", std::ios::binary | std::ios::trunc);
  metrics_file << report.metrics_json;
  if (report.replay_error) {
    // The file ends where the writer stopped: it is not the run's record.
    fmt::print(err, "syrof run: the replay {} is incomplete: {}\n", (dir / "replay").string(),
               report.replay_error->ToString());
    return 1;
  }
  if (!metrics_file || (!options.no_replay && !replay_file)) {
    fmt::print(err, "syrof run: writing the outputs in {} failed\n", dir.string());
    return 1;
  }
  replay_file.close();
  if (options.html && !options.no_replay) {
    lab::view::PageOptions page_options;
    page_options.metrics = report.metrics;
    page_options.scenario = &scenario;
    if (const std::optional<lab::Error> page_problem =
            WritePage((dir / "replay").string(), (dir / "replay.html").string(), page_options)) {
      fmt::print(err, "syrof run: writing {} failed: {}\n", (dir / "replay.html").string(), page_problem->ToString());
      return 1;
    }
  }
  const bool misbehaved = AppMisbehaved(report.metrics);
  if (!options.quiet) {
    PrintSummary(out, report.metrics, dir, !options.no_replay, scenario.app.is_library(), options.html && !options.no_replay,
                 scenario.clocks.enabled);
  } else if (misbehaved) {
    fmt::print(err, "syrof run: warning: the app misbehaved; see app in {}\n", (dir / "metrics.json").string());
  }
  if (live) lab::live::EndLive(*live, options.live, options.no_replay ? "" : (dir / "replay").string(), out);
  return options.strict && misbehaved ? 3 : 0;
}

}  // namespace syrof::cli
