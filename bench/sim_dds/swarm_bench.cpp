// A DDS swarm of 8, 16 and 32 robot processes at 20 Hz rounds on loopback
// (bench/sim_dds/swarm_idle.yaml with the robot count overridden): delivery
// ratio, round-start skew p50 / p99 / max, CPU per robot process, and P3.
//
// Usage: bench_sim_dds_swarm [--seconds S] [--robots N ...] [--realtime]
// (defaults 10 s, robots 8 16 32; --realtime: robot tasks at SCHED_FIFO,
// as `syrof swarm --realtime`, which needs root or CAP_SYS_NICE). The load
// average is printed first: skew is the machine's scheduling as much as DDS's. syrof-robot is found beside this
// program's build (SYROF_ROBOT_BINARY) or through $SYROF_ROBOT_BINARY.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/dds_world.h"

int main(int argc, char** argv) {
  double seconds = 10;
  bool realtime = false;
  std::vector<int> counts;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--seconds" && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (arg == "--realtime") {
      realtime = true;
    } else if (arg == "--robots") {
      while (i + 1 < argc && argv[i + 1][0] != '-') counts.push_back(std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: bench_sim_dds_swarm [--seconds S] [--robots N ...] [--realtime]\n");
      return 2;
    }
  }
  if (counts.empty()) counts = {8, 16, 32};
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) == 3) std::printf("load average %.2f %.2f %.2f; robot tasks %s\n", load[0], load[1], load[2],
                                            realtime ? "SCHED_FIFO (--realtime)" : "SCHED_OTHER");
  std::printf("robots  seconds  delivery  skew_p50_us  skew_p99_us  skew_max_us  cpu_mean_s  cpu_max_s  cpu_pct  p3_violations  epochs\n");
  for (const int robots : counts) {
    syrof::sim_dds::SwarmOptions options;
    options.scenario_path = std::string(SYROF_BENCH_DIR) + "/swarm_idle.yaml";
    options.overrides.robots = robots;
    options.overrides.duration_s = seconds;
    options.robot_binary = std::getenv("SYROF_ROBOT_BINARY") != nullptr ? std::getenv("SYROF_ROBOT_BINARY") : SYROF_ROBOT_BINARY;
    options.domain_id = syrof::sim_dds::DomainIdForRun(static_cast<uint64_t>(getpid()) * 131 + static_cast<uint64_t>(robots));
    options.out_dir = (std::filesystem::temp_directory_path() / ("syrof_bench_swarm_" + std::to_string(getpid()))).string();
    options.replay = false;
    options.realtime = realtime;
    std::ostringstream log;
    const syrof::sim_dds::SwarmResult result = syrof::sim_dds::RunSwarm(options, log);
    if (result.exit_code != 0) {
      std::fprintf(stderr, "%d robots: %s\n%s", robots, result.error.value_or(syrof::lab::Error{}).ToString().c_str(),
                   log.str().c_str());
      return 1;
    }
    const double cpu_sum = std::accumulate(result.cpu_seconds.begin(), result.cpu_seconds.end(), 0.0);
    const double cpu_max = *std::max_element(result.cpu_seconds.begin(), result.cpu_seconds.end());
    const double cpu_mean = cpu_sum / static_cast<double>(result.cpu_seconds.size());
    std::printf("%6d  %7.1f  %8.4f  %11.0f  %11.0f  %11.0f  %10.3f  %9.3f  %7.2f  %13d  %6d\n", robots, seconds,
                result.delivery_ratio, result.skew.p50_us, result.skew.p99_us, result.skew.max_us, cpu_mean, cpu_max,
                100.0 * cpu_mean / seconds, static_cast<int>(result.metrics.common_knowledge.violations),
                static_cast<int>(result.metrics.epochs_started));
    std::filesystem::remove_all(options.out_dir);
  }
  return 0;
}
