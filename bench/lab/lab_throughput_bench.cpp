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
// follows: 100 and 1000 robots on 1, 2 and 4 threads, in wall time (CPU time
// adds up over threads), in rounds that run each in turn; a speed-up is the
// median over rounds of the round's N-thread rate over its 1-thread rate (a
// machine shared with others drifts between rounds more than within one).
// Beside them, what the machine gives two independent copies of the
// 1-thread run started together (two processes, from the first start to the
// last end) over one copy alone: no program can beat that here, so the
// 2-thread speed-up reads against it.
//
// Usage: bench_lab_throughput [--quick | --safety | --threads [ROUNDS] | --one ROBOTS SECONDS [THREADS]]
//   --quick: shorter runs, for CI smoke; --safety: only the safety filter's
//   table; --threads: only the thread mode's table, over ROUNDS rounds
//   (default 5; 3 in the full run); --one: a single run of
//   builtin:idle with the safety filter on, for profilers (valgrind
//   --tool=callgrind, perf record), printing its figure (per wall second
//   when THREADS > 1).
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

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

// Two copies of a 1-thread run, in two processes: each builds its
// simulation, both start running together, and the figure is their
// robot-seconds over the wall time from the first start to the last end.
double TwoCopies(int robots, double duration_s) {
  int ready[2];
  int go[2];
  int report[2];
  if (pipe(ready) != 0 || pipe(go) != 0 || pipe(report) != 0) {
    fmt::print(stderr, "bench: pipe failed\n");
    std::exit(1);
  }
  pid_t children[2];
  for (pid_t& child : children) {
    child = fork();
    if (child < 0) {
      fmt::print(stderr, "bench: fork failed\n");
      std::exit(1);
    }
    if (child != 0) continue;
    const scenario::LoadResult loaded =
        scenario::LoadScenarioText(StandardScenario(robots, "builtin:idle", duration_s), "bench");
    if (!loaded.ok()) _exit(1);
    std::ostringstream replay_bytes;
    sim::SimulationOptions options;
    options.replay = &replay_bytes;
    sim::Simulation simulation(*loaded.scenario, options);
    char byte = 0;
    if (write(ready[1], &byte, 1) != 1 || read(go[0], &byte, 1) != 1) _exit(1);
    double interval[2];
    interval[0] = WallSeconds();
    simulation.RunUntil(duration_s);
    interval[1] = WallSeconds();
    (void)simulation.Finish(interval[1] - interval[0]);
    _exit(write(report[1], interval, sizeof interval) == static_cast<ssize_t>(sizeof interval) ? 0 : 1);
  }
  char bytes[2] = {0, 0};
  if (read(ready[0], bytes, 1) != 1 || read(ready[0], bytes, 1) != 1 || write(go[1], bytes, 2) != 2) {
    fmt::print(stderr, "bench: a copy did not start\n");
    std::exit(1);
  }
  double first_start = 0;
  double last_end = 0;
  for (int copy = 0; copy < 2; ++copy) {
    double interval[2];
    if (read(report[0], interval, sizeof interval) != static_cast<ssize_t>(sizeof interval)) {
      fmt::print(stderr, "bench: a copy did not report\n");
      std::exit(1);
    }
    first_start = copy == 0 ? interval[0] : std::min(first_start, interval[0]);
    last_end = std::max(last_end, interval[1]);
  }
  for (const int fd : {ready[0], ready[1], go[0], go[1], report[0], report[1]}) close(fd);
  for (const pid_t child : children) waitpid(child, nullptr, 0);
  return 2.0 * robots * duration_s / (last_end - first_start);
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The thread mode's table (see the top of the file).
void PrintThreads(bool quick, int rounds) {
  fmt::print("\nthe thread mode (--threads), builtin:idle, robot-s per wall second; {} rounds, each running 1, 2 and\n"
             "4 threads and two copies in turn: the best rate, and the median over rounds of each round's ratio\n"
             "to its 1-thread run (two copies: two 1-thread runs at once in two processes; 2/copies: the 2-thread\n"
             "ratio over the two copies', what the threads get of what this machine gives two programs)\n\n",
             rounds);
  fmt::print("{:<7} {:>5} {:>8} {:>8} {:>6} {:>8} {:>6} {:>8} {:>6} {:>10}\n", "robots", "sim s", "1 thread",
             "2 thr.", "x", "4 thr.", "x", "copies", "x", "2/copies");
  struct Case {
    int robots;
    double duration_s;
  };
  for (const Case c : {Case{100, quick ? 2.0 : 10.0}, Case{1000, quick ? 0.5 : 3.0}}) {
    double best[4] = {0, 0, 0, 0};
    std::vector<double> ratios[3];
    std::vector<double> efficiency;
    for (int round = 0; round < rounds; ++round) {
      const double one = Measure(c.robots, "builtin:idle", c.duration_s, true, true, 1, true);
      const double two = Measure(c.robots, "builtin:idle", c.duration_s, true, true, 2, true);
      const double four = Measure(c.robots, "builtin:idle", c.duration_s, true, true, 4, true);
      const double copies = TwoCopies(c.robots, c.duration_s);
      const double rates[4] = {one, two, four, copies};
      for (int column = 0; column < 4; ++column) best[column] = std::max(best[column], rates[column]);
      for (int column = 0; column < 3; ++column) ratios[column].push_back(rates[column + 1] / one);
      efficiency.push_back(two / copies);
    }
    fmt::print("{:<7} {:>5.1f} {:>8.0f} {:>8.0f} {:>5.2f}x {:>8.0f} {:>5.2f}x {:>8.0f} {:>5.2f}x {:>10.2f}\n", c.robots,
               c.duration_s, best[0], best[1], Median(ratios[0]), best[2], Median(ratios[1]), best[3],
               Median(ratios[2]), Median(efficiency));
  }
}

int main(int argc, char** argv) {
  if ((argc == 2 || argc == 3) && std::strcmp(argv[1], "--threads") == 0) {
    int rounds = 5;
    const char* end = argc == 3 ? argv[2] + std::strlen(argv[2]) : nullptr;
    if (argc == 3 && std::from_chars(argv[2], end, rounds).ptr != end) rounds = 0;
    if (rounds < 1 || rounds > 100) {
      fmt::print(stderr, "--threads takes ROUNDS from 1 to 100 (default 5)\n");
      return 2;
    }
    PrintThreads(false, rounds);
    return 0;
  }
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
  if (argc > 2 || (argc == 2 && std::strcmp(argv[1], "--quick") != 0 && std::strcmp(argv[1], "--safety") != 0)) {
    fmt::print(stderr,
               "usage: bench_lab_throughput [--quick | --safety | --threads [ROUNDS] | --one ROBOTS SECONDS [THREADS]]\n"
               "  (no option: every table, a few minutes; docs/lab.md, \"Speed\")\n");
    return 2;
  }
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const bool safety_only = argc > 1 && std::strcmp(argv[1], "--safety") == 0;
  fmt::print("simulated lab throughput, robot-seconds per CPU-second on one core, safety filter on (docs/lab.md,\n"
             "\"Speed\": figures measured here; \"What bounds it\": why 20,000 at 100 robots and 10x real time at\n"
             "1000 robots are out of reach on one core)\n\n");
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
  if (!safety_only) PrintThreads(quick, 3);
  return 0;
}
