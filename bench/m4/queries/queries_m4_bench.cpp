// Instructions per query on the emulated Cortex-M4 (qemu mps2-an386 under
// -icount shift=0, where the board's cycle counter counts executed
// instructions in steps of 40), for a swarm of kMaxMembers robots (32 in the
// Teensy build) and as many targets. Each query runs kRepetitions times on
// the same input and the mean is printed. Inputs come from a fixed seed, so
// the counts are the same on every run of the same image.
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "syrof/base/split_mix64.h"
#include "syrof/board/cycles.h"
#include "syrof/queries/swarm_queries.h"

namespace {

using namespace syrof::queries;

constexpr int kRepetitions = 16;
constexpr uint16_t kCount = kMaxMembers < kMaxTargets ? kMaxMembers : kMaxTargets;

// Seeded, the same inputs as on every other run.
syrof::base::SplitMix64 rng(32);
int16_t Coordinate() { return static_cast<int16_t>(rng.Between(-20000, 20000)); }

Workspace workspace;  // static: about 6 KB in this build
Member members[kCount];
Point targets[kCount];
uint16_t hull[kCount];
Assignment by_robot[kCount];
uint16_t robot_of_target[kCount];

template <typename Query>
void Measure(const char* name, Query&& query) {
  query();  // once unmeasured, so every measured run does the same work
  const uint64_t begin = syrof::board::cycle_counter_read();
  for (int repetition = 0; repetition < kRepetitions; ++repetition) query();
  const uint64_t instructions = (syrof::board::cycle_counter_read() - begin) / kRepetitions;
  std::printf("%-26s n=%u  %8llu instructions/query\n", name, unsigned{kCount},
              static_cast<unsigned long long>(instructions));
}

}  // namespace

int main() {
  syrof::board::cycle_counter_start();
  for (uint16_t index = 0; index < kCount; ++index) {
    members[index] = {static_cast<uint16_t>((index * 7u) % kCount), {Coordinate(), Coordinate()}};
    targets[index] = {Coordinate(), Coordinate()};
  }
  std::printf("queries on the emulated Cortex-M4, workspace %u bytes\n", unsigned{sizeof(Workspace)});
  bool ok = true;
  Measure("NumberOfMembers", [&] { ok &= NumberOfMembers(members).ok(); });
  Measure("Leader", [&] { ok &= Leader(members).ok(); });
  Measure("ConvexHull", [&] { ok &= ConvexHull(members, workspace, hull).ok(); });
  Measure("ShortestEnclosingCircle", [&] { ok &= ShortestEnclosingCircle(members, workspace).ok(); });
  Measure("MinWeightedMatching",
          [&] { ok &= MinWeightedMatching(members, targets, workspace, by_robot, robot_of_target).ok(); });
  if (!ok) std::printf("a query FAILED\n");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
