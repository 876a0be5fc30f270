#include "syrof/lab/apps/builtin_goals.h"

#include <gtest/gtest.h>

#include <vector>

namespace syrof::lab::apps {
namespace {

constexpr ArenaSize kGoalArena{4.0, 4.0};
constexpr double kGoalRadiusM = 0.1;

std::vector<GoalPose> PosesAt(const std::vector<Position>& positions) {
  std::vector<GoalPose> poses;
  for (size_t i = 0; i < positions.size(); ++i) {
    poses.push_back({static_cast<uint16_t>(i), positions[i].x_m, positions[i].y_m, 0.0, true});
  }
  return poses;
}

TEST(EvaluateGoalTest, IdleHasNoGoal) {
  // Act
  const GoalReport report = EvaluateGoal("idle", {}, kGoalArena, kGoalRadiusM, PosesAt({{1, 1}, {1.05, 1}}));

  // Assert
  EXPECT_TRUE(report.reached);
  EXPECT_EQ(report.error_m, 0.0);
}

TEST(EvaluateGoalTest, UnknownAppIsNotReached) {
  EXPECT_FALSE(EvaluateGoal("dance", {}, kGoalArena, kGoalRadiusM, PosesAt({{1, 1}})).reached);
}

TEST(EvaluateGoalTest, CircleReachedOnShuffledPointsWithinTolerance) {
  // Arrange: robots on the points in another order, one 0.05 m off.
  std::vector<Position> points = CircleTargets(CircleParams{}, 6, kGoalArena, kGoalRadiusM);
  std::swap(points[0], points[4]);
  points[2].x_m += 0.05;

  // Act
  const GoalReport report = EvaluateGoal("circle", {}, kGoalArena, kGoalRadiusM, PosesAt(points));

  // Assert
  EXPECT_TRUE(report.reached) << report.detail;
  EXPECT_NEAR(report.error_m, 0.05, 1e-3);
}

TEST(EvaluateGoalTest, CircleMissedWhenARobotIsOffItsPoint) {
  // Arrange
  std::vector<Position> points = CircleTargets(CircleParams{}, 6, kGoalArena, kGoalRadiusM);
  points[2].y_m += 0.3;

  // Act
  const GoalReport report = EvaluateGoal("circle", {}, kGoalArena, kGoalRadiusM, PosesAt(points));

  // Assert
  EXPECT_FALSE(report.reached);
  EXPECT_NEAR(report.error_m, 0.3, 1e-3);
}

TEST(EvaluateGoalTest, CircleCountsOnlyPresentRobots) {
  // Arrange: five robots on the five-point circle, a sixth crashed elsewhere.
  std::vector<GoalPose> poses = PosesAt(CircleTargets(CircleParams{}, 5, kGoalArena, kGoalRadiusM));
  poses.push_back({9, 0.5, 0.5, 0.0, false});

  // Act
  const GoalReport report = EvaluateGoal("circle", {}, kGoalArena, kGoalRadiusM, poses);

  // Assert
  EXPECT_TRUE(report.reached) << report.detail;
}

TEST(EvaluateGoalTest, CircleParamsChangeTheGoal) {
  // Arrange
  const std::map<std::string, double> params{{"radius_m", 0.8}, {"centre_x_m", 1.5}};
  const std::vector<Position> points = CircleTargets(ReadCircleParams(params), 4, kGoalArena, kGoalRadiusM);

  // Act, assert
  EXPECT_TRUE(EvaluateGoal("circle", params, kGoalArena, kGoalRadiusM, PosesAt(points)).reached);
  EXPECT_FALSE(EvaluateGoal("circle", {}, kGoalArena, kGoalRadiusM, PosesAt(points)).reached);
}

TEST(EvaluateGoalTest, GatherReachedWhenPacked) {
  // Arrange
  const std::vector<Position> slots = GatherSlots({2, 2}, 7, GatherParams{}, kGoalArena, kGoalRadiusM);

  // Act
  const GoalReport report = EvaluateGoal("gather", {}, kGoalArena, kGoalRadiusM, PosesAt(slots));

  // Assert
  EXPECT_TRUE(report.reached) << report.detail;
  EXPECT_LT(report.error_m, 0.001);  // millimetre rounding of the poses
}

TEST(EvaluateGoalTest, GatherMissedWhenSpreadOut) {
  // Arrange
  const std::vector<Position> spread{{1, 1}, {3, 1}, {2, 3}};

  // Act
  const GoalReport report = EvaluateGoal("gather", {}, kGoalArena, kGoalRadiusM, PosesAt(spread));

  // Assert
  EXPECT_FALSE(report.reached);
  EXPECT_GT(report.error_m, 0.5);
}

TEST(EvaluateGoalTest, OverlappingBodiesMissTheGoal) {
  // Arrange: packed tighter than two radii.
  const std::vector<Position> slots = GatherSlots({2, 2}, 3, {0.1, 0.1, 0.08}, kGoalArena, kGoalRadiusM);
  std::vector<GoalPose> poses = PosesAt(slots);
  poses[1].x_m = poses[0].x_m + 0.15;
  poses[1].y_m = poses[0].y_m;

  // Act
  const GoalReport report = EvaluateGoal("gather", {}, kGoalArena, kGoalRadiusM, poses);

  // Assert
  EXPECT_FALSE(report.reached);
  EXPECT_NE(report.detail.find("overlap"), std::string::npos) << report.detail;
}

TEST(EvaluateGoalTest, MixedKindsOverlapByTheirOwnRadii) {
  // Arrange: an omni body (0.10 m) and a rover (0.12 m) 0.21 m apart: clear
  // by two omni radii (0.20 m), overlapping by their own (0.22 m).
  std::vector<GoalPose> poses = PosesAt({{1.0, 1.0}, {1.21, 1.0}});
  poses[0].radius_m = 0.10;
  poses[1].radius_m = 0.12;

  // Act
  const GoalReport report = EvaluateGoal("gather", {}, kGoalArena, kGoalRadiusM, poses);

  // Assert
  EXPECT_FALSE(report.reached);
  EXPECT_NE(report.detail.find("robots 0 and 1 overlap"), std::string::npos) << report.detail;
  EXPECT_NE(report.detail.find("0.220"), std::string::npos) << report.detail;
}

TEST(EvaluateGoalTest, LeaderFollowReachedWithTheLineBehindTheLeader) {
  // Arrange: leader 0 at angle 1 rad, followers on their slots.
  const LeaderPath path = MakeLeaderPath(LeaderFollowParams{}, 5, kGoalArena, kGoalRadiusM);
  std::vector<Position> positions{PathPoint(path, 1.0)};
  for (const Position& slot : FollowerSlots(path, 1.0, 4)) positions.push_back(slot);

  // Act
  const GoalReport report = EvaluateGoal("leader_follow", {}, kGoalArena, kGoalRadiusM, PosesAt(positions));

  // Assert
  EXPECT_TRUE(report.reached) << report.detail;
  EXPECT_LT(report.error_m, 1e-3);
}

TEST(EvaluateGoalTest, LeaderFollowMissedWhenTheLineIsAhead) {
  // Arrange: followers ahead of the leader instead of behind.
  const LeaderPath path = MakeLeaderPath(LeaderFollowParams{}, 5, kGoalArena, kGoalRadiusM);
  std::vector<Position> positions{PathPoint(path, 1.0)};
  for (int k = 1; k <= 4; ++k) positions.push_back(PathPoint(path, 1.0 + k * path.slot_angle_rad));

  // Act
  const GoalReport report = EvaluateGoal("leader_follow", {}, kGoalArena, kGoalRadiusM, PosesAt(positions));

  // Assert
  EXPECT_FALSE(report.reached);
}

TEST(EvaluateGoalTest, NoPresentRobotReachesTheGoal) {
  // Arrange
  std::vector<GoalPose> poses = PosesAt({{1, 1}});
  poses[0].present = false;

  // Act, assert
  EXPECT_TRUE(EvaluateGoal("circle", {}, kGoalArena, kGoalRadiusM, poses).reached);
}

}  // namespace
}  // namespace syrof::lab::apps
