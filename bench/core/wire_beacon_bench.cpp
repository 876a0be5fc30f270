// Beacon encode and decode cost, and the encoded size, per swarm size.
// Each benchmark's argument is the swarm size; the "bytes" counter is the
// encoded size for it.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "syrof/wire/beacon_codec.h"

namespace {

using syrof::wire::Beacon;
using syrof::wire::kMaxBeaconBytes;
using syrof::wire::kMaxSwarmSize;

// A beacon as the synchronizer sends it in WAIT: half the swarm known to be
// waiting, a moving pose and a full payload.
Beacon typical_beacon(uint16_t swarm_size) {
  Beacon beacon;
  beacon.robot_id = static_cast<uint16_t>(swarm_size - 1);
  beacon.epoch = 4711;
  beacon.phase = syrof::wire::Phase::kWait;
  beacon.mode = syrof::wire::Mode::kCooperative;
  beacon.vote_counter = 0;
  for (uint16_t member = 0; member < swarm_size; member += 2) beacon.waiting.set(member);
  beacon.snapshot.x_mm = 1234;
  beacon.snapshot.y_mm = -2345;
  beacon.snapshot.heading_mrad = 1571;
  beacon.snapshot.vx_mm_s = 150;
  beacon.snapshot.vy_mm_s = -75;
  const std::array<uint8_t, syrof::wire::kMaxPayloadBytes> payload = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  if (beacon.snapshot.SetPayload(payload) != syrof::wire::WireError::kOk) std::abort();
  return beacon;
}

uint16_t swarm_size_of(const benchmark::State& state) {
  return static_cast<uint16_t>(state.range(0));
}

void BM_BeaconEncode(benchmark::State& state) {
  const uint16_t swarm_size = swarm_size_of(state);
  const Beacon beacon = typical_beacon(swarm_size);
  std::array<uint8_t, kMaxBeaconBytes> buffer{};
  for (auto _ : state) {
    benchmark::DoNotOptimize(beacon);
    const auto size = syrof::wire::Encode(beacon, swarm_size, buffer);
    benchmark::DoNotOptimize(size);
    benchmark::ClobberMemory();
  }
  state.counters["bytes"] = static_cast<double>(syrof::wire::EncodedSize(swarm_size));
}

void BM_BeaconDecode(benchmark::State& state) {
  const uint16_t swarm_size = swarm_size_of(state);
  std::array<uint8_t, kMaxBeaconBytes> buffer{};
  const auto size = syrof::wire::Encode(typical_beacon(swarm_size), swarm_size, buffer);
  if (!size.ok()) std::abort();
  const std::span<const uint8_t> encoding = std::span<const uint8_t>(buffer).first(size.value());
  for (auto _ : state) {
    benchmark::DoNotOptimize(encoding.data());
    const auto beacon = syrof::wire::Decode(encoding, swarm_size);
    benchmark::DoNotOptimize(beacon);
  }
  state.counters["bytes"] = static_cast<double>(size.value());
}

void swarm_sizes(benchmark::internal::Benchmark* benchmark) {
  for (const int swarm_size : {8, 32, 128, 1024}) {
    if (swarm_size <= kMaxSwarmSize) benchmark->Arg(swarm_size);
  }
}

BENCHMARK(BM_BeaconEncode)->Apply(swarm_sizes);
BENCHMARK(BM_BeaconDecode)->Apply(swarm_sizes);

}  // namespace
