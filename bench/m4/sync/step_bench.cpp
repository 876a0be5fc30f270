// Instructions per synchronizer step (sync::Step) on the emulated Cortex-M4
// (qemu mps2-an386, -icount shift=0: one counted cycle per executed
// instruction), in a swarm of 32 robots that all hear each other: 32
// synchronizers stepped in lockstep for kRounds rounds, each with the 31
// beacons the others sent the round before, the maneuver finishing after 20
// rounds of PROGRESS as the runtime's default. Robot 0's step is measured
// every round: the mean, the worst, and the worst of the rounds that start
// an epoch (they build the LDMap). The counter ticks in steps of 40.
#include <cstdint>
#include <cstdio>
#include <span>

#include "syrof/board/cycles.h"
#include "syrof/sync/config.h"
#include "syrof/sync/ldmap.h"
#include "syrof/sync/synchronizer.h"

namespace {

using namespace syrof;

constexpr uint16_t kRobots = 32;
constexpr int kRounds = 600;
constexpr uint16_t kManeuverRounds = 20;

sync::SyncConfig configs[kRobots];
sync::SyncState states[kRobots];
sync::LDMap maps[kRobots];
sync::StepOutput outputs[kRobots];
wire::Beacon sent[kRobots];  // last round's beacons
bool sending[kRobots];
uint16_t progress_rounds[kRobots];

}  // namespace

int main() {
  board::cycle_counter_start();
  for (uint16_t id = 0; id < kRobots; ++id) {
    configs[id] = sync::SyncConfig::ForSwarm(kRobots, id);
    wire::Snapshot start{};
    start.x_mm = static_cast<int16_t>(100 * id);
    states[id] = sync::InitialState(configs[id], start);
    sent[id] = sync::MakeBeacon(configs[id], states[id]);
    sending[id] = true;
  }
  uint64_t total = 0, worst = 0, worst_epoch_start = 0;
  int measured = 0, epochs = 0, cooperative = 0;
  const wire::Beacon* received[kRobots];
  for (int round = 0; round < kRounds; ++round) {
    for (uint16_t id = 0; id < kRobots; ++id) {
      size_t count = 0;
      for (uint16_t other = 0; other < kRobots; ++other) {
        if (other != id && sending[other]) received[count++] = &sent[other];
      }
      sync::StepInput input;
      input.own_snapshot = states[id].live;
      input.maneuver_finished = progress_rounds[id] >= kManeuverRounds;
      const uint64_t begin = board::cycle_counter_read();
      sync::Step(configs[id], states[id], std::span<const wire::Beacon* const>(received, count), input, outputs[id],
                 maps[id]);
      const uint64_t cycles = board::cycle_counter_read() - begin;
      if (id == 0 && count == kRobots - 1) {
        total += cycles;
        ++measured;
        if (cycles > worst) worst = cycles;
        if (outputs[0].epoch_started && cycles > worst_epoch_start) worst_epoch_start = cycles;
      }
      if (outputs[id].epoch_started) progress_rounds[id] = 0;
      if (states[id].phase == wire::Phase::kProgress) ++progress_rounds[id];
      if (id == 0 && outputs[0].epoch_started) {
        ++epochs;
        if (maps[0].mode == wire::Mode::kCooperative) ++cooperative;
      }
    }
    for (uint16_t id = 0; id < kRobots; ++id) {
      sending[id] = outputs[id].send;
      if (outputs[id].send) sent[id] = outputs[id].beacon;
    }
  }
  std::printf("synchronizer step on Cortex-M4 soft-float, %u robots, 31 beacons a round, %d rounds\n",
              unsigned{kRobots}, kRounds);
  std::printf("  mean step:                        %8llu instructions\n",
              static_cast<unsigned long long>(measured > 0 ? total / static_cast<uint64_t>(measured) : 0));
  std::printf("  worst step:                       %8llu instructions\n", static_cast<unsigned long long>(worst));
  std::printf("  worst step starting an epoch:     %8llu instructions\n",
              static_cast<unsigned long long>(worst_epoch_start));
  std::printf("  robot 0: %d epochs started, %d COOPERATIVE\n", epochs, cooperative);
  return epochs > 0 && cooperative > 0 ? 0 : 1;
}
