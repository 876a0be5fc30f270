// The built-in apps' NewRound on hand-built maps.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "app_test_support.h"
#include "syrof/lab/apps/catalog.h"

namespace syrof::lab::apps::testing {
namespace {

double Distance(Position a, Position b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m); }

Position Target(const syrof_car_command& command) {
  return {static_cast<double>(command.x_m), static_cast<double>(command.y_m)};
}

// Eight robots spread over the arena, in increasing id order.
MapBuilder SpreadMap() {
  MapBuilder map;
  const std::vector<Position> starts = RandomStarts(7, 8, 0.4);
  for (size_t i = 0; i < starts.size(); ++i) map.Add(static_cast<uint16_t>(i), starts[i].x_m, starts[i].y_m);
  return map;
}

TEST(IdleAppTest, StopsInEveryMode) {
  for (const syrof_mode mode : {SYROF_MODE_COOPERATIVE, SYROF_MODE_AUTONOMOUS}) {
    // Act
    const std::vector<Plan> plans = PlanEveryRobot("idle", {}, SpreadMap(), mode);

    // Assert
    for (const Plan& plan : plans) EXPECT_EQ(plan.command.kind, SYROF_COMMAND_STOP);
  }
}

class MovingAppTest : public ::testing::TestWithParam<const char*> {};

TEST_P(MovingAppTest, AutonomousHoldsStill) {
  // Act
  const std::vector<Plan> plans = PlanEveryRobot(GetParam(), {}, SpreadMap(), SYROF_MODE_AUTONOMOUS);

  // Assert
  for (const Plan& plan : plans) EXPECT_EQ(plan.command.kind, SYROF_COMMAND_STOP);
}

TEST_P(MovingAppTest, CooperativeRobotsMove) {
  // Act
  const std::vector<Plan> plans = PlanEveryRobot(GetParam(), {}, SpreadMap(), SYROF_MODE_COOPERATIVE);

  // Assert
  int moving = 0;
  for (const Plan& plan : plans) moving += plan.command.kind == SYROF_COMMAND_MOVE_TO ? 1 : 0;
  EXPECT_GE(moving, 4);
}

TEST_P(MovingAppTest, SameMapGivesAConsistentSafePlan) {
  // Arrange: robots packed close together, so the safety rule has work.
  MapBuilder map;
  for (uint16_t id = 0; id < 9; ++id) map.Add(id, 1.4 + 0.3 * (id % 3), 1.4 + 0.3 * (id / 3));

  // Act
  const std::vector<Plan> plans = PlanEveryRobot(GetParam(), {}, map, SYROF_MODE_COOPERATIVE);

  // Assert
  for (size_t i = 0; i < plans.size(); ++i) {
    EXPECT_LE(SegmentLengthM(plans[i].segment), 0.8 * kMaxSpeedMps + 0.001);
    if (plans[i].command.kind == SYROF_COMMAND_MOVE_TO) {
      EXPECT_GT(plans[i].command.speed_mps, 0.0f);
      EXPECT_LE(plans[i].command.speed_mps, static_cast<float>(kMaxSpeedMps));
    }
    for (size_t j = i + 1; j < plans.size(); ++j) {
      EXPECT_GE(Distance(plans[i].segment.end, plans[j].segment.end), 2 * kBodyRadiusM) << i << "," << j;
      EXPECT_GE(SegmentDistanceM(plans[i].segment, plans[j].segment), 2 * kBodyRadiusM) << i << "," << j;
    }
  }
}

TEST_P(MovingAppTest, TargetsStayInsideTheArena) {
  // Arrange: robots along the walls.
  MapBuilder map;
  map.Add(0, 0.12, 0.12);
  map.Add(1, 3.88, 0.12);
  map.Add(2, 3.88, 3.88);
  map.Add(3, 0.12, 3.88);

  // Act
  const std::vector<Plan> plans = PlanEveryRobot(GetParam(), {}, map, SYROF_MODE_COOPERATIVE);

  // Assert
  for (const Plan& plan : plans) {
    if (plan.command.kind != SYROF_COMMAND_MOVE_TO) continue;
    EXPECT_GE(plan.command.x_m, kBodyRadiusM);
    EXPECT_LE(plan.command.x_m, kArenaM - kBodyRadiusM);
    EXPECT_GE(plan.command.y_m, kBodyRadiusM);
    EXPECT_LE(plan.command.y_m, kArenaM - kBodyRadiusM);
  }
}

INSTANTIATE_TEST_SUITE_P(Apps, MovingAppTest, ::testing::Values("gather", "circle", "leader_follow"));

TEST(CircleAppTest, OnlyTheDisplacedRobotMovesBackToItsPoint) {
  // Arrange: six robots on their points; robot 3 pulled 0.2 m inwards.
  const std::vector<Position> points = CircleTargets(CircleParams{}, 6, {kArenaM, kArenaM}, kBodyRadiusM);
  MapBuilder map;
  for (uint16_t id = 0; id < 6; ++id) {
    const double pull = id == 3 ? 0.2 / 1.2 : 0.0;
    map.Add(id, points[id].x_m + (2.0 - points[id].x_m) * pull, points[id].y_m + (2.0 - points[id].y_m) * pull);
  }

  // Act
  const std::vector<Plan> plans = PlanEveryRobot("circle", {}, map, SYROF_MODE_COOPERATIVE);

  // Assert
  for (uint16_t id = 0; id < 6; ++id) {
    if (id == 3) {
      ASSERT_EQ(plans[id].command.kind, SYROF_COMMAND_MOVE_TO);
      EXPECT_LT(Distance(Target(plans[id].command), points[3]), 0.001);
      EXPECT_NEAR(plans[id].command.speed_mps, 0.2 / 0.8, 0.002);
    } else {
      EXPECT_EQ(plans[id].command.kind, SYROF_COMMAND_STOP) << id;
    }
  }
}

TEST(CircleAppTest, ReSpacesWhenARobotLeavesTheMap) {
  // Arrange: five robots on the points of six; robot 5 crashed and is gone.
  const std::vector<Position> six = CircleTargets(CircleParams{}, 6, {kArenaM, kArenaM}, kBodyRadiusM);
  const std::vector<Position> five = CircleTargets(CircleParams{}, 5, {kArenaM, kArenaM}, kBodyRadiusM);
  MapBuilder map;
  for (uint16_t id = 0; id < 5; ++id) map.Add(id, six[id].x_m, six[id].y_m);

  // Act
  const std::vector<Plan> plans = PlanEveryRobot("circle", {}, map, SYROF_MODE_COOPERATIVE);

  // Assert: every robot heads for a distinct point of the five.
  std::vector<bool> taken(5, false);
  for (const Plan& plan : plans) {
    size_t nearest = 0;
    for (size_t k = 1; k < 5; ++k) {
      if (Distance(plan.segment.end, five[k]) < Distance(plan.segment.end, five[nearest])) nearest = k;
    }
    const Position direction{five[nearest].x_m - plan.segment.start.x_m, five[nearest].y_m - plan.segment.start.y_m};
    const Position moved{plan.segment.end.x_m - plan.segment.start.x_m, plan.segment.end.y_m - plan.segment.start.y_m};
    EXPECT_GE(direction.x_m * moved.x_m + direction.y_m * moved.y_m, 0.0);
    EXPECT_FALSE(taken[nearest]);
    taken[nearest] = true;
  }
}

TEST(GatherAppTest, PublishesTheCentreOfTheEnclosingCircle) {
  // Arrange
  MapBuilder map;
  map.Add(0, 1.0, 2.0);
  map.Add(1, 3.0, 2.0);
  FakePlatform platform;
  const std::unique_ptr<app::App> gather = MakeBuiltinApp("gather", {});
  uint8_t global_state = 0;
  ASSERT_TRUE(gather->Init(MakeInfo(0, 2), platform, global_state).ok());
  syrof_car_command command{};

  // Act
  ASSERT_TRUE(gather->NewRound(command, map.Build(0, SYROF_MODE_COOPERATIVE), global_state, 0).ok());

  // Assert: 'G', then x = y = 2000 mm little-endian.
  EXPECT_EQ(platform.payload, (std::vector<uint8_t>{'G', 0xD0, 0x07, 0xD0, 0x07}));
  ASSERT_EQ(command.kind, SYROF_COMMAND_MOVE_TO);
  EXPECT_GT(command.x_m, 1.0f);
}

TEST(GatherAppTest, AdoptsTheCentreOfTheSmallestIdThatPublishedOne) {
  // Arrange: robot 1 published (1.5, 1.5), robot 2 (2.5, 2.5).
  MapBuilder map;
  map.Add(0, 1.0, 1.0);
  map.Add(1, 3.0, 1.0, {'G', 0xDC, 0x05, 0xDC, 0x05});
  map.Add(2, 2.0, 3.0, {'G', 0xC4, 0x09, 0xC4, 0x09});
  FakePlatform platform;
  const std::unique_ptr<app::App> gather = MakeBuiltinApp("gather", {});
  uint8_t global_state = 0;
  ASSERT_TRUE(gather->Init(MakeInfo(0, 3), platform, global_state).ok());
  syrof_car_command command{};

  // Act
  ASSERT_TRUE(gather->NewRound(command, map.Build(0, SYROF_MODE_COOPERATIVE), global_state, 0).ok());

  // Assert
  EXPECT_EQ(platform.payload, (std::vector<uint8_t>{'G', 0xDC, 0x05, 0xDC, 0x05}));
}

TEST(GatherAppTest, AutonomousKeepsPublishingTheKnownCentre) {
  // Arrange
  MapBuilder map;
  map.Add(0, 1.0, 2.0);
  map.Add(1, 3.0, 2.0);
  FakePlatform platform;
  const std::unique_ptr<app::App> gather = MakeBuiltinApp("gather", {});
  uint8_t global_state = 0;
  ASSERT_TRUE(gather->Init(MakeInfo(0, 2), platform, global_state).ok());
  syrof_car_command command{};
  ASSERT_TRUE(gather->NewRound(command, map.Build(0, SYROF_MODE_COOPERATIVE, 1), global_state, 0).ok());
  platform.payload.clear();

  // Act
  ASSERT_TRUE(gather->NewRound(command, map.Build(0, SYROF_MODE_AUTONOMOUS, 2), global_state, 1400).ok());

  // Assert
  EXPECT_EQ(command.kind, SYROF_COMMAND_STOP);
  EXPECT_EQ(platform.payload, (std::vector<uint8_t>{'G', 0xD0, 0x07, 0xD0, 0x07}));
}

TEST(LeaderFollowAppTest, LeaderDrivesCounterClockwiseAndTheLineFollows) {
  // Arrange: leader 2 (smallest id) at angle 0 of the path, followers on
  // their slots.
  const LeaderFollowParams params;
  const LeaderPath path = MakeLeaderPath(params, 4, {kArenaM, kArenaM}, kBodyRadiusM);
  const std::vector<Position> slots = FollowerSlots(path, 0.0, 3);
  MapBuilder map;
  map.Add(2, PathPoint(path, 0.0).x_m, PathPoint(path, 0.0).y_m);
  for (uint16_t k = 0; k < 3; ++k) map.Add(static_cast<uint16_t>(3 + k), slots[k].x_m, slots[k].y_m);

  // Act
  const std::vector<Plan> plans = PlanEveryRobot("leader_follow", {}, map, SYROF_MODE_COOPERATIVE);

  // Assert
  const double step_m = LeaderStepM(params, kBodyRadiusM, kManeuverMs / 1000.0);
  const double step_rad = 2 * std::asin(step_m / (2 * path.radius_m));
  ASSERT_EQ(plans[0].command.kind, SYROF_COMMAND_MOVE_TO);
  EXPECT_LT(Distance(Target(plans[0].command), PathPoint(path, step_rad)), 0.001);
  const std::vector<Position> next = FollowerSlots(path, step_rad, 3);
  for (size_t k = 0; k < 3; ++k) {
    ASSERT_EQ(plans[k + 1].command.kind, SYROF_COMMAND_MOVE_TO) << k;
    EXPECT_LT(Distance(Target(plans[k + 1].command), next[k]), 0.001) << k;
  }
}

}  // namespace
}  // namespace syrof::lab::apps::testing
