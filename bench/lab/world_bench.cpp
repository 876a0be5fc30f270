// Cost of one World::Step per robot, for 10, 100 and 1000 omni robots at
// 100 Hz in an arena scaled to keep the density of the paper's lab (one
// robot per 0.25 m^2), driving at random (seeded) velocities that change
// every second, so bodies meet each other and the walls all the time. The
// "robot_step" counter is the time per robot per step (the design's target:
// under 300 ns, i.e. 30 us per step per 100 robots).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "syrof/base/split_mix64.h"
#include "syrof/lab/world/world.h"

namespace {

using namespace syrof;
using lab::world::BodySpec;
using lab::world::World;

constexpr double kDt = 0.01;
constexpr int64_t kStepNs = 10'000'000;

void SetRandomDrives(World& world, base::SplitMix64& random) {
  for (uint16_t id = 0; id < world.size(); ++id) {
    motion::DriveCommand drive;
    drive.kind = motion::DriveKind::kOmni;
    drive.vx_mps = static_cast<float>(random.Between(-50, 50)) / 100.0f;
    drive.vy_mps = static_cast<float>(random.Between(-50, 50)) / 100.0f;
    world.SetDrive(id, drive);
  }
}

void BM_WorldStep(benchmark::State& state) {
  const auto robots = static_cast<uint16_t>(state.range(0));
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(robots))));
  lab::world::ArenaSpec arena;
  arena.width_m = arena.height_m = 0.5 * side;
  std::vector<BodySpec> bodies;
  for (uint16_t id = 0; id < robots; ++id) {
    BodySpec body;
    body.id = id;
    body.x_m = 0.25 + 0.5 * (id % side);
    body.y_m = 0.25 + 0.5 * (id / side);
    bodies.push_back(body);
  }
  World world(arena, bodies);
  base::SplitMix64 random(2024);
  int64_t step = 0;
  for (auto _ : state) {
    if (step % 100 == 0) {
      state.PauseTiming();
      SetRandomDrives(world, random);
      state.ResumeTiming();
    }
    ++step;
    world.Step(step * kStepNs, kDt);
    benchmark::DoNotOptimize(world.min_separation_m());
  }
  state.counters["robot_step"] =
      benchmark::Counter(static_cast<double>(robots), benchmark::Counter::kIsIterationInvariantRate |
                                                           benchmark::Counter::kInvert);
  state.counters["contacts_per_s"] = static_cast<double>(world.contacts()) / (static_cast<double>(step) * kDt);
}

BENCHMARK(BM_WorldStep)->Arg(10)->Arg(100)->Arg(1000);

}  // namespace

BENCHMARK_MAIN();
