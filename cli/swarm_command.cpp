#include "swarm_command.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>

#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "exit_status.h"
#include "usage.h"
#include "run_summary.h"
#include "syrof/lab/live/live_server.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/sim_dds/dds_world.h"

namespace syrof::cli {
namespace {

std::atomic<bool> g_swarm_stop{false};
void StopSwarm(int) { g_swarm_stop.store(true); }

}  // namespace

CLI::App* SetupSwarmCommand(CLI::App& app, SwarmOptions& options) {
  CLI::App* swarm = app.add_subcommand(
      "swarm", "Run a scenario as a DDS swarm: one syrof-robot process per robot, in wall-clock time");
  swarm->add_option("scenario", options.scenario_path, "Scenario file (YAML, docs/scenarios.md)")->required();
  swarm->add_option("--app", options.app,
                    "App to run instead of the scenario's: builtin:NAME, or your library's path (build/libmyapp.so)");
  swarm->add_option("--seed", options.seed, "Seed instead of the scenario's");
  swarm->add_option("--robots", options.robots, "Robot count instead of the scenario's")->check(CLI::Range(1, 110));
  swarm->add_option("--duration", options.duration_s, "Seconds (wall clock) instead of the scenario's")
      ->check(DurationValidator());
  swarm->add_option("--out", options.out_dir, "Output folder (default: out/<scenario name>-dds)");
  swarm->add_option("--interface", options.interface,
                    "Network interface for DDS: lo keeps the swarm on this machine (default lo)");
  swarm->add_option("--domain", options.domain, "DDS domain id (default: $SYROF_DDS_DOMAIN, else one per run)")
      ->check(CLI::Range(0, 232));
  swarm->add_flag("--no-replay", options.no_replay, "Do not write the replay");
  swarm->add_flag("--realtime", options.realtime,
                  "Robot tasks at SCHED_FIFO priorities (root or CAP_SYS_NICE; without it robots say so and go on)");
  swarm->add_flag("--align-rounds", options.align_rounds,
                  "Robots align their rounds from the beacons they hear and number their own (hosts without synchronised clocks; docs/dds.md)");
  swarm->add_flag("--realtime-start", options.realtime_start,
                  "Robots read the start on CLOCK_REALTIME (robots on several hosts whose clocks are kept in sync)");
  CLI::Option* stress = swarm->add_option("--stress", options.stress_seed,
                    "Seeded stress: SIGSTOP bursts of 10-200 ms to robots and the world, late beacons and readings; a failing run reruns from its seed (docs/dds.md)")
      ->check(CLI::Range(uint64_t{1}, std::numeric_limits<uint64_t>::max()));
  swarm->add_option("--stress-rate", options.stress_rate, "With --stress: bursts a second over the swarm (default 4)")
      ->check(CLI::Range(0.0, 100.0))
      ->needs(stress);
  swarm->add_option("--stress-cpu-quota", options.stress_cpu_quota,
                    "With --stress: the robot processes together get this many per mille of one core (a cgroup; root)")
      ->check(CLI::Range(1, 1000))
      ->needs(stress);
  swarm->add_option("--stress-late", options.stress_late,
                    "With --stress: this fraction of beacons and sensor readings reach their robot 10-200 ms late (default 0.05)")
      ->check(CLI::Range(0.0, 1.0))
      ->needs(stress);
  swarm->add_flag("--quiet", options.quiet, "No progress line, no summary");
  lab::live::SetupLiveOptions(*swarm, options.live);
  swarm->footer(
      "Each robot is a process (syrof-robot) running the robot software on the POSIX port; this process is the\n"
      "world (bodies, sensors, faults, metrics). Faults are real: crash = SIGKILL, pause = SIGSTOP/SIGCONT,\n"
      "join = a process started late. Ctrl-C stops every process. See docs/dds.md.");
  return swarm;
}

int RunSwarmCommand(const SwarmOptions& options, std::ostream& out, std::ostream& err) {
  lab::scenario::Overrides overrides;
  overrides.seed = options.seed;
  overrides.robots = options.robots;
  overrides.duration_s = options.duration_s;
  overrides.app = options.app;
  // The scenario is read here once for its name and errors; the world and
  // every robot read it again with the same overrides.
  const std::string scenario_file = ScenarioArgument(options.scenario_path, "swarm", err, options.quiet);
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(scenario_file, overrides);
  if (!loaded.ok()) {
    fmt::print(err, "syrof swarm: {}\n", loaded.error->ToString());
    return kBadInput;
  }
  sim_dds::SwarmOptions swarm;
  // Robots may run in another working directory's meaning of a relative
  // path: hand them absolute ones.
  swarm.scenario_path = std::filesystem::absolute(scenario_file).string();
  swarm.overrides = overrides;
  if (overrides.app && lab::scenario::IsLibraryPath(*overrides.app)) {
    swarm.overrides.app = std::filesystem::absolute(*overrides.app).string();
  }
  swarm.out_dir = options.out_dir.empty() ? (std::filesystem::path("out") / (loaded.scenario->name + "-dds")).string()
                                          : options.out_dir;
  swarm.replay = !options.no_replay;
  swarm.interface = options.interface;
  swarm.realtime = options.realtime;
  swarm.align_rounds = options.align_rounds;
  swarm.realtime_start = options.realtime_start;
  swarm.domain_id = options.domain;
  swarm.stress.seed = options.stress_seed;
  swarm.stress.stalls_per_second = options.stress_rate;
  swarm.stress.cpu_quota_permille = options.stress_cpu_quota;
  swarm.stress.delayed_fraction = options.stress_late;
  g_swarm_stop.store(false);
  swarm.stop = &g_swarm_stop;
  struct sigaction action {};
  struct sigaction old_int {}, old_term {};
  action.sa_handler = StopSwarm;
  sigaction(SIGINT, &action, &old_int);
  sigaction(SIGTERM, &action, &old_term);
  if (!options.quiet) {
    fmt::print(out, "syrof swarm: {} ({}), {} robot processes, seed {}, {:.1f} s\n", loaded.scenario->name,
               loaded.scenario->app.name, loaded.scenario->robots.size(), loaded.scenario->seed,
               loaded.scenario->timing.duration_s);
    // One line, rewritten each second on a terminal; every 10 s otherwise.
    const bool terminal = &out == &std::cout && isatty(STDOUT_FILENO) != 0;
    const double duration = loaded.scenario->timing.duration_s;
    swarm.progress = [&out, terminal, duration](double seconds) {
      if (terminal) {
        fmt::print(out, "\r  {:.0f} of {:.0f} s", seconds, duration);
        out.flush();
      } else if (static_cast<int64_t>(seconds) % 10 == 0) {
        fmt::print(out, "  {:.0f} of {:.0f} s\n", seconds, duration);
      }
    };
  }
  lab::live::LiveResult started_live =
      lab::live::StartLive(options.live, loaded.scenario->name + " (DDS swarm)", out, swarm.sinks);
  if (!started_live.ok()) {
    fmt::print(err, "syrof swarm: {}\n", started_live.error->ToString());
    return kBadInput;
  }
  const std::unique_ptr<lab::live::LiveServer> live = std::move(started_live.server);
  const sim_dds::SwarmResult result = sim_dds::RunSwarm(swarm, err);
  // A swarm that failed before its end never told the sinks: the page says
  // the run stopped.
  if (live) live->OnFinish(false);
  if (!options.quiet && &out == &std::cout && isatty(STDOUT_FILENO) != 0) fmt::print(out, "\n");
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  if (result.exit_code != 0) {
    fmt::print(err, "syrof swarm: {}\n", result.error->ToString());
    if (live) live->SetReplayPage(std::nullopt);
    return result.exit_code == 2 ? kBadInput : kInternalError;
  }
  if (result.stress_seed != 0 && result.metrics.common_knowledge.violations > 0) {
    fmt::print(err, "syrof swarm: P3 violated under stress seed {} ({} stalls): rerun with --stress {} --stress-rate {:g} "
               "--stress-late {:g}{}{}\n",
               result.stress_seed, result.stalls, result.stress_seed, options.stress_rate, options.stress_late,
               options.stress_cpu_quota > 0 ? fmt::format(" --stress-cpu-quota {}", options.stress_cpu_quota) : "",
               options.align_rounds ? " --align-rounds" : "");
  }
  if (!options.quiet) {
    const lab::metrics::Metrics& metrics = result.metrics;
    if (result.stopped_early) fmt::print(out, "  stopped early (signal): the metrics cover what ran\n");
    PrintSummary(out, metrics, swarm.out_dir, swarm.replay, loaded.scenario->app.is_library(), false, false,
                 "SyROF swarm");
    double cpu_max = 0, cpu_sum = 0;
    for (const double seconds : result.cpu_seconds) {
      cpu_max = std::max(cpu_max, seconds);
      cpu_sum += seconds;
    }
    const double wall = metrics.wall_seconds;
    fmt::print(out, "  {:<17} in-round delivery {:.2f}%; round-start skew p50 {:.0f} us, p99 {:.0f} us, max {:.0f} us\n",
               "dds", 100.0 * result.delivery_ratio, result.skew.p50_us, result.skew.p99_us, result.skew.max_us);
    if (!result.cpu_seconds.empty() && wall > 0) {
      fmt::print(out, "  {:<17} CPU per robot process {:.1f}% mean, {:.1f}% max (of one core)\n", "",
                 100.0 * cpu_sum / static_cast<double>(result.cpu_seconds.size()) / wall, 100.0 * cpu_max / wall);
    }
  }
  if (!options.quiet && result.stress_seed != 0) {
    fmt::print(out, "  {:<17} seed {}: {} SIGSTOP bursts{}{} (rerun: --stress {})\n", "stress", result.stress_seed,
               result.stalls,
               options.stress_late > 0 ? fmt::format(", {:g}% of beacons and readings 10-200 ms late", 100 * options.stress_late) : "",
               options.stress_cpu_quota > 0 ? fmt::format(", robots at {} per mille of a core", options.stress_cpu_quota) : "",
               result.stress_seed);
  }
  if (live) lab::live::EndLive(*live, options.live, swarm.replay ? (std::filesystem::path(swarm.out_dir) / "replay").string() : "", out);
  return kOk;
}

}  // namespace syrof::cli
