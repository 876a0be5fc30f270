// The live page's costs (docs/viewer.md, "Live"): prints figures, asserts
// nothing.
//   1. latency from a recorded round to a browser: a lab run paced to the
//      wall clock (as `syrof run --live`) with one SSE client reading
//      /events; per round, the client's receive time minus the round's `w`
//      (the server's wall clock when it recorded it): p50, p99, max;
//   2. the run's slowdown with 5 SSE clients attached against none: the same
//      run unpaced (as fast as the lab goes, the case most sensitive to the
//      server's cost), wall time, best of three each;
//   3. the same with the run paced (as `syrof run --live` runs it): its
//      wall time against the world time, with no client and with 5 (a
//      paced run that kept up takes its world time, plus the last round).
// `bench_lab_live [ROBOTS [SECONDS]]` (default 20 robots, 20 s of world time).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "sse_client.h"
#include "syrof/lab/live/live_server.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace {

using namespace syrof::lab;
using Clock = std::chrono::steady_clock;
using live::testing::SseClient;
using live::testing::SseEvent;

std::string Scenario(int robots, double duration_s) {
  return fmt::format(R"(name: bench_live_{robots}
seed: 1
robots: {{ count: {robots}, placement: circle, radius_m: 1.5 }}
timing: {{ duration_s: {duration} }}
channel: {{ model: iid, loss: 0.05 }}
app: builtin:circle
)",
                     fmt::arg("robots", robots), fmt::arg("duration", duration_s));
}

// Runs `scenario` with `server` as a sink (none if null), paced or not;
// the wall seconds.
double RunWith(const scenario::Scenario& scenario, live::LiveServer* server, bool paced) {
  sim::SimulationOptions options;
  if (server != nullptr) options.sinks = {server};
  sim::Simulation simulation(scenario, options);
  const Clock::time_point start = Clock::now();
  if (paced) {
    const double step_s = scenario.timing.radio_round_s;
    for (int64_t round = 1;; ++round) {
      const double until_s = std::min(scenario.timing.duration_s, static_cast<double>(round) * step_s);
      simulation.RunUntil(until_s);
      std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(until_s)));
      if (until_s >= scenario.timing.duration_s) break;
    }
  }
  simulation.RunUntil(scenario.timing.duration_s);
  simulation.Finish(0);
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// `count` clients reading /events until the end event, on threads.
struct Readers {
  Readers(int port, int count) {
    for (int i = 0; i < count; ++i) {
      clients.push_back(std::make_unique<SseClient>());
      clients.back()->Get(port, "/events");
    }
    for (auto& client : clients) {
      threads.emplace_back([&client] {
        client->ReadUntil(
            [](const std::vector<SseEvent>& events) { return !events.empty() && events.back().name == "end"; },
            std::chrono::minutes(10));
      });
    }
  }
  ~Readers() {
    for (auto& thread : threads) thread.join();
  }
  std::vector<std::unique_ptr<SseClient>> clients;
  std::vector<std::thread> threads;
};

void WaitForClients(const live::LiveServer& server, size_t count) {
  while (server.clients() < count) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(p * static_cast<double>(values.size())))];
}

}  // namespace

int main(int argc, char** argv) {
  const int robots = argc > 1 ? std::atoi(argv[1]) : 20;
  const double duration_s = argc > 2 ? std::atof(argv[2]) : 20;
  const scenario::LoadResult loaded = scenario::LoadScenarioText(Scenario(robots, duration_s), "bench_live.yaml");
  if (!loaded.ok()) {
    fmt::print(stderr, "bench_lab_live: {}\n", loaded.error->ToString());
    return 1;
  }
  const scenario::Scenario& scenario = *loaded.scenario;
  fmt::print("bench_lab_live: {} robots, {:.0f} s of world time, 50 ms radio rounds, builtin:circle\n", robots,
             duration_s);

  // 1. Latency, paced.
  {
    live::LiveServer server;
    if (server.Start("127.0.0.1", 0)) return 1;
    Readers reader(server.listening().port, 1);
    WaitForClients(server, 1);
    RunWith(scenario, &server, true);
    reader.threads[0].join();
    reader.threads.clear();
    const SseClient& client = *reader.clients[0];
    std::vector<double> latency_ms;
    for (size_t i = 0; i < client.events().size(); ++i) {
      const SseEvent& event = client.events()[i];
      if (event.name != "round") continue;
      const size_t at = event.data.find("\"w\":");
      const int64_t recorded_us = std::strtoll(event.data.c_str() + at + 4, nullptr, 10);
      latency_ms.push_back(static_cast<double>(client.received_us()[i] - recorded_us) / 1000.0);
    }
    fmt::print("  latency, recorded round to an SSE client (paced run, {} rounds): p50 {:.2f} ms, p99 {:.2f} ms, "
               "max {:.2f} ms\n",
               latency_ms.size(), Percentile(latency_ms, 0.5), Percentile(latency_ms, 0.99),
               latency_ms.empty() ? 0.0 : *std::max_element(latency_ms.begin(), latency_ms.end()));
  }

  // 2. Slowdown with 5 clients, unpaced (10x the world time), best of
  // three each, alternating.
  scenario::Scenario longer = scenario;
  longer.timing.duration_s = 10 * duration_s;
  double bare_s = 1e9, none_s = 1e9, five_s = 1e9;
  for (int trial = 0; trial < 3; ++trial) {
    bare_s = std::min(bare_s, RunWith(longer, nullptr, false));
    {
      live::LiveServer server;
      if (server.Start("127.0.0.1", 0)) return 1;
      none_s = std::min(none_s, RunWith(longer, &server, false));
    }
    {
      live::LiveServer server;
      if (server.Start("127.0.0.1", 0)) return 1;
      Readers readers(server.listening().port, 5);
      WaitForClients(server, 5);
      five_s = std::min(five_s, RunWith(longer, &server, false));
    }
  }
  fmt::print("  unpaced run of {:.0f} s, wall time (best of 3): no live server {:.3f} s, live server and no client "
             "{:.3f} s, 5 SSE clients {:.3f} s: slowdown with 5 clients x{:.3f} against none (x{:.3f} against no "
             "server)\n",
             longer.timing.duration_s, bare_s, none_s, five_s, five_s / none_s, five_s / bare_s);

  // 3. Paced, as `--live` runs: does the run keep the wall clock's pace
  // with 5 browsers reading?
  double paced_none_s = 0, paced_five_s = 0;
  {
    live::LiveServer server;
    if (server.Start("127.0.0.1", 0)) return 1;
    paced_none_s = RunWith(scenario, &server, true);
  }
  {
    live::LiveServer server;
    if (server.Start("127.0.0.1", 0)) return 1;
    Readers readers(server.listening().port, 5);
    WaitForClients(server, 5);
    paced_five_s = RunWith(scenario, &server, true);
  }
  fmt::print("  paced run of {:.0f} s (as --live): wall time {:.3f} s with no client, {:.3f} s with 5 SSE clients "
             "(x{:.4f} and x{:.4f} of the world time)\n",
             duration_s, paced_none_s, paced_five_s, paced_none_s / duration_s, paced_five_s / duration_s);
  return 0;
}
