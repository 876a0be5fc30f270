// RoundGrid (sim_dds/src/round_grid.h): the DDS world's rounds on its clock,
// and the origin that follows aligning robots.
#include "round_grid.h"

#include <gtest/gtest.h>

namespace syrof::sim_dds {
namespace {

constexpr int64_t kGridRoundNs = 50'000'000;

TEST(RoundGrid, RoundsAreFlooredOnBothSidesOfTheOrigin) {
  RoundGrid grid(kGridRoundNs, 3);
  grid.Start(1'000'000'000);
  EXPECT_EQ(grid.RoundAt(1'000'000'000), 0);
  EXPECT_EQ(grid.RoundAt(1'049'999'999), 0);
  EXPECT_EQ(grid.RoundAt(1'050'000'000), 1);
  EXPECT_EQ(grid.RoundAt(999'999'999), -1);  // just before the origin: round -1, not 0
  EXPECT_EQ(grid.RoundAt(950'000'000), -1);
  EXPECT_EQ(grid.RoundAt(949'999'999), -2);
  EXPECT_EQ(grid.StartOf(4), 1'200'000'000);
}

TEST(RoundGrid, TheOriginFollowsTheMedianOfTheRunningRobotsThatReported) {
  RoundGrid grid(kGridRoundNs, 4);
  grid.Start(1'000'000'000);
  const auto all = [](uint16_t) { return true; };
  grid.FollowRobots(all);  // nobody reported: unchanged
  EXPECT_EQ(grid.origin_ns(), 1'000'000'000);

  grid.NoteRound(0, 10, 1'500'000'000 + 1'000);  // origin 1'000'001'000
  grid.NoteRound(1, 10, 1'500'000'000 + 3'000);  // origin 1'000'003'000
  grid.NoteRound(2, 12, 1'600'000'000 + 9'000);  // origin 1'000'009'000
  grid.FollowRobots(all);
  EXPECT_EQ(grid.origin_ns(), 1'000'003'000);

  // Robot 2 no longer runs: of two, the upper one.
  grid.FollowRobots([](uint16_t id) { return id != 2; });
  EXPECT_EQ(grid.origin_ns(), 1'000'003'000);
  grid.FollowRobots([](uint16_t id) { return id == 0 || id == 2; });
  EXPECT_EQ(grid.origin_ns(), 1'000'009'000);
  EXPECT_EQ(grid.RoundAt(1'000'009'000 + 3 * kGridRoundNs), 3);
}

}  // namespace
}  // namespace syrof::sim_dds
