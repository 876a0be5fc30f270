// Kinematic closed loop: every robot runs its own app instance on the same
// COOPERATIVE map and drives its segment exactly; checks that the goals are
// reached from seeded random starts without two swept segments ever coming
// closer than two body radii.
#include <gtest/gtest.h>

#include <cstdio>

#include "app_test_support.h"

namespace syrof::lab::apps::testing {
namespace {

struct LoopCase {
  const char* app;
  size_t robots;
  uint64_t seed;
  int max_epochs;
};

class ClosedLoopTest : public ::testing::TestWithParam<LoopCase> {};

TEST_P(ClosedLoopTest, ReachesGoalWithoutContact) {
  // Arrange
  const LoopCase& loop = GetParam();
  const std::vector<Position> starts = RandomStarts(loop.seed, loop.robots, 0.4);

  // Act
  const LoopResult result = RunClosedLoop(loop.app, {}, starts, loop.max_epochs);

  // Assert
  std::printf("[ loop ] %s n=%zu seed=%llu: goal after %d epochs, closest %.3f m, %s\n", loop.app, loop.robots,
              static_cast<unsigned long long>(loop.seed), result.epochs_to_goal, result.min_segment_distance_m,
              result.final_report.detail.c_str());
  EXPECT_GT(result.epochs_to_goal, 0) << result.final_report.detail;
  EXPECT_GE(result.min_segment_distance_m, 2 * kBodyRadiusM);
  EXPECT_LE(result.longest_move_m, 0.8 * kMaxSpeedMps * kManeuverMs / 1000.0 + 0.002);
  EXPECT_LE(result.fastest_mps, kMaxSpeedMps + 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Circle, ClosedLoopTest,
                         ::testing::Values(LoopCase{"circle", 5, 1, 40}, LoopCase{"circle", 8, 2, 40},
                                           LoopCase{"circle", 10, 3, 40}, LoopCase{"circle", 12, 4, 40}));
INSTANTIATE_TEST_SUITE_P(Gather, ClosedLoopTest,
                         ::testing::Values(LoopCase{"gather", 5, 11, 40}, LoopCase{"gather", 8, 12, 40},
                                           LoopCase{"gather", 10, 13, 40}, LoopCase{"gather", 12, 14, 40}));
INSTANTIATE_TEST_SUITE_P(LeaderFollow, ClosedLoopTest,
                         ::testing::Values(LoopCase{"leader_follow", 4, 21, 60}, LoopCase{"leader_follow", 6, 22, 60},
                                           LoopCase{"leader_follow", 8, 23, 60}));

}  // namespace
}  // namespace syrof::lab::apps::testing
