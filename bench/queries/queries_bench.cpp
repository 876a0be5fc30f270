// Microseconds per query on the host for swarms of 10, 100 and 1000 robots
// (more than the host's kMaxMembers are skipped). Members are uniform in a
// 40 m square, targets likewise; every input comes from a fixed seed.
// Ring variants put every member on the hull (a formation), the worst case
// for hull output and for the enclosing circle's support changes.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>
#include <vector>

#include "syrof/base/split_mix64.h"
#include "syrof/queries/swarm_queries.h"

namespace syrof::queries {
namespace {

// Seeded, so the inputs are the same on every run and machine.
using Rng = base::SplitMix64;

int16_t Coordinate(Rng& rng) { return static_cast<int16_t>(rng.Between(-20000, 20000)); }

Workspace& SharedWorkspace() {
  static const auto workspace = std::make_unique<Workspace>();
  return *workspace;
}

// n members with ids 0..n-1 in a scrambled order.
std::vector<Member> RandomMembers(size_t n, uint64_t seed) {
  Rng rng(seed);
  std::vector<Member> members(n);
  for (size_t index = 0; index < n; ++index) {
    members[index] = {static_cast<uint16_t>((index * 7919) % n), {Coordinate(rng), Coordinate(rng)}};
  }
  return members;
}

std::vector<Member> RingMembers(size_t n) {
  std::vector<Member> members(n);
  for (size_t index = 0; index < n; ++index) {
    const double angle = 2 * 3.14159265358979 * static_cast<double>(index) / static_cast<double>(n);
    members[index] = {static_cast<uint16_t>(index),
                      {static_cast<int16_t>(std::lround(20000 * std::cos(angle))),
                       static_cast<int16_t>(std::lround(20000 * std::sin(angle)))}};
  }
  return members;
}

std::vector<Point> RandomTargets(size_t n, uint64_t seed) {
  Rng rng(seed);
  std::vector<Point> targets(n);
  for (Point& target : targets) target = {Coordinate(rng), Coordinate(rng)};
  return targets;
}

bool TooLarge(benchmark::State& state) {
  if (state.range(0) <= kMaxMembers) return false;
  state.SkipWithError("more members than kMaxMembers in this build");
  return true;
}

void BM_NumberOfMembers(benchmark::State& state) {
  if (TooLarge(state)) return;
  const std::vector<Member> members = RandomMembers(static_cast<size_t>(state.range(0)), 1);
  for (auto _ : state) benchmark::DoNotOptimize(NumberOfMembers(members));
}

void BM_Leader(benchmark::State& state) {
  if (TooLarge(state)) return;
  const std::vector<Member> members = RandomMembers(static_cast<size_t>(state.range(0)), 2);
  for (auto _ : state) benchmark::DoNotOptimize(Leader(members));
}

void BM_ConvexHull(benchmark::State& state) {
  if (TooLarge(state)) return;
  const std::vector<Member> members = RandomMembers(static_cast<size_t>(state.range(0)), 3);
  std::vector<uint16_t> hull(members.size());
  for (auto _ : state) benchmark::DoNotOptimize(ConvexHull(members, SharedWorkspace(), hull));
}

void BM_ConvexHullRing(benchmark::State& state) {
  if (TooLarge(state)) return;
  const std::vector<Member> members = RingMembers(static_cast<size_t>(state.range(0)));
  std::vector<uint16_t> hull(members.size());
  for (auto _ : state) benchmark::DoNotOptimize(ConvexHull(members, SharedWorkspace(), hull));
}

void BM_ShortestEnclosingCircle(benchmark::State& state) {
  if (TooLarge(state)) return;
  const std::vector<Member> members = RandomMembers(static_cast<size_t>(state.range(0)), 4);
  for (auto _ : state) benchmark::DoNotOptimize(ShortestEnclosingCircle(members, SharedWorkspace()));
}

void BM_ShortestEnclosingCircleRing(benchmark::State& state) {
  if (TooLarge(state)) return;
  const std::vector<Member> members = RingMembers(static_cast<size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(ShortestEnclosingCircle(members, SharedWorkspace()));
}

// As many targets as robots, both random.
void BM_MinWeightedMatching(benchmark::State& state) {
  if (TooLarge(state)) return;
  const auto n = static_cast<size_t>(state.range(0));
  const std::vector<Member> members = RandomMembers(n, 5);
  const std::vector<Point> targets = RandomTargets(n, 6);
  std::vector<Assignment> by_robot(n);
  std::vector<uint16_t> robot_of_target(n);
  for (auto _ : state) {
    benchmark::DoNotOptimize(MinWeightedMatching(members, targets, SharedWorkspace(), by_robot, robot_of_target));
  }
}

// A formation change: robots on a ring move to a ring rotated by half a step.
void BM_MinWeightedMatchingRing(benchmark::State& state) {
  if (TooLarge(state)) return;
  const auto n = static_cast<size_t>(state.range(0));
  const std::vector<Member> members = RingMembers(n);
  std::vector<Point> targets(n);
  for (size_t index = 0; index < n; ++index) {
    const double angle = 2 * 3.14159265358979 * (static_cast<double>(index) + 0.5) / static_cast<double>(n);
    targets[index] = {static_cast<int16_t>(std::lround(15000 * std::cos(angle))),
                      static_cast<int16_t>(std::lround(15000 * std::sin(angle)))};
  }
  std::vector<Assignment> by_robot(n);
  std::vector<uint16_t> robot_of_target(n);
  for (auto _ : state) {
    benchmark::DoNotOptimize(MinWeightedMatching(members, targets, SharedWorkspace(), by_robot, robot_of_target));
  }
}

BENCHMARK(BM_NumberOfMembers)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Leader)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConvexHull)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConvexHullRing)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ShortestEnclosingCircle)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ShortestEnclosingCircleRing)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MinWeightedMatching)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MinWeightedMatchingRing)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace syrof::queries
