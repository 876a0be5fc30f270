// The app host's figures (docs/app_host.md):
//   1. one callback's round trip through syrof-app-host (NewRound of a
//      10-member map, the app doing a little work), p50 and p99;
//   2. starting one sandboxed host (spawn, hardening, library loaded, its
//      hello received), p50 and p99;
//   3. lab throughput with the app as a library in one host per robot
//      against the same C code linked in (CAbiApp), 10 and 100 robots: wall
//      time of the run phase and of the whole run (hosts started and
//      stopped), and the whole run's CPU time (the hosts' included).
// Timings are wall-clock unless said: on a shared machine they move with its
// load, so the throughput takes the best of a few runs.
//
// Usage: bench_app_host [--quick | --robots N]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <sys/resource.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "syrof/app/c_abi_app.h"
#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

extern "C" const syrof_app_descriptor* bench_app_entry(void);

namespace {

using namespace syrof;
using Clock = std::chrono::steady_clock;

double Microseconds(Clock::duration duration) { return std::chrono::duration<double, std::micro>(duration).count(); }

double Percentile(std::vector<double> values, double fraction) {
  std::sort(values.begin(), values.end());
  return values[static_cast<size_t>(fraction * static_cast<double>(values.size() - 1))];
}

class NullPlatform final : public app::Platform {
 public:
  syrof_app_status SendMessageData(std::span<const uint8_t> payload) override {
    return payload.size() > SYROF_APP_MAX_PAYLOAD_BYTES ? SYROF_APP_PAYLOAD_TOO_LONG : SYROF_APP_OK;
  }
  syrof_queries_workspace* queries_workspace() override { return nullptr; }
};

app_host::HostOptions Options() {
  app_host::HostOptions options;
  options.library_path = SYROF_BENCH_APP_LIBRARY;
  return options;
}

void RoundTrip(int calls) {
  NullPlatform platform;
  std::unique_ptr<app::App> app = app_host::MakeHostedApp(Options(), 0);
  syrof_app_info info{};
  info.abi_version = SYROF_APP_ABI_VERSION;
  info.swarm_size = 10;
  uint8_t state = 0;
  if (!app->Init(info, platform, state).ok()) {
    fmt::print(stderr, "the bench app did not start\n");
    std::exit(1);
  }
  syrof_member_state members[10] = {};
  for (uint16_t id = 0; id < 10; ++id) {
    members[id].id = id;
    members[id].x_mm = static_cast<int16_t>(100 * id);
    members[id].y_mm = static_cast<int16_t>(37 * id);
  }
  std::vector<double> samples;
  samples.reserve(static_cast<size_t>(calls));
  for (int i = 0; i < calls + 100; ++i) {
    const syrof_ldmap map{static_cast<uint16_t>(i), SYROF_MODE_COOPERATIVE, 3, 10, members};
    syrof_car_command command{};
    const Clock::time_point start = Clock::now();
    const app::CallStatus status = app->NewRound(command, map, state, static_cast<uint32_t>(i));
    const Clock::time_point end = Clock::now();
    if (!status.ok()) {
      fmt::print(stderr, "call failed: {}\n", status.detail());
      std::exit(1);
    }
    if (i >= 100) samples.push_back(Microseconds(end - start));  // the first 100 warm up
  }
  // The same call linked in, for scale.
  NullPlatform in_process_platform;
  app::CAbiApp linked(*bench_app_entry());
  (void)linked.Init(info, in_process_platform, state);
  std::vector<double> linked_samples;
  for (int i = 0; i < calls; ++i) {
    const syrof_ldmap map{static_cast<uint16_t>(i), SYROF_MODE_COOPERATIVE, 3, 10, members};
    syrof_car_command command{};
    const Clock::time_point start = Clock::now();
    (void)linked.NewRound(command, map, state, static_cast<uint32_t>(i));
    linked_samples.push_back(Microseconds(Clock::now() - start));
  }
  fmt::print("callback round trip (NewRound, 10 members), {} calls:\n", calls);
  fmt::print("  through the host   p50 {:7.1f} us   p99 {:7.1f} us\n", Percentile(samples, 0.5),
             Percentile(samples, 0.99));
  fmt::print("  linked in          p50 {:7.1f} us   p99 {:7.1f} us\n", Percentile(linked_samples, 0.5),
             Percentile(linked_samples, 0.99));
}

void StartCost(int starts) {
  std::vector<double> samples;
  for (int i = 0; i < starts; ++i) {
    const Clock::time_point start = Clock::now();
    std::unique_ptr<app::App> app = app_host::MakeHostedApp(Options(), static_cast<uint16_t>(i));
    (void)app->name();  // waits for the hello: the library is loaded
    samples.push_back(Microseconds(Clock::now() - start) / 1000.0);
  }
  fmt::print("starting one sandboxed host (spawn to hello), {} starts:\n", starts);
  fmt::print("  p50 {:6.2f} ms   p99 {:6.2f} ms\n", Percentile(samples, 0.5), Percentile(samples, 0.99));
}

std::string Scenario(int robots, double duration_s) {
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(robots))));
  const double arena_m = side + 1.0;
  return fmt::format(R"(name: bench_app_host_{robots}
seed: 1
arena:
  width_m: {arena}
  height_m: {arena}
  anchors:
    - {{x_m: 0, y_m: 0, z_m: 0}}
    - {{x_m: {arena}, y_m: {arena}, z_m: 0}}
    - {{x_m: 0, y_m: {arena}, z_m: 2}}
    - {{x_m: {arena}, y_m: 0, z_m: 2}}
robots: {{count: {robots}, kind: omni, placement: grid, spacing_m: 1.0}}
timing: {{radio_round_s: 0.05, app_round_s: 1.0, duration_s: {duration}}}
channel: {{model: iid, loss: 0.05}}
app: builtin:idle
)",
                     fmt::arg("robots", robots), fmt::arg("arena", arena_m), fmt::arg("duration", duration_s));
}

struct Timing {
  double start_s = 0;  // the Simulation built and every app loaded
  double run_s = 0;    // the scenario run and finished
  double stop_s = 0;   // the Simulation destroyed (the hosts killed and reaped)
  double cpu_s = 0;    // CPU of the whole run: this process and its (reaped) hosts
  std::string metrics;
  double total() const { return start_s + run_s + stop_s; }
};

double CpuSeconds(int who) {
  rusage usage{};
  getrusage(who, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
}

// Wall seconds of one run, by phase.
Timing RunWall(int robots, double duration_s, bool hosted) {
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioText(Scenario(robots, duration_s), "bench");
  if (!loaded.ok()) {
    fmt::print(stderr, "bench scenario refused: {}\n", loaded.error->ToString());
    std::exit(1);
  }
  const app_host::HostOptions options = Options();
  std::vector<app::App*> apps;
  lab::sim::SimulationOptions sim_options;
  sim_options.apps.source = "bench";
  if (hosted) {
    sim_options.apps.factory = [&options, &apps](uint16_t id) {
      std::unique_ptr<app::App> app = app_host::MakeHostedApp(options, id);
      apps.push_back(app.get());
      return app;
    };
  } else {
    sim_options.apps.factory = [](uint16_t) { return std::make_unique<app::CAbiApp>(*bench_app_entry()); };
  }
  Timing timing;
  const double cpu_before = CpuSeconds(RUSAGE_SELF) + CpuSeconds(RUSAGE_CHILDREN);
  Clock::time_point start = Clock::now();
  auto simulation = std::make_unique<lab::sim::Simulation>(*loaded.scenario, sim_options);
  for (app::App* app : apps) (void)app->name();  // waits for each host's hello
  timing.start_s = Microseconds(Clock::now() - start) / 1e6;
  start = Clock::now();
  simulation->RunUntil(duration_s);
  timing.metrics = simulation->Finish(0.0).metrics_json;
  timing.run_s = Microseconds(Clock::now() - start) / 1e6;
  start = Clock::now();
  simulation.reset();
  timing.stop_s = Microseconds(Clock::now() - start) / 1e6;
  timing.cpu_s = CpuSeconds(RUSAGE_SELF) + CpuSeconds(RUSAGE_CHILDREN) - cpu_before;
  return timing;
}

// The best of `repeats` runs each way (a shared machine only adds time).
Timing Best(int robots, double duration_s, bool hosted, int repeats) {
  Timing best = RunWall(robots, duration_s, hosted);
  for (int i = 1; i < repeats; ++i) {
    const Timing next = RunWall(robots, duration_s, hosted);
    best.start_s = std::min(best.start_s, next.start_s);
    best.run_s = std::min(best.run_s, next.run_s);
    best.stop_s = std::min(best.stop_s, next.stop_s);
    best.cpu_s = std::min(best.cpu_s, next.cpu_s);
  }
  return best;
}

void Throughput(int robots, double duration_s, int repeats) {
  const Timing linked = Best(robots, duration_s, false, repeats);
  const Timing hosted = Best(robots, duration_s, true, repeats);
  fmt::print("  {:4d} robots, {:3.0f} s simulated, best of {}{}:\n", robots, duration_s, repeats,
             hosted.metrics == linked.metrics ? "" : "  (METRICS DIFFER)");
  fmt::print("    run phase  wall {:6.3f} s linked in, {:6.3f} s library: {:5.2f}x\n", linked.run_s, hosted.run_s,
             hosted.run_s / linked.run_s);
  fmt::print("    whole run  wall {:6.3f} s linked in, {:6.3f} s library: {:5.2f}x (hosts start {:5.3f} s, stop {:5.3f} s)\n",
             linked.total(), hosted.total(), hosted.total() / linked.total(), hosted.start_s, hosted.stop_s);
  fmt::print("    whole run  CPU  {:6.3f} s linked in, {:6.3f} s library, hosts included: {:5.2f}x\n", linked.cpu_s,
             hosted.cpu_s, hosted.cpu_s / linked.cpu_s);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2 && std::strcmp(argv[1], "--robots") == 0) {
    // One throughput line for a swarm of the given size (scale checks).
    fmt::print("lab run, the same C app as a library (one host per robot) and linked in:\n");
    Throughput(std::atoi(argv[2]), 5, 1);
    return 0;
  }
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  RoundTrip(quick ? 500 : 5000);
  StartCost(quick ? 10 : 100);
  fmt::print("lab run, the same C app as a library (one host per robot) and linked in:\n");
  Throughput(10, quick ? 5 : 60, quick ? 1 : 5);
  Throughput(100, quick ? 2 : 10, quick ? 1 : 3);
  return 0;
}
