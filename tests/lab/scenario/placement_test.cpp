#include "placement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "scenario_test_util.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::Load;

TEST(Placement, GridIsRowMajorFromTheLowerLeftAndCentred) {
  const LoadResult result = Load(
      "robots: { count: 5, placement: grid, spacing_m: 0.5, centre: {x_m: 2, y_m: 2} }\n"
      "app: builtin:idle\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<RobotSpec>& robots = result.scenario->robots;
  ASSERT_EQ(robots.size(), 5u);  // 3 columns, 2 rows
  EXPECT_EQ(result.scenario->placement, Placement::kGrid);
  EXPECT_DOUBLE_EQ(robots[0].x_m, 1.5);
  EXPECT_DOUBLE_EQ(robots[0].y_m, 1.75);
  EXPECT_DOUBLE_EQ(robots[2].x_m, 2.5);
  EXPECT_DOUBLE_EQ(robots[2].y_m, 1.75);
  EXPECT_DOUBLE_EQ(robots[3].x_m, 1.5);
  EXPECT_DOUBLE_EQ(robots[3].y_m, 2.25);
  EXPECT_DOUBLE_EQ(robots[4].x_m, 2.0);
  for (const RobotSpec& robot : robots) EXPECT_EQ(robot.heading_rad, 0);
}

TEST(Placement, CircleStartsAtAngleZeroAndFacesOutwards) {
  const LoadResult result = Load(
      "robots: { count: 4, placement: circle, radius_m: 1, centre: {x_m: 2, y_m: 2} }\n"
      "app: builtin:idle\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<RobotSpec>& robots = result.scenario->robots;
  ASSERT_EQ(robots.size(), 4u);
  EXPECT_DOUBLE_EQ(robots[0].x_m, 3);
  EXPECT_DOUBLE_EQ(robots[0].y_m, 2);
  EXPECT_DOUBLE_EQ(robots[0].heading_rad, 0);
  EXPECT_NEAR(robots[1].x_m, 2, 1e-12);
  EXPECT_DOUBLE_EQ(robots[1].y_m, 3);
  EXPECT_DOUBLE_EQ(robots[1].heading_rad, std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(robots[2].heading_rad, std::numbers::pi);
  EXPECT_DOUBLE_EQ(robots[3].heading_rad, -std::numbers::pi / 2);
}

TEST(Placement, CircleDefaultsToTheArenaCentreAndAQuarterOfItsSide) {
  const LoadResult result = Load("robots: { count: 2, placement: circle }\napp: builtin:idle\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_DOUBLE_EQ(result.scenario->robots[0].x_m, 3);
  EXPECT_DOUBLE_EQ(result.scenario->robots[1].x_m, 1);
}

TEST(Placement, ExplicitTakesEveryPoseAndItsKind) {
  const LoadResult result = Load(
      "robots:\n"
      "  kind: rover\n"
      "  poses:\n"
      "    - { x_m: 1, y_m: 1, heading_rad: 0.5 }\n"
      "    - { x_m: 3, y_m: 1, kind: omni }\n"
      "app: builtin:idle\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<RobotSpec>& robots = result.scenario->robots;
  ASSERT_EQ(robots.size(), 2u);
  EXPECT_EQ(result.scenario->placement, Placement::kExplicit);
  EXPECT_EQ(robots[0].kind, world::RobotKind::kRover);
  EXPECT_DOUBLE_EQ(robots[0].heading_rad, 0.5);
  EXPECT_EQ(robots[1].kind, world::RobotKind::kOmni);
  EXPECT_DOUBLE_EQ(robots[1].x_m, 3);
  EXPECT_EQ(robots[1].id, 1);
}

TEST(Placement, RandomKeepsBodiesInsideAndApart) {
  const LoadResult result =
      Load("robots: { count: 20, placement: random, min_separation_m: 0.2 }\napp: builtin:idle\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<RobotSpec>& robots = result.scenario->robots;
  for (size_t a = 0; a < robots.size(); ++a) {
    EXPECT_GE(robots[a].x_m, 0.1);
    EXPECT_LE(robots[a].x_m, 3.9);
    EXPECT_GE(robots[a].y_m, 0.1);
    EXPECT_LE(robots[a].y_m, 3.9);
    for (size_t b = 0; b < a; ++b) {
      EXPECT_GE(std::hypot(robots[a].x_m - robots[b].x_m, robots[a].y_m - robots[b].y_m), 0.4);
    }
  }
}

TEST(Placement, RandomIsTheSameForASeedAndDiffersForAnother) {
  const std::string text = "robots: { count: 8, placement: random }\napp: builtin:idle\n";
  Overrides seed_5;
  seed_5.seed = 5;
  Overrides seed_6;
  seed_6.seed = 6;

  const LoadResult first = Load(text, seed_5);
  const LoadResult again = Load(text, seed_5);
  const LoadResult other = Load(text, seed_6);

  ASSERT_TRUE(first.ok() && again.ok() && other.ok());
  bool any_different = false;
  for (size_t i = 0; i < first.scenario->robots.size(); ++i) {
    const RobotSpec& a = first.scenario->robots[i];
    const RobotSpec& b = again.scenario->robots[i];
    const RobotSpec& c = other.scenario->robots[i];
    EXPECT_EQ(a.x_m, b.x_m);
    EXPECT_EQ(a.y_m, b.y_m);
    EXPECT_EQ(a.heading_rad, b.heading_rad);
    any_different = any_different || a.x_m != c.x_m || a.y_m != c.y_m;
  }
  EXPECT_TRUE(any_different);
}

TEST(Placement, RandomFailsAfterBoundedTriesWhenRobotsDoNotFit) {
  const LoadResult result = Load(
      "arena: { width_m: 1, height_m: 1 }\n"
      "robots: { count: 30, placement: random, min_separation_m: 0.1 }\n"
      "app: builtin:idle\n");

  EXPECT_TRUE(FailsAt(result, 2, 9, {"robots", "no free spot", "1000 tries"}));
}

TEST(Placement, OverlapNamesBothRobotsAndPositions) {
  const LoadResult result = Load(
      "robots:\n"
      "  poses:\n"
      "    - { x_m: 1, y_m: 1 }\n"
      "    - { x_m: 2, y_m: 2 }\n"
      "    - { x_m: 1.15, y_m: 1 }\n"
      "app: builtin:idle\n");

  EXPECT_TRUE(FailsAt(result, 5, 7,
                      {"robots.poses[2]", "robot 0 at (1, 1)", "robot 2 at (1.15, 1)", "overlap", "0.2 m"}));
}

TEST(Placement, GridTooTightOverlaps) {
  const LoadResult result = Load("robots: { count: 4, spacing_m: 0.15 }\napp: builtin:idle\n");

  EXPECT_TRUE(FailsAt(result, 1, 9, {"robots:", "robot 0", "robot 1", "overlap"}));
}

TEST(Placement, RobotOutsideTheArenaIsNamed) {
  const LoadResult result = Load(
      "robots:\n"
      "  poses:\n"
      "    - { x_m: 1, y_m: 1 }\n"
      "    - { x_m: 3.95, y_m: 2 }\n"
      "app: builtin:idle\n");

  EXPECT_TRUE(FailsAt(result, 4, 7, {"robots.poses[1]", "robot 1 at (3.95, 2)", "outside the arena"}));
}

TEST(Placement, CircleTooLargeLeavesTheArena) {
  const LoadResult result = Load("robots: { count: 3, placement: circle, radius_m: 2 }\napp: builtin:idle\n");

  EXPECT_TRUE(FailsAt(result, 1, 9, {"robot 0 at (4, 2)", "outside the arena"}));
}

}  // namespace
}  // namespace syrof::lab::scenario
