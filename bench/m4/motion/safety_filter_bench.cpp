// Instructions per motion step on the emulated Cortex-M4 with software
// floating point (qemu mps2-an386, -icount shift=0: one counted cycle per
// executed instruction), for a swarm of 32 robots: what the motion task does
// at 100 Hz (runtime::Robot::RunMotion, docs/safety.md "Cost"): the
// controller's Update, the copy of the round task's reports, and the safety
// filter's Apply against the 31 others' reports and the walls. Each step
// drives towards a different point around the robot (200 directions), and
// every step is counted: worst and mean. Situations (crowd.h):
//   - clear: every other robot at least 1 m away (each costs the
//     squared-distance test, no square root);
//   - 8 within reach, and all 31 within reach (the registry's limit:
//     more constraints than the filter keeps, so it picks the nearest);
//   - rover: the same for a differential-drive robot.
// Plus the round task's side: recording one beacon's report.
// A 72 MHz Teensy 3.2 has 720,000 cycles per 10 ms motion period.
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "crowd.h"
#include "syrof/board/cycles.h"
#include "syrof/motion/controller.h"
#include "syrof/motion/safety_filter.h"

namespace {

using namespace syrof::motion;
using syrof::bench::kCrowdCentreM;
using syrof::bench::kCrowdSwarm;

constexpr uint16_t kSwarm = kCrowdSwarm;
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

SafetyReports shared_reports;  // the round task's
SafetyReports reports;         // the motion task's copy
volatile float sink = 0;

struct Counts {
  uint64_t worst = 0;
  uint64_t mean = 0;
};

Counts MeasureStep(DriveKind kind, int near) {
  syrof::bench::FillCrowd(shared_reports, near);
  MotionController controller(Config(kind));
  SafetyFilter filter(Safety(), Config(kind), kSwarm);
  auto estimate = At(kCrowdCentreM, kCrowdCentreM);
  uint64_t total = 0;
  Counts counts;
  for (int step = 0; step < kSteps; ++step) {
    const float angle = 6.2831853f * static_cast<float>(step) / kSteps;
    syrof_car_command command{};
    command.kind = SYROF_COMMAND_MOVE_TO;
    command.x_m = kCrowdCentreM + 1.5f * std::cos(angle);
    command.y_m = kCrowdCentreM + 1.5f * std::sin(angle);
    command.speed_mps = 0.4f;
    // 20 ms after the reports: the discs have grown a little.
    const int64_t now_ns = 20'000'000 + step;
    estimate.timestamp_ns = now_ns;
    estimate.heading_rad = angle;  // a rover faces its target, so it drives rather than turns
    const uint64_t begin = syrof::board::cycle_counter_read();
    controller.SetCommand(command);
    const DriveCommand desired = controller.Update(estimate, now_ns);
    reports.CopyFrom(shared_reports, kSwarm);
    SafetyOutcome outcome;
    const DriveCommand out = filter.Apply(desired, estimate, reports, now_ns, outcome);
    const uint64_t instructions = syrof::board::cycle_counter_read() - begin;
    sink = sink + out.vx_mps + out.left_mps;
    total += instructions;
    if (instructions > counts.worst) counts.worst = instructions;
  }
  counts.mean = total / kSteps;
  return counts;
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

void Print(const char* what, Counts counts) {
  std::printf("  %-34s %8llu worst %8llu mean\n", what, static_cast<unsigned long long>(counts.worst),
              static_cast<unsigned long long>(counts.mean));
}

}  // namespace

int main() {
  syrof::board::cycle_counter_start();
  const Counts clear = MeasureStep(DriveKind::kOmni, 0);
  const Counts crowded = MeasureStep(DriveKind::kOmni, 8);
  const Counts all = MeasureStep(DriveKind::kOmni, kSwarm - 1);
  const Counts rover = MeasureStep(DriveKind::kWheels, 8);
  const Counts rover_all = MeasureStep(DriveKind::kWheels, kSwarm - 1);
  const uint64_t report = MeasureReport();
  std::printf("motion step (controller + report copy + safety filter) on Cortex-M4 soft-float, %d robots, "
              "%d steps, instructions per step\n",
              kSwarm, kSteps);
  Print("omni, nobody within reach:", clear);
  Print("omni, 8 robots within reach:", crowded);
  Print("omni, 31 robots within reach:", all);
  Print("rover, 8 robots within reach:", rover);
  Print("rover, 31 robots within reach:", rover_all);
  std::printf("  one beacon's report (round task): %7llu instructions\n", static_cast<unsigned long long>(report));
  const uint64_t worst = all.worst > rover_all.worst ? all.worst : rover_all.worst;
  std::printf("  worst step at 100 Hz: %.1f%% of a 72 MHz core\n", 100.0 * static_cast<double>(worst) / 720000.0);
  return 0;
}
