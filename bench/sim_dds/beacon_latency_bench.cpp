// Beacon latency over DDS on loopback between two robot processes: one
// BeaconRadio sends a beacon every radio round, another process's
// BeaconRadio receives it; both read CLOCK_MONOTONIC (one host), so the
// one-way latency is arrival minus send. Prints the delivery ratio and the
// latency p50 / p99 / max, then the cost of the sample checks per sample.
//
// Usage: bench_sim_dds_beacon_latency [--rounds N] [--round-ms R] [--robots S]
// (defaults 200 rounds at 50 ms, a swarm of 32 for the beacon's size).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "syrof/sim_dds/beacon_radio.h"
#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/sample_check.h"
#include "syrof/wire/beacon_codec.h"

namespace {

using namespace syrof::sim_dds;

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

BeaconRadioOptions Options(uint16_t self, uint16_t swarm, std::atomic<int64_t>& round) {
  BeaconRadioOptions options;
  options.self = self;
  options.swarm_size = swarm;
  options.current_round = [&round] { return round.load(); };
  return options;
}

// The receiving process: records each round's arrival time and writes them
// (int64 per round, -1 never heard) to `out` when all arrived or at the
// deadline.
int Receive(uint32_t domain, uint16_t swarm, int rounds, int64_t deadline_ns, int out) {
  std::vector<std::atomic<int64_t>> arrival(static_cast<size_t>(rounds));
  for (auto& slot : arrival) slot = -1;
  std::atomic<int> heard{0};
  std::atomic<int64_t> round{-1};
  ParticipantOrError participant = Participant::Create(domain, CycloneOptions{});
  if (!participant.ok()) return 1;
  BeaconRadioOrError radio = BeaconRadio::Create(
      *participant.participant, Options(1, swarm, round), [&](std::span<const uint8_t>, uint16_t, uint32_t r) {
        const int64_t now = NowNs();
        if (r < arrival.size()) {
          arrival[r] = now;
          ++heard;
        }
      });
  if (!radio.ok()) return 1;
  while (heard < rounds && NowNs() < deadline_ns) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::vector<int64_t> times;
  for (auto& slot : arrival) times.push_back(slot.load());
  const auto bytes = static_cast<ssize_t>(times.size() * sizeof(int64_t));
  return write(out, times.data(), static_cast<size_t>(bytes)) == bytes ? 0 : 1;
}

double Percentile(std::vector<int64_t> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(p * static_cast<double>(values.size())));
  return static_cast<double>(values[index]);
}

void SampleCheckCost(uint16_t swarm) {
  std::vector<uint8_t> bytes(syrof::wire::EncodedSize(swarm));
  syrof::wire::Beacon beacon;
  beacon.robot_id = 2;
  (void)syrof::wire::Encode(beacon, swarm, bytes);
  SampleFilter filter(0, swarm);
  constexpr int kSamples = 1'000'000;
  const int64_t start = NowNs();
  for (int i = 0; i < kSamples; ++i) {
    syrof::wire::Beacon out;
    (void)filter.Check(2, static_cast<uint32_t>(i), bytes, i, out);
  }
  const double ns = static_cast<double>(NowNs() - start) / kSamples;
  std::printf("sample checks (accepted beacon, %u robots): %.0f ns per sample (%llu accepted)\n", swarm, ns,
              static_cast<unsigned long long>(filter.counters().accepted()));
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 200;
  int round_ms = 50;
  int swarm = 32;
  for (int i = 1; i + 1 < argc; i += 2) {
    const int value = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--rounds") == 0) rounds = value;
    else if (std::strcmp(argv[i], "--round-ms") == 0) round_ms = value;
    else if (std::strcmp(argv[i], "--robots") == 0) swarm = value;
  }
  if (rounds < 1 || round_ms < 1 || swarm < 2 || swarm > kMaxDdsSwarm) {
    std::fprintf(stderr, "usage: bench_sim_dds_beacon_latency [--rounds N] [--round-ms R] [--robots S]\n");
    return 2;
  }
  const uint32_t domain = DomainIdForRun(static_cast<uint64_t>(getpid()) << 20);
  int pipe_ends[2];
  if (pipe(pipe_ends) != 0) return 1;
  const int64_t deadline = NowNs() + (static_cast<int64_t>(rounds) * round_ms + 10'000) * 1'000'000;
  // Fork before any DDS entity exists: the child starts Cyclone afresh.
  const pid_t child = fork();
  if (child == 0) {
    close(pipe_ends[0]);
    _exit(Receive(domain, static_cast<uint16_t>(swarm), rounds, deadline, pipe_ends[1]));
  }
  close(pipe_ends[1]);

  std::atomic<int64_t> round{0};
  std::vector<int64_t> sent(static_cast<size_t>(rounds), 0);
  {
    ParticipantOrError participant = Participant::Create(domain, CycloneOptions{});
    if (!participant.ok()) return 1;
    BeaconRadioOrError radio = BeaconRadio::Create(*participant.participant,
                                                   Options(0, static_cast<uint16_t>(swarm), round),
                                                   [](std::span<const uint8_t>, uint16_t, uint32_t) {});
    if (!radio.ok()) return 1;
    const int64_t discovery_start = NowNs();
    while (radio.radio->matched_readers() < 1 && NowNs() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    std::printf("discovery: %.1f ms until the receiver's reader matched\n",
                static_cast<double>(NowNs() - discovery_start) * 1e-6);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the receiver's side matches too
    syrof::wire::Beacon beacon;
    beacon.robot_id = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < rounds; ++r) {
      std::this_thread::sleep_until(start + std::chrono::milliseconds(static_cast<int64_t>(r) * round_ms));
      round = r;
      sent[static_cast<size_t>(r)] = NowNs();
      radio.radio->Broadcast(beacon);
    }
    std::vector<int64_t> arrival(static_cast<size_t>(rounds), -1);
    size_t got = 0;
    auto* bytes = reinterpret_cast<char*>(arrival.data());
    const size_t want = arrival.size() * sizeof(int64_t);
    while (got < want) {
      const ssize_t n = read(pipe_ends[0], bytes + got, want - got);
      if (n <= 0) break;
      got += static_cast<size_t>(n);
    }
    int status = 0;
    waitpid(child, &status, 0);
    std::vector<int64_t> latency;
    for (int r = 0; r < rounds; ++r) {
      if (arrival[static_cast<size_t>(r)] >= 0) latency.push_back(arrival[static_cast<size_t>(r)] - sent[static_cast<size_t>(r)]);
    }
    std::printf("beacons over DDS, loopback, 2 processes, %d rounds at %d ms, %u-robot beacon (%zu bytes):\n", rounds,
                round_ms, swarm, syrof::wire::EncodedSize(static_cast<uint16_t>(swarm)));
    std::printf("  delivered %zu of %d (%.1f %%)\n", latency.size(), rounds,
                100.0 * static_cast<double>(latency.size()) / rounds);
    std::printf("  one-way latency: p50 %.0f us, p99 %.0f us, max %.0f us\n", Percentile(latency, 0.5) * 1e-3,
                Percentile(latency, 0.99) * 1e-3, Percentile(latency, 1.0) * 1e-3);
  }
  SampleCheckCost(static_cast<uint16_t>(swarm));
  return 0;
}
