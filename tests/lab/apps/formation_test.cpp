#include "syrof/lab/apps/formation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace syrof::lab::apps {
namespace {

constexpr ArenaSize kArena{4.0, 4.0};
constexpr double kRadiusM = 0.1;

double Distance(Position a, Position b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m); }

TEST(HexSlotsTest, NearestFirstAndSpacedApart) {
  // Act
  const std::vector<Position> slots = HexSlots(19, 0.3);

  // Assert: the centre, ring 1 (6 at 0.3 m), then 12 of ring 2.
  ASSERT_EQ(slots.size(), 19u);
  EXPECT_DOUBLE_EQ(Distance(slots[0], {0, 0}), 0.0);
  for (size_t k = 1; k < 7; ++k) EXPECT_NEAR(Distance(slots[k], {0, 0}), 0.3, 1e-12);
  for (size_t k = 1; k < slots.size(); ++k) {
    EXPECT_LE(Distance(slots[k - 1], {0, 0}), Distance(slots[k], {0, 0}) + 1e-12);
  }
  for (size_t i = 0; i < slots.size(); ++i) {
    for (size_t j = i + 1; j < slots.size(); ++j) EXPECT_GE(Distance(slots[i], slots[j]), 0.3 - 1e-9);
  }
}

TEST(HexSlotsTest, RingRadiusIsTheFarthestSlot) {
  EXPECT_DOUBLE_EQ(HexRingRadiusM(1, 0.3), 0.0);
  EXPECT_NEAR(HexRingRadiusM(7, 0.3), 0.3, 1e-12);
  EXPECT_NEAR(HexRingRadiusM(8, 0.3), 0.3 * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(HexRingRadiusM(19, 0.3), 0.6, 1e-12);
}

TEST(GatherSpacingTest, GapRaisedAboveTheMargin) {
  EXPECT_NEAR(GatherSpacingM({0.1, 0.1, 0.08}, kRadiusM), 0.3, 1e-12);
  EXPECT_NEAR(GatherSpacingM({0.05, 0.1, 0.08}, kRadiusM), 0.2 + 0.08 + kPlanSlackM, 1e-12);
}

TEST(GatherSlotsTest, CentreNearAWallMovesInside) {
  // Act
  const std::vector<Position> slots = GatherSlots({0.0, 2.0}, 7, GatherParams{}, kArena, kRadiusM);

  // Assert
  for (const Position& slot : slots) EXPECT_GE(slot.x_m, kRadiusM + GatherParams{}.margin_m - 1e-9);
}

TEST(CircleTargetsTest, EvenlySpacedFromAngleZero) {
  // Act
  const std::vector<Position> targets = CircleTargets(CircleParams{}, 6, kArena, kRadiusM);

  // Assert
  ASSERT_EQ(targets.size(), 6u);
  EXPECT_NEAR(targets[0].x_m, 2.0 + 1.2, 1e-12);
  EXPECT_NEAR(targets[0].y_m, 2.0, 1e-12);
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_NEAR(Distance(targets[k], {2, 2}), 1.2, 1e-12);
    EXPECT_NEAR(Distance(targets[k], targets[(k + 1) % 6]), 1.2, 1e-9);  // hexagon side = radius
  }
}

TEST(CircleTargetsTest, TooSmallARadiusGrowsToFitTheRobots) {
  // Arrange
  CircleParams params;
  params.radius_m = 0.1;

  // Act
  const std::vector<Position> targets = CircleTargets(params, 10, kArena, kRadiusM);

  // Assert
  EXPECT_GE(Distance(targets[0], targets[1]), 2 * kRadiusM + params.margin_m + kPlanSlackM - 1e-9);
}

TEST(CircleTargetsTest, StaysInsideTheArena) {
  // Arrange: centre in a corner, radius larger than the arena allows.
  CircleParams params;
  params.radius_m = 5;
  params.centre_x_m = 0.2;
  params.centre_y_m = 3.9;

  // Act
  const std::vector<Position> targets = CircleTargets(params, 8, kArena, kRadiusM);

  // Assert
  const double keep_off_m = kRadiusM + params.margin_m - 1e-9;
  for (const Position& target : targets) {
    EXPECT_GE(target.x_m, keep_off_m);
    EXPECT_LE(target.x_m, kArena.width_m - keep_off_m);
    EXPECT_GE(target.y_m, keep_off_m);
    EXPECT_LE(target.y_m, kArena.height_m - keep_off_m);
  }
}

TEST(LeaderPathTest, SlotsTrailTheLeaderAtTheSpacing) {
  // Arrange
  const LeaderFollowParams params;
  const LeaderPath path = MakeLeaderPath(params, 5, kArena, kRadiusM);
  const Position leader = PathPoint(path, 0.5);

  // Act
  const std::vector<Position> slots = FollowerSlots(path, PathAngleRad(path, leader), 4);

  // Assert: each slot one spacing behind the previous robot, clockwise.
  ASSERT_EQ(slots.size(), 4u);
  EXPECT_NEAR(Distance(leader, slots[0]), params.spacing_m, 1e-9);
  for (size_t k = 1; k < slots.size(); ++k) EXPECT_NEAR(Distance(slots[k - 1], slots[k]), params.spacing_m, 1e-9);
  EXPECT_LT(PathAngleRad(path, slots[0]), 0.5);
}

TEST(LeaderPathTest, CrowdedLineSharesTheWholeCircle) {
  // Act
  const LeaderPath path = MakeLeaderPath(LeaderFollowParams{}, 40, kArena, kRadiusM);

  // Assert
  EXPECT_NEAR(path.slot_angle_rad, 2 * std::numbers::pi / 40, 1e-12);
}

// The cap leaves room for the safety filter's disc growth at four own
// sigmas too: with the default spacing a follower's next slot is 0.345 m
// from where its predecessor starts (0.30 m before, which four sigmas held
// followers off: docs/safety.md, "Margin coverage").
TEST(LeaderStepTest, SlowedSoTheLineCanFollowInOneEpoch) {
  EXPECT_NEAR(LeaderStepM(LeaderFollowParams{}, kRadiusM, 1.0), 0.4 - 0.2 - 0.08 - kPlanSlackM - kFilterGrowthM, 1e-12);
  EXPECT_NEAR(LeaderStepM(LeaderFollowParams{}, kRadiusM, 1.0), 0.055, 1e-12);
  LeaderFollowParams wide;
  wide.spacing_m = 1.0;
  EXPECT_NEAR(LeaderStepM(wide, kRadiusM, 1.0), 0.15, 1e-12);
}

}  // namespace
}  // namespace syrof::lab::apps
