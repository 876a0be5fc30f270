// The fault schedule: faults on the radio-round grid, each due once.
#include "syrof/lab/sim/fault_schedule.h"

#include <gtest/gtest.h>

#include <vector>

namespace syrof::lab::sim {
namespace {

constexpr int64_t kRoundNs = 50'000'000;
using Kind = FaultAction::Kind;

std::vector<FaultAction> DueAt(FaultSchedule& schedule, int64_t now_ns) {
  const auto due = schedule.Due(now_ns);
  return {due.begin(), due.end()};
}

TEST(FaultScheduleTest, AFaultTakesEffectAtTheFirstRoundBoundaryAtOrAfterItsTime) {
  const std::vector<scenario::FaultSpec> faults = {{scenario::FaultKind::kCrash, 2, 1.01, 0}};
  FaultSchedule schedule(faults, kRoundNs);

  EXPECT_TRUE(DueAt(schedule, 1'000'000'000).empty());
  EXPECT_TRUE(DueAt(schedule, 1'010'000'000).empty());  // off the grid
  EXPECT_EQ(DueAt(schedule, 1'050'000'000), (std::vector<FaultAction>{{Kind::kCrash, 2}}));
  EXPECT_TRUE(DueAt(schedule, 1'100'000'000).empty());  // once
  EXPECT_EQ(schedule.EffectiveNs(1.01), 1'050'000'000);
  EXPECT_EQ(schedule.EffectiveNs(1.05), 1'050'000'000);
}

// The resume is due one round before the grid point after until_s, so the
// robot's first step (one round after its restart) is at that grid point.
TEST(FaultScheduleTest, APauseResumesOneRoundBeforeTheGridPointAfterUntil) {
  const std::vector<scenario::FaultSpec> faults = {{scenario::FaultKind::kPause, 4, 3.0, 6.02}};
  FaultSchedule schedule(faults, kRoundNs);

  EXPECT_EQ(DueAt(schedule, 3'000'000'000), (std::vector<FaultAction>{{Kind::kPause, 4}}));
  EXPECT_TRUE(DueAt(schedule, 5'950'000'000).empty());
  EXPECT_EQ(DueAt(schedule, 6'000'000'000), (std::vector<FaultAction>{{Kind::kResume, 4}}));
  EXPECT_TRUE(DueAt(schedule, 6'050'000'000).empty());
}

TEST(FaultScheduleTest, APauseOfOneRoundResumesWhereItStarts) {
  const std::vector<scenario::FaultSpec> faults = {{scenario::FaultKind::kPause, 1, 3.0, 3.05}};
  FaultSchedule schedule(faults, kRoundNs);

  EXPECT_EQ(DueAt(schedule, 3'000'000'000), (std::vector<FaultAction>{{Kind::kPause, 1}, {Kind::kResume, 1}}));
}

TEST(FaultScheduleTest, FaultsDueTogetherComeInScenarioOrderThenResumes) {
  const std::vector<scenario::FaultSpec> faults = {
      {scenario::FaultKind::kPause, 1, 1.0, 2.05},
      {scenario::FaultKind::kJoin, 5, 1.98, 0},
      {scenario::FaultKind::kCrash, 0, 2.0, 0},
  };
  FaultSchedule schedule(faults, kRoundNs);

  EXPECT_EQ(DueAt(schedule, 1'000'000'000), (std::vector<FaultAction>{{Kind::kPause, 1}}));
  EXPECT_EQ(DueAt(schedule, 2'000'000'000),
            (std::vector<FaultAction>{{Kind::kJoin, 5}, {Kind::kCrash, 0}, {Kind::kResume, 1}}));
}

TEST(FaultScheduleTest, AGridPointSkippedByTheCallerStillDeliversEarlierFaults) {
  const std::vector<scenario::FaultSpec> faults = {{scenario::FaultKind::kJoin, 3, 0.5, 0}};
  FaultSchedule schedule(faults, kRoundNs);

  EXPECT_EQ(DueAt(schedule, 1'000'000'000), (std::vector<FaultAction>{{Kind::kJoin, 3}}));
}

}  // namespace
}  // namespace syrof::lab::sim
