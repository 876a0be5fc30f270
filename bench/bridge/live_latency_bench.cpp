// From a beacon to the live page (docs/bridge.md, "The live page"): prints
// figures, asserts nothing. A base station (bridge::BaseStation, as
// `syrof-bridge --live` wires it) feeds a LiveServer; one SSE client reads
// /events as a browser does. Every 50 ms radio round each of ROBOTS robots'
// beacons arrives, at its own offset in the round (as real robots' do,
// spread over the round), the bridge ends its rounds on the wall clock as
// `syrof-bridge` does. Each beacon of robot 0 carries a position of its
// own, so the first round event showing it dates the beacon's arrival at
// the browser's stream. Latency = that event's receipt (the client's
// clock) minus the instant the beacon's bytes were handed to the bridge:
// up to one round of batching (a round is sent when it ends) plus the
// server. The page then draws at most every 100 ms (viewer.js), which is
// not counted here.
//   bench_bridge_live_latency [ROBOTS [ROUNDS]]   (default 4 robots, 400 rounds: 20 s)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "bridge_test_support.h"
#include "sse_client.h"
#include "syrof/bridge/base_station.h"
#include "syrof/lab/live/live_server.h"

namespace {

using namespace syrof;
using Clock = std::chrono::system_clock;

int64_t NowUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(p * static_cast<double>(values.size())))];
}

}  // namespace

int main(int argc, char** argv) {
  const auto robots = static_cast<uint16_t>(std::clamp(argc > 1 ? std::atoi(argv[1]) : 4, 1, 32));
  const int rounds = std::max(10, argc > 2 ? std::atoi(argv[2]) : 400);
  constexpr int64_t kRoundUs = 50'000;

  lab::live::LiveServer server;
  if (const auto error = server.Start("127.0.0.1", 0)) {
    fmt::print(stderr, "bench_bridge_live_latency: {}\n", error->ToString());
    return 1;
  }
  bridge::StationConfig config;
  bridge::BaseStation station(config, bridge::testing::HeaderFor(robots), {&server}, {});

  lab::live::testing::SseClient client;
  client.Get(server.listening().port, "/events");
  while (server.clients() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::thread reader([&client] {
    client.ReadUntil([](const auto& events) { return !events.empty() && events.back().name == "end"; },
                     std::chrono::minutes(10));
  });

  // Robot 0's beacon of round r says x = 1000 + r mm; when it was pushed.
  std::map<int64_t, int64_t> pushed_us;
  const int64_t start_us = NowUs();
  for (int round = 0; round < rounds; ++round) {
    for (uint16_t robot = 0; robot < robots; ++robot) {
      // Spread over the round's first 40 ms, robot by robot.
      const int64_t at_us = start_us + round * kRoundUs + 2'000 + robot * (38'000 / robots);
      std::this_thread::sleep_for(std::chrono::microseconds(std::max<int64_t>(0, at_us - NowUs())));
      wire::Beacon beacon = bridge::testing::MakeBeacon(robot, static_cast<uint16_t>(1 + round / 20));
      if (robot == 0) beacon.snapshot.x_mm = static_cast<int16_t>(1000 + round);
      const std::vector<uint8_t> frame =
          bridge::testing::ReceivedFrame(bridge::testing::EncodeBeacon(beacon, robots), static_cast<uint8_t>(round));
      if (robot == 0) pushed_us[1000 + round] = NowUs();
      station.Push(frame);
    }
    const int64_t end_us = start_us + (round + 1) * kRoundUs;
    std::this_thread::sleep_for(std::chrono::microseconds(std::max<int64_t>(0, end_us - NowUs())));
    station.EndRound((round + 1) * kRoundUs * 1000);
  }
  station.Finish(true);
  reader.join();

  std::vector<double> latency_ms;
  std::vector<double> server_ms;
  int64_t last_x = -1;
  for (size_t i = 0; i < client.events().size(); ++i) {
    const auto& event = client.events()[i];
    if (event.name != "round") continue;
    const nlohmann::json data = nlohmann::json::parse(event.data, nullptr, false);
    if (data.is_discarded() || !data.contains("f") || data["f"].empty()) continue;
    const int64_t x = data["f"][0][2].get<int64_t>();
    if (x == last_x) continue;
    last_x = x;
    const auto pushed = pushed_us.find(x);
    if (pushed == pushed_us.end()) continue;
    latency_ms.push_back(static_cast<double>(client.received_us()[i] - pushed->second) / 1000.0);
    server_ms.push_back(static_cast<double>(client.received_us()[i] - data["w"].get<int64_t>()) / 1000.0);
  }
  fmt::print("bench_bridge_live_latency: {} robots, {} rounds of 50 ms, robot 0's beacon at 2 ms into each round\n",
             robots, rounds);
  fmt::print("  beacon to the live stream ({} beacons): p50 {:.2f} ms, p99 {:.2f} ms, max {:.2f} ms\n",
             latency_ms.size(), Percentile(latency_ms, 0.5), Percentile(latency_ms, 0.99),
             latency_ms.empty() ? 0.0 : *std::max_element(latency_ms.begin(), latency_ms.end()));
  fmt::print("  of which the server (round recorded to the client): p50 {:.2f} ms, p99 {:.2f} ms; the rest is the "
             "round's batching (a round goes out when it ends: 48 ms for this beacon)\n",
             Percentile(server_ms, 0.5), Percentile(server_ms, 0.99));
  fmt::print("  (the page draws at most every 100 ms on top: viewer.js)\n");
  return 0;
}
