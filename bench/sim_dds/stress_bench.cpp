// P3 of a DDS swarm under seeded stress (docs/dds.md, "Stress"): the
// crash, pause, late join and 10 % loss of tests/sim_dds/scenarios/
// swarm_stress.yaml, on the world's grid and aligning from beacons, each run
// with its own stress seed (SIGSTOP bursts of robots and the world, late
// beacons and readings, and optionally the robots under one CPU quota),
// then the same runs unstressed
// for the COOPERATIVE fraction beside them.
//
// Usage: bench_sim_dds_stress [--runs N] [--first-seed S] [--rate R] [--late F]
//          [--cpu-quota PERMILLE] [--grid-only | --align-only] [--unstressed N]
//          [--keep-failures DIR] [--scenario FILE]
// Run i (0 .. N-1) uses stress seed S + i and alternates the round mode
// (even: the world's grid, odd: aligning) unless one mode is asked for. A
// run with a P3 violation prints its seed and the command that reruns it,
// keeps its metrics and replay under DIR (default /tmp), and makes the exit
// status 1. Defaults: 20 runs from seed 1, 4 bursts a second, 5 % of the
// samples late (lab/sim/stress.h's defaults), no quota,
// 4 unstressed runs. syrof-robot is found as bench_sim_dds_swarm finds it.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include "syrof/sim_dds/dds_world.h"
#include "syrof/sim_dds/participant.h"

namespace {

struct Tally {
  int runs = 0;
  int failed_runs = 0;
  int64_t violations = 0;
  int64_t starts = 0;
  int64_t cooperative_starts = 0;
  int64_t stalls = 0;
};

void PrintTally(const char* what, const Tally& t) {
  std::printf("%-28s %4d runs, %3d with P3 violations (%lld violations), COOPERATIVE starts %lld of %lld (%.1f %%), %lld SIGSTOP bursts\n",
              what, t.runs, t.failed_runs, static_cast<long long>(t.violations), static_cast<long long>(t.cooperative_starts),
              static_cast<long long>(t.starts), t.starts > 0 ? 100.0 * static_cast<double>(t.cooperative_starts) / static_cast<double>(t.starts) : 0.0,
              static_cast<long long>(t.stalls));
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 20;
  int unstressed = 4;
  uint64_t first_seed = 1;
  double rate = 4;
  double late = syrof::lab::sim::StressOptions{}.delayed_fraction;
  uint32_t quota = 0;
  int only = -1;  // -1 both, 0 grid, 1 align
  std::string keep = std::filesystem::temp_directory_path().string();
  std::string scenario = std::string(SYROF_SOURCE_DIR) + "/tests/sim_dds/scenarios/swarm_stress.yaml";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--runs" && has_value) {
      runs = std::atoi(argv[++i]);
    } else if (arg == "--first-seed" && has_value) {
      first_seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (arg == "--rate" && has_value) {
      rate = std::atof(argv[++i]);
    } else if (arg == "--late" && has_value) {
      late = std::atof(argv[++i]);
    } else if (arg == "--cpu-quota" && has_value) {
      quota = static_cast<uint32_t>(std::atoi(argv[++i]));
    } else if (arg == "--unstressed" && has_value) {
      unstressed = std::atoi(argv[++i]);
    } else if (arg == "--keep-failures" && has_value) {
      keep = argv[++i];
    } else if (arg == "--scenario" && has_value) {
      scenario = argv[++i];
    } else if (arg == "--grid-only") {
      only = 0;
    } else if (arg == "--align-only") {
      only = 1;
    } else {
      std::fprintf(stderr,
                   "usage: bench_sim_dds_stress [--runs N] [--first-seed S] [--rate R] [--late F] [--cpu-quota PERMILLE]\n"
                   "         [--grid-only | --align-only] [--unstressed N] [--keep-failures DIR] [--scenario FILE]\n");
      return 2;
    }
  }
  if (runs < 0 || unstressed < 0 || first_seed == 0) {
    std::fprintf(stderr, "bench_sim_dds_stress: runs must be >= 0 and the first seed >= 1\n");
    return 2;
  }
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) == 3) std::printf("load average %.2f %.2f %.2f; %s\n", load[0], load[1], load[2], scenario.c_str());
  std::printf("seed  mode     stalls  epochs  cooperative  p3  delivery  reports_late\n");
  Tally stressed[2], calm[2];
  bool any_failure = false;
  const auto run_one = [&](uint64_t seed, bool align, bool stress, Tally& tally) {
    syrof::sim_dds::SwarmOptions options;
    options.scenario_path = scenario;
    options.robot_binary = std::getenv("SYROF_ROBOT_BINARY") != nullptr ? std::getenv("SYROF_ROBOT_BINARY") : SYROF_ROBOT_BINARY;
    options.domain_id = syrof::sim_dds::DomainIdForRun((static_cast<uint64_t>(getpid()) << 20) ^ (seed * 2 + (align ? 1 : 0)));
    options.out_dir = (std::filesystem::temp_directory_path() / ("syrof_bench_stress_" + std::to_string(getpid()))).string();
    options.align_rounds = align;
    if (stress) {
      options.stress.seed = seed;
      options.stress.stalls_per_second = rate;
      options.stress.cpu_quota_permille = quota;
      options.stress.delayed_fraction = late;
    }
    std::ostringstream log;
    const syrof::sim_dds::SwarmResult result = syrof::sim_dds::RunSwarm(options, log);
    if (result.exit_code != 0) {
      std::fprintf(stderr, "seed %llu: %s\n%s", static_cast<unsigned long long>(seed),
                   result.error.value_or(syrof::lab::Error{}).ToString().c_str(), log.str().c_str());
      return false;
    }
    const auto& k = result.metrics.common_knowledge;
    ++tally.runs;
    tally.violations += k.violations;
    tally.failed_runs += k.violations > 0 ? 1 : 0;
    tally.starts += result.metrics.epoch_starts;
    tally.cooperative_starts += k.cooperative_starts;
    tally.stalls += result.stalls;
    std::printf("%4llu  %-7s  %6lld  %6lld  %10.1f%%  %2lld  %8.4f  %12lld%s\n", static_cast<unsigned long long>(seed),
                !stress ? "calm" : align ? "align" : "grid", static_cast<long long>(result.stalls),
                static_cast<long long>(result.metrics.epochs_started), 100.0 * k.cooperative_fraction.value_or(0),
                static_cast<long long>(k.violations), result.delivery_ratio,
                static_cast<long long>(result.metrics.dds ? result.metrics.dds->reports_late : 0),
                k.violations > 0 ? "  P3 VIOLATED" : "");
    std::fflush(stdout);
    if (k.violations > 0) {
      any_failure = true;
      const std::string kept = keep + "/syrof_stress_seed" + std::to_string(seed) + (align ? "_align" : "_grid");
      std::error_code error;
      std::filesystem::remove_all(kept, error);
      std::filesystem::rename(options.out_dir, kept, error);
      std::printf("  stress seed %llu failed: rerun with  build/bin/syrof swarm %s --stress %llu --stress-rate %g --stress-late %g%s%s --out %s\n",
                  static_cast<unsigned long long>(seed), scenario.c_str(), static_cast<unsigned long long>(seed), rate, late,
                  quota > 0 ? (" --stress-cpu-quota " + std::to_string(quota)).c_str() : "", align ? " --align-rounds" : "",
                  kept.c_str());
      std::printf("%s", log.str().c_str());
    }
    std::filesystem::remove_all(options.out_dir);
    return true;
  };
  for (int i = 0; i < runs; ++i) {
    const bool align = only >= 0 ? only == 1 : (i % 2) == 1;
    if (!run_one(first_seed + static_cast<uint64_t>(i), align, true, stressed[align ? 1 : 0])) return 1;
  }
  for (int i = 0; i < unstressed; ++i) {
    const bool align = only >= 0 ? only == 1 : (i % 2) == 1;
    if (!run_one(first_seed + static_cast<uint64_t>(i), align, false, calm[align ? 1 : 0])) return 1;
  }
  PrintTally("stressed, the world's grid", stressed[0]);
  PrintTally("stressed, aligning", stressed[1]);
  PrintTally("unstressed, the world's grid", calm[0]);
  PrintTally("unstressed, aligning", calm[1]);
  if (getloadavg(load, 3) == 3) std::printf("load average at the end %.2f %.2f %.2f\n", load[0], load[1], load[2]);
  return any_failure ? 1 : 0;
}
