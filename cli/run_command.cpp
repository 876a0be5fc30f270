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
#include <vector>

#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
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

// A JSON value for the summary: numbers with `decimals`, null as "-".
std::string Number(const nlohmann::json& value, int decimals) {
  if (value.is_null()) return "-";
  if (value.is_number_integer()) return std::to_string(value.get<int64_t>());
  return fmt::format("{:.{}f}", value.get<double>(), decimals);
}

const nlohmann::json& Field(const nlohmann::json& json, const char* object, const char* key) {
  static const nlohmann::json kNull;
  if (!json.contains(object) || !json[object].contains(key)) return kNull;
  return json[object][key];
}

// `json[key]`, or null when `json` is no object or has no such key.
const nlohmann::json& Member(const nlohmann::json& json, const char* key) {
  static const nlohmann::json kNull;
  if (!json.is_object() || !json.contains(key)) return kNull;
  return json[key];
}

std::string Text(const nlohmann::json& json, const char* key) {
  const nlohmann::json& value = Member(json, key);
  return value.is_string() ? value.get<std::string>() : std::string();
}

// How many incidents of one kind metrics.json's app object counts.
int64_t IncidentCount(const nlohmann::json& m, const char* kind) {
  const nlohmann::json& count = Member(Field(m, "app", kind), "count");
  return count.is_number_integer() ? count.get<int64_t>() : 0;
}

// Whether metrics.json's app object reports any misbehaviour.
bool AppMisbehaved(const nlohmann::json& m) {
  const nlohmann::json& faults = Field(m, "app", "faults");
  return (faults.is_array() && !faults.empty()) || IncidentCount(m, "invalid_commands") > 0 ||
         IncidentCount(m, "payload_refused") > 0;
}

// "first robot 2, epoch 3: what" for an incident's first occurrence.
std::string FirstIncident(const nlohmann::json& incidents) {
  const nlohmann::json& first = Member(incidents, "first");
  if (!first.is_object()) return "first unknown";
  return fmt::format("first robot {}, epoch {}: {}", Number(Member(first, "robot"), 0),
                     Number(Member(first, "epoch"), 0), Text(first, "what"));
}

// The app's lines: one when it behaved, a warning and the first occurrence
// of each kind of misbehaviour otherwise.
void PrintAppLines(std::ostream& out, const nlohmann::json& m) {
  const std::string name = Text(Member(m, "app"), "name");
  if (!AppMisbehaved(m)) {
    fmt::print(out, "  {:<17} {}: no faults, no invalid commands, no refused payloads\n", "app", name);
    return;
  }
  fmt::print(out, "  {:<17} {}: WARNING: the app misbehaved (see app in metrics.json; --strict exits 3)\n", "app",
             name);
  const nlohmann::json& faults = Field(m, "app", "faults");
  if (faults.is_array() && !faults.empty()) {
    const nlohmann::json& first = faults[0];
    const std::string detail = Text(first, "detail");
    fmt::print(out, "    {:<17} {} in all; first robot {}, {} of epoch {} at {} s: {}{}\n", "faults", faults.size(),
               Number(Member(first, "robot"), 0), Text(first, "callback"), Number(Member(first, "epoch"), 0),
               Number(Member(first, "time_s"), 3), Text(first, "verdict"), detail.empty() ? "" : " (" + detail + ")");
  }
  if (const int64_t count = IncidentCount(m, "invalid_commands"); count > 0) {
    fmt::print(out, "    {:<17} {} in all, each replaced by STOP; {}\n", "invalid commands", count,
               FirstIncident(Field(m, "app", "invalid_commands")));
  }
  if (const int64_t count = IncidentCount(m, "payload_refused"); count > 0) {
    fmt::print(out, "    {:<17} {} in all (over 9 bytes); {}\n", "refused payloads", count,
               FirstIncident(Field(m, "app", "payload_refused")));
  }
}

// The app host's limits for a library run: the command line's budgets over
// the scenario's over the host's defaults. An unset wall cap is raised to
// 4x the CPU budget when that is more than the default, so a larger budget
// is not cut short by the default wall cap. Empty and `problem` set when the
// two disagree or a budget is given for a built-in app.
std::optional<app_host::HostLimits> LimitsFor(const scenario::AppSpec& app, const RunOptions& options,
                                              std::string& problem) {
  if (!app.is_library()) {
    if (options.cpu_budget_ms || options.wall_cap_ms) {
      problem = fmt::format("{} is for a library app; {} runs inside the simulator",
                            options.cpu_budget_ms ? "--cpu-budget-ms" : "--wall-cap-ms", app.name);
      return std::nullopt;
    }
    return app_host::HostLimits{};
  }
  app_host::HostLimits limits;
  const std::optional<uint32_t> cpu = options.cpu_budget_ms ? options.cpu_budget_ms : app.cpu_budget_ms;
  const std::optional<uint32_t> wall = options.wall_cap_ms ? options.wall_cap_ms : app.wall_cap_ms;
  if (cpu) limits.cpu_budget_ms = *cpu;
  if (wall) {
    limits.wall_cap_ms = *wall;
  } else {
    limits.wall_cap_ms = std::max(limits.wall_cap_ms, 4 * limits.cpu_budget_ms);
  }
  if (limits.wall_cap_ms < limits.cpu_budget_ms) {
    problem = fmt::format("the wall cap ({} ms) must be at least the CPU budget ({} ms)", limits.wall_cap_ms,
                          limits.cpu_budget_ms);
    return std::nullopt;
  }
  return limits;
}

void PrintSummary(std::ostream& out, const nlohmann::json& m, const std::filesystem::path& dir, bool replay,
                  bool library, bool html, bool clocks) {
  const double sim = m.value("sim_seconds", 0.0);
  const double wall = m.value("wall_seconds", 0.0);
  fmt::print(out, "\nSyROF run: {} ({}), {} robots, seed {}\n", m.value("scenario", std::string()),
             Field(m, "app", "source").is_string() ? Field(m, "app", "source").get<std::string>() : std::string(),
             m.value("robots", 0), m.value("seed", uint64_t{0}));
  if (wall > 0) {
    fmt::print(out, "  {:<17} {:.1f} s ({} radio rounds) in {:.2f} s wall, {:.0f}x real time\n", "simulated", sim,
               m.value("radio_rounds", int64_t{0}), wall, sim / wall);
  } else {
    fmt::print(out, "  {:<17} {:.1f} s ({} radio rounds)\n", "simulated", sim, m.value("radio_rounds", int64_t{0}));
  }
  fmt::print(out, "  {:<17} {} epochs, start skew max {} rounds ({} ms)\n", "synchrony", Number(m["epochs_started"], 0),
             Number(Field(m, "synchrony", "max_start_skew_rounds"), 0),
             Number(Field(m, "synchrony", "max_start_skew_ms"), 1));
  const nlohmann::json& fraction = Field(m, "common_knowledge", "cooperative_fraction");
  fmt::print(out, "  {:<17} {} P3 violations, {} COOPERATIVE starts, mode disagreement max {} rounds\n",
             "common knowledge", Number(Field(m, "common_knowledge", "violations"), 0),
             fraction.is_null() ? std::string("-") : fmt::format("{:.1f}%", 100.0 * fraction.get<double>()),
             Number(Field(m, "common_knowledge", "max_mode_disagreement_rounds"), 0));
  fmt::print(out, "  {:<17} {} (min separation {} m), wall contacts {}\n", "collisions",
             Number(Field(m, "collisions", "count"), 0), Number(Field(m, "collisions", "min_separation_m"), 3),
             Number(Field(m, "walls", "contacts"), 0));
  const nlohmann::json& safety = Field(m, "safety", "enabled");
  if (safety.is_boolean() && !safety.get<bool>()) {
    fmt::print(out, "  {:<17} off (safety: off in the scenario)\n", "safety");
  } else if (safety.is_boolean()) {
    fmt::print(out, "  {:<17} {} interventions on {} robots, {} join waits\n", "safety",
               Number(Field(m, "safety", "interventions"), 0), Number(Field(m, "safety", "robots_involved"), 0),
               Number(Field(m, "safety", "join_waits"), 0));
  }
  const nlohmann::json& agreed = Field(m, "agreement", "agreed_epochs");
  if (agreed.is_number()) {
    const nlohmann::json& first = Field(m, "agreement", "first_disagreement");
    fmt::print(out, "  {:<17} the app's global state agreed in {} of {} COOPERATIVE epochs{}\n", "agreement",
               Number(agreed, 0), Number(Field(m, "agreement", "cooperative_epochs"), 0),
               first.is_object() ? fmt::format(" (first disagreement: epoch {}, robot {})", Number(first["epoch"], 0),
                                               Number(first["robot"], 0))
                                 : std::string());
  }
  fmt::print(out, "  {:<17} position RMSE {} m, max {} m\n", "estimation",
             Number(Field(m, "estimation", "position_rmse_m"), 3), Number(Field(m, "estimation", "max_error_m"), 3));
  fmt::print(out, "  {:<17} {} removals, {} joins\n", "membership", Number(Field(m, "membership", "removals"), 0),
             Number(Field(m, "membership", "joins"), 0));
  if (const nlohmann::json& phase = m.contains("round_phase") ? m["round_phase"] : nlohmann::json();
      clocks && phase.is_object() && phase.contains("residual") && phase["residual"].is_object()) {
    // Real clocks (docs/clocks.md): how long until every pair of members
    // stayed within the threshold, and the phase error left after that.
    const nlohmann::json& converged = phase.contains("converged_s") ? phase["converged_s"] : nlohmann::json();
    fmt::print(out, "  {:<17} {}, phase error after that p99 {} ms, max {} ms\n", "round phase",
               converged.is_number() ? fmt::format("aligned within {} ms after {:.2f} s", Number(phase["threshold_ms"], 1),
                                                   converged.get<double>())
                                     : std::string("never aligned within ") + Number(phase["threshold_ms"], 1) + " ms",
               Number(phase["residual"]["p99_ms"], 3), Number(phase["residual"]["max_ms"], 3));
  }
  const bool declared_goal = m.contains("goal") && m["goal"].is_object() && m["goal"].value("source", "") == "scenario";
  if (library && !declared_goal) {
    fmt::print(out, "  {:<17} none: declare checks under goal: in the scenario (docs/scenarios.md)\n", "goal");
  } else if (m.contains("goal")) {
    const nlohmann::json& goal = m["goal"];
    fmt::print(out, "  {:<17} {} ({})\n", "goal", goal.value("reached", false) ? "reached" : "NOT reached",
               goal.value("detail", std::string()));
  }
  PrintAppLines(out, m);
  fmt::print(out, "  {:<17} {}{}{}{}\n", "outputs", (dir / "metrics.json").string(),
             replay ? ", " + (dir / "replay").string() : std::string(),
             library ? ", " + (dir / "robots").string() + "/<id>.log" : std::string(),
             html ? ", " + (dir / "replay.html").string() : std::string());
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
  run->add_flag("--strict", options.strict,
                "Exit with status 3 if the app faulted, returned an invalid command or had a payload refused");
  return run;
}

int RunRunCommand(const RunOptions& options, std::ostream& out, std::ostream& err, bool err_is_terminal) {
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(options.scenario_path, OverridesOf(options));
  if (!loaded.ok()) {
    fmt::print(err, "syrof run: {}\n", loaded.error->ToString());
    return 2;
  }
  const scenario::Scenario& scenario = *loaded.scenario;
  std::string problem;
  const std::optional<app_host::HostLimits> limits = LimitsFor(scenario.app, options, problem);
  if (!limits) {
    fmt::print(err, "syrof run: {}\n", problem);
    return 2;
  }
  const bool library = scenario.app.is_library() && !options.app_factory;
  const std::filesystem::path dir =
      options.out_dir.empty() ? std::filesystem::path("out") / scenario.name : std::filesystem::path(options.out_dir);
  // A library is loaded once in a sandboxed host before any output exists,
  // so a library that cannot run is refused like a bad scenario.
  app_host::HostOptions host;
  std::vector<std::string> sandbox_notes;
  if (library) {
    host.library_path = scenario.app.library;
    host.limits = *limits;
    host.params = scenario.app.params;
    const app_host::LibraryCheck check = app_host::CheckLibrary(host);
    if (!check.ok) {
      fmt::print(err, "syrof run: {}\n", check.error);
      return 2;
    }
    sandbox_notes = app_host::SandboxNotes();
    host.log_directory = (dir / "robots").string();
    // Logs of an earlier run with more robots would pass for this run's.
    std::error_code ignored;
    std::filesystem::remove_all(host.log_directory, ignored);
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
                 host.limits.cpu_budget_ms, host.limits.wall_cap_ms);
    }
    for (const std::string& note : sandbox_notes) fmt::print(out, "  sandbox: {}\n", note);
  }

  const auto started = std::chrono::steady_clock::now();
  auto elapsed_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  sim::SimulationOptions sim_options;
  sim_options.replay = options.no_replay ? nullptr : &replay_file;
  sim_options.app_factory = options.app_factory;
  sim_options.app_source = options.app_source;
  if (library) {
    sim_options.app_factory = [host](uint16_t id) { return app_host::MakeHostedApp(host, id); };
    sim_options.app_source = scenario.app.library;
    sim_options.app_sandbox = sandbox_notes;
  }
  if (!options.quiet && err_is_terminal) {
    const double duration_s = scenario.timing.duration_s;
    sim_options.progress = [&err, &elapsed_s, duration_s](double sim_seconds) {
      const double wall = elapsed_s();
      fmt::print(err, "\r  t = {:6.1f} / {:.1f} s   {:6.1f}x real time ", sim_seconds, duration_s,
                 wall > 0 ? sim_seconds / wall : 0.0);
      err.flush();
    };
  }
  sim::Simulation simulation(scenario, sim_options);
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
    if (std::string page_problem = WritePage((dir / "replay").string(), (dir / "replay.html").string());
        !page_problem.empty()) {
      fmt::print(err, "syrof run: writing {} failed: {}\n", (dir / "replay.html").string(), page_problem);
      return 1;
    }
  }
  const nlohmann::json metrics = nlohmann::json::parse(report.metrics_json);
  const bool misbehaved = AppMisbehaved(metrics);
  if (!options.quiet) {
    PrintSummary(out, metrics, dir, !options.no_replay, scenario.app.is_library(), options.html && !options.no_replay,
                 scenario.clocks.enabled);
  } else if (misbehaved) {
    fmt::print(err, "syrof run: warning: the app misbehaved; see app in {}\n", (dir / "metrics.json").string());
  }
  return options.strict && misbehaved ? 3 : 0;
}

}  // namespace syrof::cli
