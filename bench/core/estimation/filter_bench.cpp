// Nanoseconds per prediction, per update and per 100 Hz cycle of the filter
// on the host, for Ekf<float> (the Teensy's scalar) and Ekf<double>.
//
// Updates run on a copy of a filter in steady state, so every iteration does
// the same work; BM_CopyFilter is that copy alone, to subtract. The cycle is
// what the Kalman task does with every sensor due: predict, one flow reading
// (two scalar updates) and a sweep of four ranges, over a recorded stretch of
// a circle at 0.5 m/s.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "syrof/estimation/arena.h"
#include "syrof/estimation/ekf.h"
#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/range_model.h"

namespace {

using namespace syrof::estimation;

template <typename Scalar>
struct CycleInput {
  ImuInput<Scalar> imu;
  BodyVelocity<Scalar> flow;
  Scalar ranges_m[4];
};

// A circle of radius 1 m around the arena's centre at 0.5 m/s, noiseless.
template <typename Scalar>
std::vector<CycleInput<Scalar>> MakeInputs(int count) {
  const Arena<double> arena = DefaultArena<double>();
  std::vector<CycleInput<Scalar>> inputs(static_cast<size_t>(count));
  for (int k = 0; k < count; ++k) {
    const double angle = 0.5 * 0.01 * (k + 1);
    const double x = 2.0 + std::cos(angle);
    const double y = 2.0 + std::sin(angle);
    CycleInput<Scalar>& input = inputs[static_cast<size_t>(k)];
    input.imu = ImuInput<Scalar>{0, static_cast<Scalar>(0.25), static_cast<Scalar>(0.5)};
    input.flow = BodyVelocity<Scalar>{static_cast<Scalar>(0.5), 0, static_cast<Scalar>(0.15)};
    for (int i = 0; i < 4; ++i) {
      const Vector3<double> offset(x - arena.anchors[i][0], y - arena.anchors[i][1],
                                   arena.tag_height_m - arena.anchors[i][2]);
      input.ranges_m[i] = static_cast<Scalar>(offset.norm());
    }
  }
  return inputs;
}

template <typename Scalar>
Ekf<Scalar> SteadyFilter() {
  Ekf<Scalar> filter;
  StateVector<Scalar> state;
  state << 3, 2, 0, static_cast<Scalar>(0.5), kPi<Scalar> / 2, 0;
  filter.Reset(state, StateVector<Scalar>::Constant(static_cast<Scalar>(0.1)));
  const Arena<Scalar> arena = DefaultArena<Scalar>();
  for (const CycleInput<Scalar>& input : MakeInputs<Scalar>(500)) {
    filter.Predict(static_cast<Scalar>(0.01), input.imu);
    (void)FuseBodyVelocity(filter, input.flow, Scalar{5});
    for (int i = 0; i < 4; ++i) {
      (void)FuseRange(filter, arena.anchors[i], arena.tag_height_m, input.ranges_m[i], static_cast<Scalar>(0.1),
                      static_cast<Scalar>(3.5));
    }
  }
  return filter;
}

template <typename Scalar>
void BM_Predict(benchmark::State& state) {
  Ekf<Scalar> filter = SteadyFilter<Scalar>();
  const ImuInput<Scalar> imu{0, static_cast<Scalar>(0.25), static_cast<Scalar>(0.5)};
  for (auto _ : state) {
    filter.Predict(static_cast<Scalar>(0.01), imu);
    benchmark::DoNotOptimize(filter);
  }
}

template <typename Scalar>
void BM_CopyFilter(benchmark::State& state) {
  const Ekf<Scalar> steady = SteadyFilter<Scalar>();
  for (auto _ : state) {
    Ekf<Scalar> filter = steady;
    benchmark::DoNotOptimize(filter);
  }
}

template <typename Scalar>
void BM_RangeUpdate(benchmark::State& state) {
  const Ekf<Scalar> steady = SteadyFilter<Scalar>();
  const Arena<Scalar> arena = DefaultArena<Scalar>();
  const Scalar range = PredictRange(steady.state(), arena.anchors[2], arena.tag_height_m) + static_cast<Scalar>(0.05);
  for (auto _ : state) {
    Ekf<Scalar> filter = steady;
    benchmark::DoNotOptimize(FuseRange(filter, arena.anchors[2], arena.tag_height_m, range, static_cast<Scalar>(0.1),
                                       static_cast<Scalar>(3.5)));
    benchmark::DoNotOptimize(filter);
  }
}

template <typename Scalar>
void BM_FlowUpdate(benchmark::State& state) {
  const Ekf<Scalar> steady = SteadyFilter<Scalar>();
  const BodyVelocity<Scalar> velocity{static_cast<Scalar>(0.52), static_cast<Scalar>(-0.02), static_cast<Scalar>(0.15)};
  for (auto _ : state) {
    Ekf<Scalar> filter = steady;
    benchmark::DoNotOptimize(FuseBodyVelocity(filter, velocity, Scalar{5}));
    benchmark::DoNotOptimize(filter);
  }
}

template <typename Scalar>
void BM_Cycle(benchmark::State& state) {
  const std::vector<CycleInput<Scalar>> inputs = MakeInputs<Scalar>(1000);
  const Arena<Scalar> arena = DefaultArena<Scalar>();
  Ekf<Scalar> filter = SteadyFilter<Scalar>();
  size_t next = 0;
  for (auto _ : state) {
    const CycleInput<Scalar>& input = inputs[next];
    next = next + 1 == inputs.size() ? 0 : next + 1;
    filter.Predict(static_cast<Scalar>(0.01), input.imu);
    benchmark::DoNotOptimize(FuseBodyVelocity(filter, input.flow, Scalar{5}));
    for (int i = 0; i < 4; ++i) {
      benchmark::DoNotOptimize(FuseRange(filter, arena.anchors[i], arena.tag_height_m, input.ranges_m[i],
                                         static_cast<Scalar>(0.1), static_cast<Scalar>(3.5)));
    }
    benchmark::DoNotOptimize(filter);
  }
}

BENCHMARK_TEMPLATE(BM_Predict, float);
BENCHMARK_TEMPLATE(BM_Predict, double);
BENCHMARK_TEMPLATE(BM_CopyFilter, float);
BENCHMARK_TEMPLATE(BM_CopyFilter, double);
BENCHMARK_TEMPLATE(BM_RangeUpdate, float);
BENCHMARK_TEMPLATE(BM_RangeUpdate, double);
BENCHMARK_TEMPLATE(BM_FlowUpdate, float);
BENCHMARK_TEMPLATE(BM_FlowUpdate, double);
BENCHMARK_TEMPLATE(BM_Cycle, float);
BENCHMARK_TEMPLATE(BM_Cycle, double);

}  // namespace

BENCHMARK_MAIN();
