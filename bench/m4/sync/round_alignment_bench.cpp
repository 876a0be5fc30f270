// Instructions per round-alignment decision (sync::Align) on the emulated
// Cortex-M4 (qemu mps2-an386, -icount shift=0: one counted cycle per executed
// instruction), for a swarm of 32 robots: the robot heard its 31 others this
// round (the runtime's case every round), and the worst case the sample
// array holds, 64 beacons (two from every sender in a misaligned round),
// both in an order the insertion sort likes least (descending) and in a
// scattered one. A 72 MHz Teensy 3.2 has 3,600,000 cycles per 50 ms round.
#include <cstdint>
#include <cstdio>
#include <span>

#include "syrof/board/cycles.h"
#include "syrof/sync/round_alignment.h"

namespace {

using namespace syrof::sync;

constexpr int kRepeats = 100;
constexpr int64_t kRound = 50'000'000;

AlignmentSample samples[kMaxAlignmentSamples];
volatile int64_t sink = 0;

void Fill(int count, bool descending) {
  for (int i = 0; i < count; ++i) {
    const int64_t spread = descending ? (count - i) * 3'001 : (i * 7'919) % 64 * 3'001;
    samples[i] = AlignmentSample{static_cast<uint16_t>(1 + i % 31), 40'000 + spread};
  }
}

uint64_t Measure(int count, bool descending) {
  Fill(count, descending);
  const AlignmentConfig config = AlignmentConfig::ForRound(kRound, 0);
  AlignmentStats stats;
  const uint64_t begin = syrof::board::cycle_counter_read();
  for (int repeat = 0; repeat < kRepeats; ++repeat) {
    const AlignmentStep step =
        Align(config, std::span<const AlignmentSample>(samples, static_cast<size_t>(count)), true, stats);
    sink = sink + step.correction_ns;
  }
  return (syrof::board::cycle_counter_read() - begin) / kRepeats;
}

}  // namespace

int main() {
  syrof::board::cycle_counter_start();
  const uint64_t heard31 = Measure(31, false);
  const uint64_t heard31_worst = Measure(31, true);
  const uint64_t heard64_worst = Measure(64, true);
  std::printf("round alignment on Cortex-M4 soft-float, 32 robots, %d decisions averaged\n", kRepeats);
  std::printf("  31 beacons, scattered order:     %8llu instructions per round\n",
              static_cast<unsigned long long>(heard31));
  std::printf("  31 beacons, descending order:    %8llu instructions per round\n",
              static_cast<unsigned long long>(heard31_worst));
  std::printf("  64 beacons, descending order:    %8llu instructions per round\n",
              static_cast<unsigned long long>(heard64_worst));
  std::printf("  worst per 50 ms round: %.3f%% of a 72 MHz core\n", 100.0 * static_cast<double>(heard64_worst) / 3600000.0);
  return 0;
}
