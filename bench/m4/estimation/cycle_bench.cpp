// Instructions per 100 Hz estimation cycle on the emulated Cortex-M4 with
// software floating point (qemu mps2-an386, -icount shift=0: one counted
// cycle per executed instruction). One cycle is what the Kalman task does in
// a step with every sensor due: convert an MPU-9250 reading and predict,
// convert a flow reading and fuse it (two scalar updates), fuse a sweep of
// four ranges (four scalar updates). The budget is 72,000 cycles, 1 ms of a
// 72 MHz Teensy 3.2 (which takes more than one cycle for some instructions,
// so the real time is somewhat higher).
//
// The readings are made up front (a circle at 0.5 m/s inside the default
// arena, small deterministic noise), so only the filter is measured. Two
// extras run only while the position is uncertain (estimator.h), so they are
// reported apart: the sweep screen (position sigma above 0.1 m) and the
// least-squares fix that replaces the range updates (above 0.5 m: at start-up
// and when the robot has lost itself).
//
// Every cycle is counted alone: each figure is the worst cycle and the mean.
// The estimator's tasks on a moving robot with the lab's simulated sensors,
// in a swarm of 32, are bench_m4_runtime_swarm's (docs/firmware.md,
// "Schedulability").
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

#include "syrof/board/cycles.h"
#include "syrof/estimation/arena.h"
#include "syrof/estimation/ekf.h"
#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/imu_model.h"
#include "syrof/estimation/multilateration.h"
#include "syrof/estimation/range_model.h"
#include "syrof/estimation/state.h"
#include "syrof/estimation/zero_rate_model.h"

namespace {

using namespace syrof::estimation;

constexpr int kCycles = 200;
constexpr float kDt = 0.01f;
constexpr float kRadius = 1.0f;
constexpr float kSpeed = 0.5f;
constexpr float kRangeSigma = 0.1f;
constexpr float kFlowSigmaPx = 2.0f;
constexpr float kGate = 3.5f;

struct CycleInput {
  ImuReading imu;
  FlowReading flow;
  float ranges_m[4];
};

CycleInput inputs[kCycles];

// A small linear congruential generator: deterministic, no library state.
uint32_t lcg_state = 12345;
float Jitter(float amplitude) {
  lcg_state = lcg_state * 1664525u + 1013904223u;
  return amplitude * (static_cast<float>(lcg_state >> 8) / 8388608.0f - 1.0f);
}

void MakeInputs(const Arena<float>& arena, const FlowGeometry<float>& geometry) {
  const float omega = kSpeed / kRadius;
  const float metres_per_pixel = FlowMetresPerPixel(geometry);
  for (int k = 0; k < kCycles; ++k) {
    const float t = static_cast<float>(k + 1) * kDt;
    const float angle = omega * t;
    const float x = 2.0f + kRadius * std::cos(angle);
    const float y = 2.0f + kRadius * std::sin(angle);
    CycleInput& input = inputs[k];
    input.imu.timestamp_ns = static_cast<int64_t>(k) * 10'000'000;
    // Heading along the circle: the centripetal acceleration points left.
    input.imu.accel_g[0] = Jitter(0.002f);
    input.imu.accel_g[1] = kSpeed * omega / kPaperGravity<float> + Jitter(0.002f);
    input.imu.accel_g[2] = 1.0f;
    input.imu.gyro_dps[0] = 0;
    input.imu.gyro_dps[1] = 0;
    input.imu.gyro_dps[2] = omega * 180.0f / kPi<float> + Jitter(0.05f);
    input.flow.timestamp_ns = input.imu.timestamp_ns;
    input.flow.interval_ns = 20'000'000;
    input.flow.delta_x_px = static_cast<int16_t>(std::lround(kSpeed * 0.02f / metres_per_pixel + Jitter(2.0f)));
    input.flow.delta_y_px = static_cast<int16_t>(std::lround(Jitter(2.0f)));
    for (int i = 0; i < 4; ++i) {
      const float dx = x - arena.anchors[i][0];
      const float dy = y - arena.anchors[i][1];
      const float dz = arena.tag_height_m - arena.anchors[i][2];
      input.ranges_m[i] = std::sqrt(dx * dx + dy * dy + dz * dz) + Jitter(kRangeSigma);
    }
  }
}

Ekf<float> MakeFilter() {
  Ekf<float> filter;
  StateVector<float> state;
  state << 3.0f, 2.0f, 0.0f, kSpeed, kPi<float> / 2, 0.0f;
  StateVector<float> sigma;
  sigma << 0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.01f;
  filter.Reset(state, sigma);
  return filter;
}

struct Counts {
  uint64_t worst = 0;
  uint64_t total = 0;
  void Add(uint64_t instructions) {
    total += instructions;
    if (instructions > worst) worst = instructions;
  }
  uint64_t mean() const { return total / kCycles; }
};

int errors = 0;
void Count(EstimationError error) {
  if (error != EstimationError::kOk && error != EstimationError::kRejectedByGate) ++errors;
}

void Predict(Ekf<float>& filter, const CycleInput& input) {
  const auto sample = ConvertImuReading<float>(input.imu);
  if (!sample) ++errors;
  filter.Predict(kDt, PlanarImuInput(sample.value()));
}

void FuseFlow(Ekf<float>& filter, const CycleInput& input, float metres_per_pixel) {
  const auto velocity = FlowToBodyVelocity(input.flow, metres_per_pixel, kFlowSigmaPx);
  if (!velocity) {
    ++errors;
    return;
  }
  Count(FuseBodyVelocity(filter, velocity.value(), 5.0f));
}

void FuseRanges(Ekf<float>& filter, const CycleInput& input, const Arena<float>& arena) {
  for (int i = 0; i < 4; ++i) {
    Count(FuseRange(filter, arena.anchors[i], arena.tag_height_m, input.ranges_m[i], kRangeSigma, kGate));
  }
}

// The sweep screen and the least-squares fix, per sweep. The fix of a
// sweep with an outlier is the slowest: one solve with every range, then one
// without each.
struct UncertainCosts {
  Counts screen;
  Counts clean_fix;
  Counts outlier_fix;
};

UncertainCosts MeasureScreenAndFix(const Arena<float>& arena) {
  const Ekf<float> filter = MakeFilter();
  const std::span<const Vector3<float>> anchors(arena.anchors, 4);
  UncertainCosts costs{};
  for (int k = 0; k < kCycles; ++k) {
    const uint64_t begin = syrof::board::cycle_counter_read();
    const int worst = FindInconsistentRange<float>(filter.state(), anchors, std::span<const float>(inputs[k].ranges_m, 4),
                                                   arena.tag_height_m, kRangeSigma, kGate);
    costs.screen.Add(syrof::board::cycle_counter_read() - begin);
    if (worst < -1) ++errors;
  }
  for (int k = 0; k < kCycles; ++k) {
    const uint64_t begin = syrof::board::cycle_counter_read();
    const auto fix = MultilaterateOnPlaneRobust<float>(anchors, std::span<const float>(inputs[k].ranges_m, 4),
                                                       arena.tag_height_m, 3 * kRangeSigma);
    costs.clean_fix.Add(syrof::board::cycle_counter_read() - begin);
    if (!fix) ++errors;
  }
  for (int k = 0; k < kCycles; ++k) {
    float ranges[4] = {inputs[k].ranges_m[0], inputs[k].ranges_m[1], inputs[k].ranges_m[2], inputs[k].ranges_m[3]};
    ranges[k % 4] += 1.5f;
    const uint64_t begin = syrof::board::cycle_counter_read();
    // Named or refused: either way every subset was solved.
    (void)MultilaterateOnPlaneRobust<float>(anchors, ranges, arena.tag_height_m, 3 * kRangeSigma);
    costs.outlier_fix.Add(syrof::board::cycle_counter_read() - begin);
  }
  return costs;
}

enum Part { kFullCycle, kPredictOnly, kFlowOnly, kRangesOnly, kZeroRateOnly };

// A robot at rest fuses a zero-rate update every cycle (zero_rate_model.h);
// the full cycle counts it too (a still robot still gets flow and ranges).
void FuseZeroRateUpdate(Ekf<float>& filter) {
  Count(FuseZeroRate(filter, filter.state()[kStateGyroBias], ZeroRateConfig<float>{}));
}

Counts Measure(Part part, const Arena<float>& arena, float metres_per_pixel) {
  Ekf<float> filter = MakeFilter();
  Counts counts;
  for (int k = 0; k < kCycles; ++k) {
    const CycleInput& input = inputs[k];
    const uint64_t begin = syrof::board::cycle_counter_read();
    if (part == kFullCycle || part == kPredictOnly) Predict(filter, input);
    if (part == kFullCycle || part == kFlowOnly) FuseFlow(filter, input, metres_per_pixel);
    if (part == kFullCycle || part == kRangesOnly) FuseRanges(filter, input, arena);
    if (part == kFullCycle || part == kZeroRateOnly) FuseZeroRateUpdate(filter);
    counts.Add(syrof::board::cycle_counter_read() - begin);
  }
  if (!filter.state().allFinite()) ++errors;
  return counts;
}

void Print(const char* what, const Counts& counts) {
  std::printf("  %-40s %8llu worst %8llu mean\n", what, static_cast<unsigned long long>(counts.worst),
              static_cast<unsigned long long>(counts.mean()));
}

}  // namespace

int main() {
  const Arena<float> arena = DefaultArena<float>();
  const FlowGeometry<float> geometry{};
  MakeInputs(arena, geometry);
  // Fixed by the geometry: the estimator computes it once, at construction.
  const float metres_per_pixel = FlowMetresPerPixel(geometry);
  syrof::board::cycle_counter_start();
  const Counts full = Measure(kFullCycle, arena, metres_per_pixel);
  const Counts predict = Measure(kPredictOnly, arena, metres_per_pixel);
  const Counts flow = Measure(kFlowOnly, arena, metres_per_pixel);
  const Counts ranges = Measure(kRangesOnly, arena, metres_per_pixel);
  const Counts zero_rate = Measure(kZeroRateOnly, arena, metres_per_pixel);
  std::printf("estimation cycle on Cortex-M4 soft-float (Ekf<float>, %d cycles), instructions\n", kCycles);
  Print("IMU conversion + predict:", predict);
  Print("flow conversion + 2 updates:", flow);
  Print("4 range updates:", ranges);
  Print("zero-rate update (at rest):", zero_rate);
  Print("full 100 Hz cycle:", full);
  std::printf("  (budget 72000 per cycle: %s)\n", full.worst < 72000 ? "met" : "EXCEEDED");
  const UncertainCosts uncertain = MeasureScreenAndFix(arena);
  std::printf("  only while the position is uncertain, per sweep (a cycle with it adds predict + flow):\n");
  Print("sweep screen (sigma > 0.1 m):", uncertain.screen);
  Print("fix of a clean sweep (sigma > 0.5 m):", uncertain.clean_fix);
  Print("fix of a sweep with a 1.5 m outlier:", uncertain.outlier_fix);
  std::printf("  worst cycle with an outlier fix: %llu\n",
              static_cast<unsigned long long>(predict.worst + flow.worst + uncertain.outlier_fix.worst));
  if (errors != 0) std::printf("  %d unexpected filter errors\n", errors);
  return errors == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
