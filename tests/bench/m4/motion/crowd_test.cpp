// The motion benchmark's crowd (bench/m4/motion/crowd.h) puts its near
// robots within the safety filter's reach, and its far ones out of it.
#include "crowd.h"

#include <cmath>

#include <gtest/gtest.h>

#include "syrof/motion/controller.h"
#include "syrof/motion/safety_filter.h"

namespace syrof::bench {
namespace {

using motion::DriveCommand;
using motion::DriveKind;
using motion::SafetyFilter;
using motion::SafetyOutcome;
using motion::SafetyReports;

motion::SafetyConfig Safety() {
  motion::SafetyConfig safety;
  safety.self_id = 0;
  safety.arena_width_m = 4;
  safety.arena_height_m = 4;
  return safety;
}

// Whether a full-speed command straight at robot `id`, with only its report
// in the table, is limited 20 ms after the report (as the bench applies it).
bool LimitsCommandAt(uint16_t id, int near) {
  motion::ControllerConfig config;
  config.kind = DriveKind::kOmni;
  SafetyFilter filter(Safety(), config, kCrowdSwarm);
  float x_m = 0, y_m = 0;
  CrowdPosition(id, near, x_m, y_m);
  SafetyReports reports;
  reports.ReportMetres(id, 0, x_m, y_m, false, 0, 0, 0.8f);
  estimation::StateEstimate estimate{};
  estimate.x_m = kCrowdCentreM;
  estimate.y_m = kCrowdCentreM;
  estimate.status = estimation::kEstimateInitialized;
  const float dx = x_m - kCrowdCentreM, dy = y_m - kCrowdCentreM;
  const float length = std::sqrt(dx * dx + dy * dy);
  DriveCommand desired;
  desired.kind = DriveKind::kOmni;
  desired.vx_mps = config.limits.max_speed_mps * dx / length;
  desired.vy_mps = config.limits.max_speed_mps * dy / length;
  SafetyOutcome outcome;
  (void)filter.Apply(desired, estimate, reports, 20'000'000, outcome);
  return outcome.limited;
}

TEST(CrowdTest, EveryNearRobotIsWithinTheFiltersReach) {
  for (uint16_t id = 1; id < kCrowdSwarm; ++id) {
    EXPECT_TRUE(LimitsCommandAt(id, kCrowdSwarm - 1)) << "robot " << id;
  }
}

TEST(CrowdTest, FarRobotsAreOutOfReach) {
  for (uint16_t id = 1; id < kCrowdSwarm; ++id) {
    EXPECT_FALSE(LimitsCommandAt(id, 0)) << "robot " << id;
  }
}

TEST(CrowdTest, FillCrowdReportsEveryOtherRobot) {
  SafetyReports reports;
  FillCrowd(reports, kCrowdSwarm - 1);
  for (uint16_t id = 1; id < kCrowdSwarm; ++id) EXPECT_TRUE(reports[id].valid) << "robot " << id;
}

}  // namespace
}  // namespace syrof::bench
