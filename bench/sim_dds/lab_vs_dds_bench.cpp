// The same scenario and seeds in the simulated lab and as a DDS swarm, side
// by side: epochs, COOPERATIVE starts, P3 violations, removals and joins,
// the goal, and (DDS only) in-round delivery and round-start skew. The lab
// is virtual time and bit-identical per seed; the DDS run is wall-clock time
// on real processes, so its figures vary from run to run, and its channel
// draws the lab's losses by (seed, round, sender, receiver).
//
// Usage: bench_sim_dds_lab_vs_dds [--scenario PATH] [--seeds N] [--seconds S] [--realtime]
// (defaults: lab/scenarios/demo_circle.yaml, 3 seeds from the scenario's,
// 20 s each).
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/dds_world.h"

namespace {

struct Row {
  int64_t epochs = 0;
  double cooperative = 0;
  int64_t p3 = 0;
  int64_t removals = 0;
  int64_t joins = 0;
  bool goal = false;
};

Row RowOf(const syrof::lab::metrics::Metrics& m) {
  Row row;
  row.epochs = m.epochs_started;
  row.cooperative = m.common_knowledge.cooperative_fraction.value_or(0.0);
  row.p3 = m.common_knowledge.violations;
  row.removals = m.membership.removals;
  row.joins = m.membership.joins;
  row.goal = m.goal.reached;
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_path = std::string(SYROF_SOURCE_DIR) + "/lab/scenarios/demo_circle.yaml";
  int seeds = 3;
  double seconds = 20;
  bool realtime = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--scenario" && i + 1 < argc) {
      scenario_path = argv[++i];
    } else if (arg == "--seeds" && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else if (arg == "--seconds" && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (arg == "--realtime") {
      realtime = true;
    } else {
      std::fprintf(stderr, "usage: bench_sim_dds_lab_vs_dds [--scenario PATH] [--seeds N] [--seconds S] [--realtime]\n");
      return 2;
    }
  }
  syrof::lab::scenario::Overrides overrides;
  overrides.duration_s = seconds;
  const syrof::lab::scenario::LoadResult base = syrof::lab::scenario::LoadScenarioFile(scenario_path, overrides);
  if (!base.ok()) {
    std::fprintf(stderr, "%s\n", base.error->ToString().c_str());
    return 2;
  }
  std::printf("%s (%s), %zu robots, %.0f s per run\n", base.scenario->name.c_str(), base.scenario->app.name.c_str(),
              base.scenario->robots.size(), seconds);
  std::printf("seed     runtime  epochs  cooperative  p3  removals  joins  goal  delivery  skew_p99_us\n");
  for (int k = 0; k < seeds; ++k) {
    overrides.seed = base.scenario->seed + static_cast<uint64_t>(k);
    const syrof::lab::scenario::LoadResult loaded = syrof::lab::scenario::LoadScenarioFile(scenario_path, overrides);
    syrof::lab::sim::Simulation lab(*loaded.scenario);
    const Row l = RowOf(lab.Finish(0).metrics);
    std::printf("%-8llu lab      %6lld  %10.1f%%  %2lld  %8lld  %5lld  %-4s  %8s  %11s\n",
                static_cast<unsigned long long>(*overrides.seed), static_cast<long long>(l.epochs), 100 * l.cooperative,
                static_cast<long long>(l.p3), static_cast<long long>(l.removals), static_cast<long long>(l.joins),
                l.goal ? "yes" : "no", "-", "-");

    syrof::sim_dds::SwarmOptions options;
    options.scenario_path = scenario_path;
    options.overrides = overrides;
    options.robot_binary =
        std::getenv("SYROF_ROBOT_BINARY") != nullptr ? std::getenv("SYROF_ROBOT_BINARY") : SYROF_ROBOT_BINARY;
    options.domain_id = syrof::sim_dds::DomainIdForRun(static_cast<uint64_t>(getpid()) * 977 + static_cast<uint64_t>(k));
    options.out_dir = (std::filesystem::temp_directory_path() / ("syrof_bench_vs_" + std::to_string(getpid()))).string();
    options.replay = false;
    options.realtime = realtime;
    std::ostringstream log;
    const syrof::sim_dds::SwarmResult result = syrof::sim_dds::RunSwarm(options, log);
    std::filesystem::remove_all(options.out_dir);
    if (result.exit_code != 0) {
      std::fprintf(stderr, "seed %llu: %s\n%s", static_cast<unsigned long long>(*overrides.seed),
                   result.error.value_or(syrof::lab::Error{}).ToString().c_str(),
                   log.str().c_str());
      return 1;
    }
    const Row d = RowOf(result.metrics);
    std::printf("%-8llu dds      %6lld  %10.1f%%  %2lld  %8lld  %5lld  %-4s  %7.2f%%  %11.0f\n",
                static_cast<unsigned long long>(*overrides.seed), static_cast<long long>(d.epochs), 100 * d.cooperative,
                static_cast<long long>(d.p3), static_cast<long long>(d.removals), static_cast<long long>(d.joins),
                d.goal ? "yes" : "no", 100 * result.delivery_ratio, result.skew.p99_us);
  }
  return 0;
}
