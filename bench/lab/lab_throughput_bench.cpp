// Simulated-lab throughput: robot-seconds simulated per second of CPU time on
// one core, for 10, 100 and 1000 robots in the standard scenario: every
// robot runs its EKF at 100 Hz, its synchronizer at 20 Hz (50 ms radio
// rounds), over a channel losing 5% of beacons i.i.d.; the arena grows with
// the swarm (robots on a 1 m grid up to 31 a side, anchors at its corners). The app is
// builtin:idle, so the figure is the platform's cost (sensors, estimator,
// synchronizer, radio, physics, metrics, replay); apps add their own (the
// second table runs builtin:circle, whose matching every robot computes).
// A last table runs 100 robots with the safety filter (docs/safety.md) on
// and off: its cost is the difference (target: at most 10%).
//
// A table of the thread mode (`syrof run --threads`, docs/lab.md "Threads")
// follows: 100 and 1000 robots, 1 thread against 2, in wall time (CPU time
// adds up over threads), runs alternating; the speed-up is the best 1-thread
// wall time over the best 2-thread one.
//
// Usage: bench_lab_throughput [--quick | --safety | --threads | --one ROBOTS SECONDS [THREADS]]
//   --quick: shorter runs, for CI smoke; --safety: only the safety filter's
//   table; --threads: only the thread mode's table; --one: a single run of
//   builtin:idle with the safety filter on, for profilers (valgrind
//   --tool=callgrind, perf record), printing its figure (per wall second
//   when THREADS > 1).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace {

using namespace syrof::lab;

std::string StandardScenario(int robots, const char* app, double duration_s, bool safety = true) {
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(robots))));
  // Robots 1 m apart, the arena one spacing wider than the grid; from 32
  // robots a side the arena stays at 32 m (beacon positions are int16
  // millimetres, at most 32.767 m) and the spacing shrinks to fit.
  const double arena_m = std::min(side + 1.0, 32.0);
  const double spacing_m = arena_m / (side + 1.0);
  return fmt::format(R"(name: bench_standard_{robots}
seed: 1
arena:
  width_m: {arena}
  height_m: {arena}
  anchors:
    - {{x_m: 0, y_m: 0, z_m: 0}}
    - {{x_m: {arena}, y_m: {arena}, z_m: 0}}
    - {{x_m: 0, y_m: {arena}, z_m: 2}}
    - {{x_m: {arena}, y_m: 0, z_m: 2}}
robots:
  count: {robots}
  kind: omni
  placement: grid
  spacing_m: {spacing}
timing:
  radio_round_s: 0.05
  app_round_s: 1.0
  duration_s: {duration}
channel:
  model: iid
  loss: 0.05
app: {app}
safety: {safety}
)",
                     fmt::arg("robots", robots), fmt::arg("arena", arena_m), fmt::arg("spacing", spacing_m), fmt::arg("duration", duration_s),
                     fmt::arg("app", app), fmt::arg("safety", safety ? "on" : "off"));
}

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }
double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Returns robot-seconds per CPU second (construction excluded); with
// `wall`, per wall second.
double Measure(int robots, const char* app, double duration_s, bool replay, bool safety = true, int threads = 1,
               bool wall = false) {
  const scenario::LoadResult loaded =
      scenario::LoadScenarioText(StandardScenario(robots, app, duration_s, safety), "bench");
  if (!loaded.ok()) {
    fmt::print(stderr, "bench scenario refused: {}\n", loaded.error->ToString());
    std::exit(1);
  }
  std::ostringstream replay_bytes;
  sim::SimulationOptions options;
  options.replay = replay ? &replay_bytes : nullptr;
  options.threads = threads;
  sim::Simulation simulation(*loaded.scenario, options);
  const auto now = wall ? WallSeconds : CpuSeconds;
  const double start = now();
  simulation.RunUntil(duration_s);
  const double cpu = now() - start;
  const sim::RunReport report = simulation.Finish(cpu);
  (void)report;
  return robots * duration_s / cpu;
}

}  // namespace

// The thread mode's table (see the top of the file).
void PrintThreads(bool quick) {
  fmt::print("\nthe thread mode (--threads), builtin:idle, wall time, best of 3, runs alternating 1 and 2 threads\n\n");
  fmt::print("{:<16} {:>8} {:>12} {:>20} {:>20} {:>9}\n", "app", "robots", "sim seconds", "1 thread, robot-s/s",
             "2 threads, robot-s/s", "speed-up");
  struct Case {
    int robots;
    double duration_s;
  };
  for (const Case c : {Case{100, quick ? 2.0 : 10.0}, Case{1000, quick ? 0.5 : 3.0}}) {
    double best_one = 0;
    double best_two = 0;
    for (int run = 0; run < 3; ++run) {
      best_one = std::max(best_one, Measure(c.robots, "builtin:idle", c.duration_s, true, true, 1, true));
      best_two = std::max(best_two, Measure(c.robots, "builtin:idle", c.duration_s, true, true, 2, true));
    }
    fmt::print("{:<16} {:>8} {:>12.1f} {:>20.0f} {:>20.0f} {:>8.2f}x\n", "builtin:idle", c.robots, c.duration_s,
               best_one, best_two, best_two / best_one);
  }
}

int main(int argc, char** argv) {
  if ((argc == 4 || argc == 5) && std::strcmp(argv[1], "--one") == 0) {
    const int robots = std::atoi(argv[2]);
    const double duration_s = std::atof(argv[3]);
    const int threads = argc == 5 ? std::atoi(argv[4]) : 1;
    if (robots < 1 || !(duration_s > 0) || threads < 1 || threads > sim::kMaxThreads) {
      fmt::print(stderr, "--one needs ROBOTS >= 1, SECONDS > 0 and THREADS from 1 to {}\n", sim::kMaxThreads);
      return 2;
    }
    fmt::print("builtin:idle {} robots {} s, {} thread(s): {:.0f} robot-s per {} s\n", robots, duration_s, threads,
               Measure(robots, "builtin:idle", duration_s, true, true, threads, threads > 1), threads > 1 ? "wall" : "CPU");
    return 0;
  }
  if (argc > 2 || (argc == 2 && std::strcmp(argv[1], "--quick") != 0 && std::strcmp(argv[1], "--safety") != 0 &&
                    std::strcmp(argv[1], "--threads") != 0)) {
    fmt::print(stderr,
               "usage: bench_lab_throughput [--quick | --safety | --threads | --one ROBOTS SECONDS [THREADS]]\n"
               "  (no option: every table, a few minutes; docs/lab.md, \"Speed\")\n");
    return 2;
  }
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const bool safety_only = argc > 1 && std::strcmp(argv[1], "--safety") == 0;
  if (argc > 1 && std::strcmp(argv[1], "--threads") == 0) {
    PrintThreads(false);
    return 0;
  }
  fmt::print("simulated lab throughput, robot-seconds per CPU-second on one core, safety filter on (issue 15's\n"
             "targets: >= 20,000 at 100 robots; 1000 robots >= 10x real time)\n\n");
  fmt::print("{:<16} {:>8} {:>12} {:>27} {:>10}\n", "app", "robots", "sim seconds", "robot-s per CPU-s, best of 3",
             "x real time");
  struct Case {
    const char* app;
    int robots;
    double duration_s;
  };
  const Case cases[] = {
      {"builtin:idle", 10, quick ? 10.0 : 60.0},  {"builtin:idle", 100, quick ? 2.0 : 10.0},
      {"builtin:idle", 1000, quick ? 0.5 : 3.0},  {"builtin:circle", 10, quick ? 10.0 : 60.0},
      {"builtin:circle", 100, quick ? 2.0 : 10.0},
  };
  // Each case runs three times; the best run is the machine's figure (the
  // others lost time to whatever else the machine was doing), the median
  // shows the spread.
  constexpr int kRepeats = 3;
  double idle_100 = 0;
  double circle_100 = 0;
  for (const Case& c : cases) {
    if (safety_only) break;
    std::vector<double> rates;
    for (int run = 0; run < kRepeats; ++run) rates.push_back(Measure(c.robots, c.app, c.duration_s, true));
    std::sort(rates.begin(), rates.end());
    fmt::print("{:<16} {:>8} {:>12.1f} {:>10.0f} (median {:>6.0f}) {:>10.1f}\n", c.app, c.robots, c.duration_s,
               rates.back(), rates[kRepeats / 2], rates.back() / c.robots);
    if (c.robots == 100) (std::strcmp(c.app, "builtin:idle") == 0 ? idle_100 : circle_100) = rates.back();
  }
  if (idle_100 > 0 && circle_100 > 0) {
    // The app's own work, apart from the platform's: CPU time per robot-second
    // with builtin:circle minus with builtin:idle (each robot computes the
    // matching on its own map once an epoch).
    fmt::print("builtin:circle's own work at 100 robots: {:.0f} us of CPU per robot-second (its matching)\n",
               1e6 * (1.0 / circle_100 - 1.0 / idle_100));
  }

  fmt::print("\nthe safety filter's cost at 100 robots (best of 3 each; runs alternate on and off)\n\n");
  fmt::print("{:<16} {:>8} {:>14} {:>14} {:>8}\n", "app", "robots", "filter on", "filter off", "cost");
  for (const char* app : {"builtin:idle", "builtin:circle", "builtin:gather"}) {
    const double duration_s = quick ? 2.0 : 10.0;
    double best_on = 0;
    double best_off = 0;
    for (int run = 0; run < kRepeats; ++run) {
      best_on = std::max(best_on, Measure(100, app, duration_s, true, true));
      best_off = std::max(best_off, Measure(100, app, duration_s, true, false));
    }
    fmt::print("{:<16} {:>8} {:>14.0f} {:>14.0f} {:>7.1f}%\n", app, 100, best_on, best_off,
               100.0 * (best_off / best_on - 1.0));
  }
  if (!safety_only) PrintThreads(quick);
  return 0;
}
