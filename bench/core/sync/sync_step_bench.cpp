// Cost of one synchronizer step per robot against the swarm size, when the
// robot hears every other robot in the round (the worst case for the radio
// part), and the beacon size for that swarm. Each benchmark's argument is the
// swarm size; the "beacon_bytes" counter is the encoded beacon size.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "syrof/sync/synchronizer.h"
#include "syrof/wire/beacon_layout.h"

namespace {

using namespace syrof;

struct Setup {
  sync::SyncConfig config;
  sync::SyncState state;
  std::vector<wire::Beacon> received;
};

// Robot 0 in `phase` of epoch 7 with every robot a member; everyone else's
// beacon of the same phase arrives.
Setup MakeSetup(uint16_t swarm_size, wire::Phase phase) {
  Setup setup;
  setup.config = sync::SyncConfig::ForSwarm(swarm_size, 0);
  setup.state = sync::InitialState(setup.config, wire::Snapshot{});
  setup.state.epoch = 7;
  setup.state.phase = phase;
  for (uint16_t id = 1; id < swarm_size; ++id) {
    wire::Beacon beacon;
    beacon.robot_id = id;
    beacon.epoch = 7;
    beacon.phase = phase;
    beacon.snapshot.x_mm = static_cast<int16_t>(id);
    if (phase == wire::Phase::kVote) {
      beacon.vote_counter = 1;
      beacon.waiting = setup.state.members;
    } else {
      beacon.waiting.set(id);
    }
    setup.received.push_back(beacon);
  }
  return setup;
}

// PROGRESS: the failure detector and membership over every member; the
// state does not change from step to step, so every iteration is alike.
void BM_StepProgress(benchmark::State& state) {
  const auto swarm_size = static_cast<uint16_t>(state.range(0));
  Setup setup = MakeSetup(swarm_size, wire::Phase::kProgress);
  sync::StepOutput out;
  sync::LDMap ldmap;
  const sync::StepInput input;
  for (auto _ : state) {
    sync::Step(setup.config, setup.state, setup.received, input, out, ldmap);
    benchmark::DoNotOptimize(out);
  }
  state.counters["beacon_bytes"] = static_cast<double>(wire::EncodedSize(swarm_size));
  state.counters["ns_per_beacon"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * (swarm_size - 1),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// VOTE, first round: snapshots stored, view compared with every vote. The
// state is restored outside the timing each iteration.
void BM_StepVote(benchmark::State& state) {
  const auto swarm_size = static_cast<uint16_t>(state.range(0));
  Setup setup = MakeSetup(swarm_size, wire::Phase::kWait);
  // Enter VOTE once, then time the step that counts the votes.
  sync::StepOutput out;
  sync::LDMap ldmap;
  sync::Step(setup.config, setup.state, setup.received, sync::StepInput{}, out, ldmap);
  const Setup votes = MakeSetup(swarm_size, wire::Phase::kVote);
  const sync::SyncState voting = setup.state;
  for (auto _ : state) {
    state.PauseTiming();
    setup.state = voting;
    state.ResumeTiming();
    sync::Step(setup.config, setup.state, votes.received, sync::StepInput{}, out, ldmap);
    benchmark::DoNotOptimize(out);
  }
  state.counters["beacon_bytes"] = static_cast<double>(wire::EncodedSize(swarm_size));
}

BENCHMARK(BM_StepProgress)->Arg(8)->Arg(32)->Arg(128)->Arg(1024);
BENCHMARK(BM_StepVote)->Arg(8)->Arg(32)->Arg(128)->Arg(1024);

}  // namespace

BENCHMARK_MAIN();
