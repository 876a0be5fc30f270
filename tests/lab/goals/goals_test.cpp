// The declarative goal checks on hand-made poses: each check's pass, its
// failure with the reason a student reads, and the schedules (every epoch,
// deadline, coverage over the run).
#include "syrof/lab/goals/goals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace syrof::lab::goals {
namespace {

std::vector<RobotPose> Poses(std::initializer_list<Point> points) {
  std::vector<RobotPose> poses;
  uint16_t id = 0;
  for (const Point& p : points) poses.push_back({id++, p.x_m, p.y_m, 0.1});
  return poses;
}

GoalCheck Slots(std::vector<Point> points, bool by_id, double tolerance_m) {
  GoalCheck check;
  check.kind = CheckKind::kSlots;
  check.name = "slots";
  check.points = std::move(points);
  check.by_id = by_id;
  check.tolerance_m = tolerance_m;
  return check;
}

TEST(GoalsTest, SlotsByMatchingAcceptAnyAssignment) {
  Workspace workspace;
  const GoalCheck check = Slots({{1, 1}, {2, 1}, {3, 1}}, false, 0.1);

  const Measure measure = MeasurePoses(check, Poses({{3.02, 1}, {1, 1.05}, {2, 1}}), workspace);

  EXPECT_TRUE(measure.holds) << measure.reason;
  EXPECT_NEAR(measure.value, 0.05, 1e-3);
}

TEST(GoalsTest, SlotsByIdNameTheRobotFarFromItsSlot) {
  Workspace workspace;
  const GoalCheck check = Slots({{1, 1}, {2, 1}, {3, 1}}, true, 0.1);

  const Measure measure = MeasurePoses(check, Poses({{1, 1}, {2, 1.42}, {3, 1}}), workspace);

  EXPECT_FALSE(measure.holds);
  EXPECT_NEAR(measure.value, 0.42, 1e-9);
  EXPECT_EQ(measure.reason, "robot 1 is 0.420 m from its slot (2.000, 1.000), tolerance 0.100 m");
}

TEST(GoalsTest, SlotsByIdRefuseSwappedRobots) {
  Workspace workspace;
  const GoalCheck check = Slots({{1, 1}, {2, 1}}, true, 0.1);

  EXPECT_FALSE(MeasurePoses(check, Poses({{2, 1}, {1, 1}}), workspace).holds);
  EXPECT_TRUE(MeasurePoses(Slots({{1, 1}, {2, 1}}, false, 0.1), Poses({{2, 1}, {1, 1}}), workspace).holds);
}

GoalCheck Shape(std::vector<Point> points, double tolerance_m) {
  GoalCheck check;
  check.kind = CheckKind::kShape;
  check.points = std::move(points);
  check.tolerance_m = tolerance_m;
  return check;
}

// An L of four points, moved by (1.5, 2) and turned by 37 degrees, robots
// listed in another order than the points.
TEST(GoalsTest, ShapeHoldsUpToTranslationAndRotation) {
  Workspace workspace;
  const std::vector<Point> shape = {{0, 0}, {0, 0.6}, {0, 1.2}, {0.6, 0}};
  const double angle = 37.0 * std::numbers::pi / 180.0;
  std::vector<RobotPose> robots;
  const int order[] = {2, 0, 3, 1};
  for (uint16_t i = 0; i < 4; ++i) {
    const Point& p = shape[order[i]];
    robots.push_back({i, 1.5 + std::cos(angle) * p.x_m - std::sin(angle) * p.y_m,
                      2 + std::sin(angle) * p.x_m + std::cos(angle) * p.y_m, 0.1});
  }

  const Measure measure = MeasurePoses(Shape(shape, 0.05), robots, workspace);

  EXPECT_TRUE(measure.holds) << measure.reason;
  EXPECT_LT(measure.value, 0.01);
}

TEST(GoalsTest, ShapeFailsWhenOneRobotIsOutOfPlace) {
  Workspace workspace;
  const std::vector<Point> shape = {{0, 0}, {0, 0.6}, {0, 1.2}, {0.6, 0}};
  // A straight line of four is no L.
  const Measure measure = MeasurePoses(Shape(shape, 0.05), Poses({{1, 1}, {1, 1.6}, {1, 2.2}, {1, 2.8}}), workspace);

  EXPECT_FALSE(measure.holds);
  EXPECT_GT(measure.value, 0.2);
  EXPECT_NE(measure.reason.find("from its point of the shape at the best alignment"), std::string::npos)
      << measure.reason;
}

TEST(GoalsTest, ShapeIsDeterministic) {
  Workspace workspace;
  const GoalCheck check = Shape({{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0.5, 1.7}}, 0.1);
  const std::vector<RobotPose> robots = Poses({{1, 1}, {2.1, 1.2}, {1.1, 2}, {2.2, 2.1}, {1.7, 2.9}});

  const Measure first = MeasurePoses(check, robots, workspace);
  const Measure second = MeasurePoses(check, robots, workspace);

  EXPECT_EQ(first.value, second.value);
  EXPECT_EQ(first.reason, second.reason);
}

TEST(GoalsTest, ShapeNeedsOnePointPerRunningRobot) {
  Workspace workspace;
  const Measure measure = MeasurePoses(Shape({{0, 0}, {1, 0}, {0, 1}}, 0.1), Poses({{1, 1}, {2, 1}}), workspace);

  EXPECT_FALSE(measure.holds);
  EXPECT_EQ(measure.reason, "2 robots are running; the shape has 3 points");
}

GoalCheck Line(double spacing_m, std::optional<double> direction_rad) {
  GoalCheck check;
  check.kind = CheckKind::kLine;
  check.spacing_m = spacing_m;
  check.direction_rad = direction_rad;
  check.tolerance_m = 0.05;
  return check;
}

TEST(GoalsTest, LineSortedByIdHoldsInAnyDirectionWhenFree) {
  Workspace workspace;
  const Measure measure = MeasurePoses(Line(0.5, std::nullopt), Poses({{1, 1}, {1.3, 1.4}, {1.6, 1.8}}), workspace);

  EXPECT_TRUE(measure.holds) << measure.reason;
}

TEST(GoalsTest, LineOutOfIdOrderFails) {
  Workspace workspace;
  const Measure measure = MeasurePoses(Line(0.5, 0.0), Poses({{1, 1}, {2, 1}, {1.5, 1}}), workspace);

  EXPECT_FALSE(measure.holds);
  EXPECT_NEAR(measure.value, 0.5, 1e-9);
  EXPECT_NE(measure.reason.find("robot 1 is 0.500 m from its place on the line by id"), std::string::npos)
      << measure.reason;
}

TEST(GoalsTest, LineWithAGivenDirectionRefusesTheOppositeOne) {
  Workspace workspace;
  EXPECT_TRUE(MeasurePoses(Line(0.5, 0.0), Poses({{1, 1}, {1.5, 1}, {2, 1}}), workspace).holds);
  EXPECT_FALSE(MeasurePoses(Line(0.5, std::numbers::pi), Poses({{1, 1}, {1.5, 1}, {2, 1}}), workspace).holds);
}

GoalCheck Gathered(double radius_m, std::optional<Point> centre = std::nullopt) {
  GoalCheck check;
  check.kind = CheckKind::kGathered;
  check.radius_m = radius_m;
  check.centre = centre;
  return check;
}

TEST(GoalsTest, GatheredMeasuresTheSmallestEnclosingCircle) {
  Workspace workspace;
  const std::vector<RobotPose> robots = Poses({{1, 1}, {1.6, 1}, {1.3, 1.2}});

  const Measure inside = MeasurePoses(Gathered(0.35), robots, workspace);
  const Measure outside = MeasurePoses(Gathered(0.25), robots, workspace);

  EXPECT_TRUE(inside.holds) << inside.reason;
  EXPECT_NEAR(inside.value, 0.3, 2e-3);
  EXPECT_FALSE(outside.holds);
}

TEST(GoalsTest, GatheredAroundAGivenCentreNamesTheFarthestRobot) {
  Workspace workspace;
  const Measure measure = MeasurePoses(Gathered(0.5, Point{1, 1}), Poses({{1, 1.2}, {1.9, 1}}), workspace);

  EXPECT_FALSE(measure.holds);
  EXPECT_EQ(measure.reason, "robot 1 is 0.900 m from (1.000, 1.000); the limit is 0.500 m");
}

GoalCheck WithInput(GoalCheck check, GoalCheck::InputUse use, std::vector<double> values) {
  check.input_use = use;
  check.input = "key";
  check.input_values = std::move(values);
  return check;
}

TEST(GoalsTest, LineOrderedByAnInputFollowsItsValuesNotTheIds) {
  Workspace workspace;
  // Robot 2 has the smallest key, robot 0 the largest: the line runs 2, 1, 0.
  const GoalCheck by_key = WithInput(Line(0.5, 0.0), GoalCheck::InputUse::kOrderBy, {9, 4, 1});
  const Measure sorted = MeasurePoses(by_key, Poses({{2, 1}, {1.5, 1}, {1, 1}}), workspace);
  const Measure by_id = MeasurePoses(by_key, Poses({{1, 1}, {1.5, 1}, {2, 1}}), workspace);

  EXPECT_TRUE(sorted.holds) << sorted.reason;
  EXPECT_NE(sorted.reason.find("on a line by key"), std::string::npos) << sorted.reason;
  EXPECT_FALSE(by_id.holds);
  EXPECT_NE(by_id.reason.find("on the line by key"), std::string::npos) << by_id.reason;
}

TEST(GoalsTest, LineOrderedByAnInputBreaksTiesById) {
  Workspace workspace;
  const GoalCheck by_key = WithInput(Line(0.5, 0.0), GoalCheck::InputUse::kOrderBy, {3, 3, 1});
  EXPECT_TRUE(MeasurePoses(by_key, Poses({{1.5, 1}, {2, 1}, {1, 1}}), workspace).holds);
  EXPECT_FALSE(MeasurePoses(by_key, Poses({{2, 1}, {1.5, 1}, {1, 1}}), workspace).holds);
}

TEST(GoalsTest, GatheredAtTheRobotWithTheLargestInput) {
  Workspace workspace;
  const GoalCheck at_max = WithInput(Gathered(0.5), GoalCheck::InputUse::kCentreAtMax, {0.2, 0.9, 0.5});
  // Around robot 1 (0.9): robot 2 is 0.6 m away.
  const Measure far = MeasurePoses(at_max, Poses({{1.2, 1}, {1, 1}, {1.6, 1}}), workspace);
  const Measure near = MeasurePoses(at_max, Poses({{1.2, 1}, {1, 1}, {0.7, 1}}), workspace);

  EXPECT_FALSE(far.holds);
  EXPECT_EQ(far.reason, "robot 2 is 0.600 m from robot 1 (the largest key, 0.9); the limit is 0.500 m");
  EXPECT_TRUE(near.holds) << near.reason;
  // Robot 1 crashed: the running robot with the largest value is robot 2.
  const std::vector<RobotPose> without_1 = {{0, 1.2, 1, 0.1}, {2, 1.6, 1, 0.1}};
  const Measure after_crash = MeasurePoses(at_max, without_1, workspace);
  EXPECT_TRUE(after_crash.holds) << after_crash.reason;
  EXPECT_NE(after_crash.reason.find("robot 2 (the largest key, 0.5)"), std::string::npos) << after_crash.reason;
}

TEST(GoalsTest, GatheredByGroupsJudgesEachGroupAndTheirDistance) {
  Workspace workspace;
  GoalCheck teams = WithInput(Gathered(0.3), GoalCheck::InputUse::kGroupBy, {0, 1, 0, 1});
  teams.groups_apart_m = 1.0;
  const Measure apart = MeasurePoses(teams, Poses({{1, 1}, {3, 1}, {1.2, 1}, {3.2, 1}}), workspace);
  const Measure too_close = MeasurePoses(teams, Poses({{1, 1}, {1.8, 1}, {1.2, 1}, {2.0, 1}}), workspace);
  const Measure mixed = MeasurePoses(teams, Poses({{1, 1}, {1.1, 1}, {3, 1}, {3.1, 1}}), workspace);

  EXPECT_TRUE(apart.holds) << apart.reason;
  EXPECT_NEAR(apart.value, 0.1, 2e-3);
  EXPECT_FALSE(too_close.holds);
  EXPECT_NE(too_close.reason.find("groups of key 0 and 1 are only 0.800 m apart"), std::string::npos)
      << too_close.reason;
  EXPECT_FALSE(mixed.holds);
  EXPECT_NE(mixed.reason.find("robots of key 0 fit only in a circle of 1.000 m"), std::string::npos) << mixed.reason;
}

TEST(GoalsTest, NoRunningRobotNeverHolds) {
  Workspace workspace;
  const Measure measure = MeasurePoses(Gathered(1.0), {}, workspace);
  EXPECT_FALSE(measure.holds);
  EXPECT_EQ(measure.reason, "no robot is running");
}

GoalCheck Circle(double min_m, double max_m, double tolerance_rad) {
  GoalCheck check;
  check.kind = CheckKind::kCircle;
  check.radius_min_m = min_m;
  check.radius_max_m = max_m;
  check.angle_tolerance_rad = tolerance_rad;
  return check;
}

std::vector<RobotPose> OnCircle(Point centre, double radius, std::vector<double> degrees) {
  std::vector<RobotPose> robots;
  uint16_t id = 0;
  for (double d : degrees) {
    const double a = d * std::numbers::pi / 180.0;
    robots.push_back({id++, centre.x_m + radius * std::cos(a), centre.y_m + radius * std::sin(a), 0.1});
  }
  return robots;
}

TEST(GoalsTest, CircleEvenlySpacedHolds) {
  Workspace workspace;
  const Measure measure =
      MeasurePoses(Circle(0.9, 1.1, 0.05), OnCircle({2, 2}, 1.0, {10, 100, 190, 280}), workspace);
  EXPECT_TRUE(measure.holds) << measure.reason;
  EXPECT_LT(measure.value, 1e-9);
}

TEST(GoalsTest, CircleUnevenGapFailsNamingTheNeighbours) {
  Workspace workspace;
  GoalCheck check = Circle(0.9, 1.1, 0.05);
  check.centre = Point{2, 2};
  const Measure measure = MeasurePoses(check, OnCircle({2, 2}, 1.0, {0, 45, 170, 270}), workspace);

  EXPECT_FALSE(measure.holds);
  EXPECT_NEAR(measure.value, std::numbers::pi / 4, 1e-9);
  EXPECT_NE(measure.reason.find("the gap from robot 0 to robot 1 is 0.785 rad"), std::string::npos) << measure.reason;
}

TEST(GoalsTest, CircleRadiusOutOfRangeFails) {
  Workspace workspace;
  const Measure measure = MeasurePoses(Circle(1.2, 1.4, 0.05), OnCircle({2, 2}, 1.0, {0, 120, 240}), workspace);
  EXPECT_FALSE(measure.holds);
  EXPECT_NE(measure.reason.find("the radius must be in [1.200, 1.400] m"), std::string::npos) << measure.reason;
}

TEST(GoalMonitorTest, EveryEpochReportsTheFirstEpochThatFailed) {
  GoalCheck check = Gathered(0.5);
  check.name = "together";
  check.when = When::kEveryEpoch;
  check.from_s = 2.0;
  GoalMonitor monitor({check});
  const std::vector<RobotPose> near = Poses({{1, 1}, {1.2, 1}});
  const std::vector<RobotPose> apart = Poses({{1, 1}, {3, 1}});

  monitor.OnEpoch(1, 1.0, apart);  // before from_s: does not count
  monitor.OnEpoch(2, 2.0, near);
  monitor.OnEpoch(3, 3.0, apart);
  monitor.OnEpoch(4, 4.0, near);
  const std::vector<CheckResult> results = monitor.Finish(5.0, near);

  ASSERT_EQ(results.size(), 1u);
  EXPECT_FALSE(results[0].passed);
  EXPECT_EQ(results[0].samples, 3);
  EXPECT_NEAR(results[0].value, 1.0, 2e-3);
  EXPECT_EQ(results[0].reason.rfind("at epoch 3 (3.00 s): ", 0), 0u) << results[0].reason;
}

TEST(GoalMonitorTest, AnUnmeasurableSampleStaysTheWorstValue) {
  GoalCheck check = Gathered(0.5);
  check.when = When::kEveryEpoch;
  GoalMonitor monitor({check});
  const std::vector<RobotPose> near = Poses({{1, 1}, {1.2, 1}});

  monitor.OnEpoch(1, 1.0, {});  // no robot running: not measurable
  monitor.OnEpoch(2, 2.0, Poses({{1, 1}, {3, 1}}));
  const std::vector<CheckResult> results = monitor.Finish(3.0, near);

  EXPECT_FALSE(results[0].passed);
  EXPECT_TRUE(std::isnan(results[0].value));
  EXPECT_EQ(results[0].reason, "at epoch 1 (1.00 s): no robot is running");
}

TEST(GoalMonitorTest, DeadlineReportsTheEpochFromWhichTheGoalHeld) {
  GoalCheck check = Gathered(0.5);
  check.deadline_s = 3.5;
  GoalMonitor monitor({check});
  const std::vector<RobotPose> near = Poses({{1, 1}, {1.2, 1}});
  const std::vector<RobotPose> apart = Poses({{1, 1}, {3, 1}});

  monitor.OnEpoch(1, 1.0, apart);
  monitor.OnEpoch(2, 2.0, near);
  monitor.OnEpoch(3, 3.0, apart);  // broke the first streak
  monitor.OnEpoch(4, 3.2, near);
  monitor.OnEpoch(5, 4.0, near);
  const std::vector<CheckResult> results = monitor.Finish(5.0, near);

  EXPECT_TRUE(results[0].passed) << results[0].reason;
  EXPECT_EQ(results[0].held_from_epoch, 4);
  EXPECT_EQ(results[0].held_from_s, 3.2);
}

TEST(GoalMonitorTest, DeadlineMissedWhenTheGoalHeldTooLate) {
  GoalCheck check = Gathered(0.5);
  check.deadline_s = 2.5;
  GoalMonitor monitor({check});
  const std::vector<RobotPose> near = Poses({{1, 1}, {1.2, 1}});
  const std::vector<RobotPose> apart = Poses({{1, 1}, {3, 1}});

  monitor.OnEpoch(1, 1.0, apart);
  monitor.OnEpoch(2, 2.0, apart);
  monitor.OnEpoch(3, 3.0, near);
  const std::vector<CheckResult> results = monitor.Finish(5.0, near);

  EXPECT_FALSE(results[0].passed);
  EXPECT_EQ(results[0].held_from_epoch, 3);
  EXPECT_EQ(results[0].reason, "held only from epoch 3 (3.00 s) on; the deadline is 2.50 s");
}

TEST(GoalMonitorTest, CoverageCountsCellsUnderABody) {
  GoalCheck check;
  check.kind = CheckKind::kCoverage;
  check.area_min = {0, 0};
  check.area_max = {1, 1};
  check.cell_m = 0.5;  // four cells, centres at 0.25 and 0.75
  check.min_fraction = 0.75;
  check.deadline_s = 10;
  GoalMonitor monitor({check});

  monitor.OnRound(1.0, std::vector<RobotPose>{{0, 0.25, 0.25, 0.1}});
  monitor.OnRound(2.0, std::vector<RobotPose>{{0, 0.75, 0.25, 0.1}, {1, 0.5, 0.5, 0.1}});  // the second covers none
  monitor.OnRound(3.0, std::vector<RobotPose>{{0, 0.75, 0.75, 0.1}});
  const std::vector<CheckResult> results = monitor.Finish(4.0, {});

  EXPECT_TRUE(results[0].passed) << results[0].reason;
  EXPECT_EQ(results[0].value, 0.75);
  EXPECT_EQ(results[0].held_from_s, 3.0);
}

}  // namespace
}  // namespace syrof::lab::goals
