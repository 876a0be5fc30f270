// Instructions per safety-filter step on the emulated Cortex-M4 with software
// floating point (qemu mps2-an386, -icount shift=0: one counted cycle per
// executed instruction), for a swarm of 32 robots: the robot filters its
// command against the 31 others' reports and the walls, as the motion task
// does at 100 Hz (docs/safety.md, "Cost"). Three situations:
//   - clear: every other robot at least 1 m away (each costs the
//     squared-distance test, no square root);
//   - crowded: eight robots within reach, the command pressed against them
//     (constraints kept, four projection passes);
//   - rover: the crowded case for a differential-drive robot.
// Plus the round task's side: recording one beacon's report.
// A 72 MHz Teensy 3.2 has 720,000 cycles per 10 ms motion period.
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "syrof/board/cycles.h"
#include "syrof/motion/safety_filter.h"

namespace {

using namespace syrof::motion;

constexpr uint16_t kSwarm = 32;
constexpr int kSteps = 200;

ControllerConfig Config(DriveKind kind) {
  ControllerConfig config;
  config.kind = kind;
  return config;
}

SafetyConfig Safety() {
  SafetyConfig safety;
  safety.self_id = 0;
  safety.arena_width_m = 4;
  safety.arena_height_m = 4;
  return safety;
}

syrof::estimation::StateEstimate At(float x, float y) {
  syrof::estimation::StateEstimate estimate{};
  estimate.x_m = x;
  estimate.y_m = y;
  estimate.heading_rad = 0.3f;
  estimate.status = syrof::estimation::kEstimateInitialized;
  return estimate;
}

// Robot 0 at (2, 2); the others on rings around it: `near` of them 0.35 to
// 0.5 m away, the rest more than 1 m.
void Fill(SafetyReports& reports, int near) {
  for (uint16_t id = 1; id < kSwarm; ++id) {
    const float angle = 0.7f * static_cast<float>(id);
    const float radius = id <= near ? 0.35f + 0.02f * static_cast<float>(id) : 1.0f + 0.05f * static_cast<float>(id);
    reports.ReportMetres(id, 0, 2.0f + radius * std::cos(angle), 2.0f + radius * std::sin(angle), id % 3 == 0, 0.1f,
                   0.0f, 0.8f);
  }
}

SafetyReports reports;
volatile float sink = 0;

uint64_t MeasureApply(DriveKind kind, int near) {
  Fill(reports, near);
  SafetyFilter filter(Safety(), Config(kind), kSwarm);
  DriveCommand desired;
  desired.kind = kind;
  desired.vx_mps = 0.4f;
  desired.vy_mps = 0.2f;
  desired.left_mps = 0.3f;
  desired.right_mps = 0.35f;
  const auto estimate = At(2.0f, 2.0f);
  const uint64_t begin = syrof::board::cycle_counter_read();
  for (int step = 0; step < kSteps; ++step) {
    SafetyOutcome outcome;
    // 20 ms after the reports: the discs have grown a little.
    const DriveCommand out = filter.Apply(desired, estimate, reports, 20'000'000 + step, outcome);
    sink = sink + out.vx_mps + out.left_mps;
  }
  return (syrof::board::cycle_counter_read() - begin) / kSteps;
}

uint64_t MeasureReport() {
  const uint64_t begin = syrof::board::cycle_counter_read();
  for (int step = 0; step < kSteps; ++step) {
    const uint16_t id = static_cast<uint16_t>(1 + step % (kSwarm - 1));
    // As the runtime records a beacon: its millimetres, half of them parked.
    reports.Report(id, step, static_cast<int16_t>(1000 + step), 2000, step % 2 == 0, 200, 100, 0.8f);
  }
  return (syrof::board::cycle_counter_read() - begin) / kSteps;
}

}  // namespace

int main() {
  syrof::board::cycle_counter_start();
  const uint64_t clear = MeasureApply(DriveKind::kOmni, 0);
  const uint64_t crowded = MeasureApply(DriveKind::kOmni, 8);
  const uint64_t rover = MeasureApply(DriveKind::kWheels, 8);
  const uint64_t report = MeasureReport();
  std::printf("safety filter on Cortex-M4 soft-float, %d robots, %d steps averaged\n", kSwarm, kSteps);
  std::printf("  omni, nobody within reach:       %8llu instructions per step\n",
              static_cast<unsigned long long>(clear));
  std::printf("  omni, 8 robots within reach:     %8llu instructions per step\n",
              static_cast<unsigned long long>(crowded));
  std::printf("  rover, 8 robots within reach:    %8llu instructions per step\n",
              static_cast<unsigned long long>(rover));
  std::printf("  one beacon's report (round task): %7llu instructions\n", static_cast<unsigned long long>(report));
  std::printf("  worst step at 100 Hz: %.1f%% of a 72 MHz core\n",
              100.0 * static_cast<double>(crowded > rover ? crowded : rover) / 720000.0);
  return 0;
}
