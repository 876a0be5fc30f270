// `goal:`: every check kind read into lab/goals' GoalCheck, and the errors a
// student reads for a wrong one (place, key path, nearest key).
#include <gtest/gtest.h>

#include "scenario_test_util.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::Load;

const char* const kBase = "robots: { count: 3 }\napp: builtin:idle\n";

TEST(SchemaGoalTest, EveryKindLoads) {
  const LoadResult result = Load(std::string(kBase) +
                                 "goal:\n"
                                 "  - check: gathered\n"
                                 "    radius_m: 0.6\n"
                                 "    deadline_s: 40\n"
                                 "  - check: circle\n"
                                 "    radius_min_m: 1\n"
                                 "    radius_max_m: 1.4\n"
                                 "    centre: { x_m: 2, y_m: 2 }\n"
                                 "  - { check: line, spacing_m: 0.4, direction_rad: 0, when: every_epoch, from_s: 30 }\n"
                                 "  - check: slots\n"
                                 "    assign: by_id\n"
                                 "    points: [{x_m: 1, y_m: 1}, {x_m: 2, y_m: 1}, {x_m: 3, y_m: 1}]\n"
                                 "  - { check: shape, name: vee, points: [{x_m: 0, y_m: 0}, {x_m: 1, y_m: 1}, {x_m: 2, y_m: 0}] }\n"
                                 "  - { check: coverage, min_fraction: 0.5, cell_m: 0.5 }\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<goals::GoalCheck>& goal = result.scenario->goal;
  ASSERT_EQ(goal.size(), 6u);
  EXPECT_EQ(goal[0].kind, goals::CheckKind::kGathered);
  EXPECT_EQ(goal[0].name, "gathered");
  EXPECT_EQ(goal[0].deadline_s, 40.0);
  EXPECT_EQ(goal[1].centre, (goals::Point{2, 2}));
  EXPECT_EQ(goal[2].when, goals::When::kEveryEpoch);
  EXPECT_EQ(goal[2].from_s, 30.0);
  EXPECT_EQ(goal[2].direction_rad, 0.0);
  EXPECT_TRUE(goal[3].by_id);
  EXPECT_EQ(goal[4].name, "vee");
  EXPECT_EQ(goal[5].area_max, (goals::Point{4, 4}));
}

TEST(SchemaGoalTest, ChecksReadTheScenariosInputs) {
  const LoadResult result = Load(std::string(kBase) +
                                 "inputs: { charge: [0.2, 0.9, 0.5], colour: [0, 1, 0] }\n"
                                 "goal:\n"
                                 "  - { check: gathered, name: strongest, radius_m: 0.6, centre_at_max: charge }\n"
                                 "  - { check: gathered, name: teams, radius_m: 0.4, group_by: colour, groups_apart_m: 1 }\n"
                                 "  - { check: line, spacing_m: 0.4, order_by: charge }\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<goals::GoalCheck>& goal = result.scenario->goal;
  EXPECT_EQ(goal[0].input_use, goals::GoalCheck::InputUse::kCentreAtMax);
  EXPECT_EQ(goal[0].input, "charge");
  EXPECT_EQ(goal[0].input_values, (std::vector<double>{0.2, 0.9, 0.5}));
  EXPECT_EQ(goal[1].input_use, goals::GoalCheck::InputUse::kGroupBy);
  EXPECT_EQ(goal[1].groups_apart_m, 1.0);
  EXPECT_EQ(goal[2].input_use, goals::GoalCheck::InputUse::kOrderBy);
}

TEST(SchemaGoalTest, AnInputTheScenarioLacksIsNamed) {
  const std::string inputs = "inputs: { charge: [0.2, 0.9, 0.5] }\n";
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + inputs + "goal:\n  - { check: line, spacing_m: 0.4, order_by: charj }\n"),
                      5, 46, {"goal[0].order_by", "no input 'charj'", "did you mean 'charge'"}));
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - { check: gathered, radius_m: 1, group_by: colour }\n"), 4,
                      47, {"no input 'colour'", "gives none"}));
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + inputs +
                           "goal:\n  - { check: gathered, radius_m: 1, groups_apart_m: 1 }\n"),
                      5, 53, {"needs group_by"}));
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + inputs +
                           "goal:\n  - { check: gathered, radius_m: 1, centre_at_max: charge, group_by: charge }\n"),
                      5, 70, {"not both"}));
}

TEST(SchemaGoalTest, TwoChecksOfOneKindAreNumbered) {
  const LoadResult result = Load(std::string(kBase) +
                                 "goal: [{check: gathered, radius_m: 1}, {check: gathered, radius_m: 2}]\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->goal[0].name, "gathered#0");
  EXPECT_EQ(result.scenario->goal[1].name, "gathered#1");
}

TEST(SchemaGoalTest, AnUnknownKindSuggestsTheNearest) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - check: gatherd\n"), 4, 12,
                      {"goal[0].check", "unknown value 'gatherd'", "did you mean 'gathered'?"}));
}

TEST(SchemaGoalTest, AKeyOfAnotherKindIsUnknown) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - check: gathered\n    radius_m: 1\n    spacing_m: 2\n"),
                      6, 5, {"goal[0]", "unknown key 'spacing_m'"}));
}

TEST(SchemaGoalTest, AMisspeltKeySuggestsTheNearest) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - check: gathered\n    radius: 1\n"), 5, 5,
                      {"unknown key 'radius'", "did you mean 'radius_m'?"}));
}

TEST(SchemaGoalTest, ARequiredKeyIsNamed) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - check: line\n"), 4, 5,
                      {"missing required key 'goal[0].spacing_m'"}));
}

TEST(SchemaGoalTest, SlotsByIdNeedOnePerRobot) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) +
                           "goal:\n  - check: slots\n    assign: by_id\n    points: [{x_m: 1, y_m: 1}]\n"),
                      6, 13, {"goal[0].points", "one slot per robot: 1 given, the scenario has 3 robots"}));
}

TEST(SchemaGoalTest, ASlotOutsideTheArenaIsRefused) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) +
                           "goal:\n  - check: slots\n    points: [{x_m: 1, y_m: 1}, {x_m: 9, y_m: 1}, {x_m: 2, y_m: 2}]\n"),
                      5, 38, {"goal[0].points[1].x_m", "must be in [0, 4]"}));
}

TEST(SchemaGoalTest, FromNeedsEveryEpoch) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - {check: gathered, radius_m: 1, from_s: 3}\n"), 4, 36,
                      {"'from_s' needs 'when: every_epoch'"}));
}

TEST(SchemaGoalTest, ADeadlineAfterTheRunIsRefused) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "timing: {duration_s: 20}\ngoal:\n  - {check: gathered, radius_m: 1, deadline_s: 30}\n"),
                      5, 48, {"goal[0].deadline_s", "must be in (0, 20]"}));
}

TEST(SchemaGoalTest, CoverageTakesNoWhen) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - {check: coverage, min_fraction: 0.5, when: every_epoch}\n"),
                      4, 48, {"coverage is measured over the whole run"}));
}

TEST(SchemaGoalTest, TooManyCoverageCellsAreRefused) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - {check: coverage, min_fraction: 0.5, cell_m: 0.001}\n"),
                      4, 50, {"goal[0].cell_m", "16000000 cells"}));
}

TEST(SchemaGoalTest, DuplicateNamesAreRefused) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) +
                           "goal:\n  - {check: gathered, radius_m: 1, name: a}\n  - {check: gathered, radius_m: 2, name: a}\n"),
                      5, 42, {"another check is already named 'a'"}));
}

TEST(SchemaGoalTest, ARadiusRangeMustNotBeEmpty) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal:\n  - {check: circle, radius_min_m: 2, radius_max_m: 1}\n"), 4,
                      52, {"goal[0].radius_max_m", "must be at least radius_min_m (2)"}));
}

TEST(SchemaGoalTest, GoalMustBeAList) {
  EXPECT_TRUE(FailsAt(Load(std::string(kBase) + "goal: {check: gathered}\n"), 3, 7, {"goal: expected a list"}));
}

}  // namespace
}  // namespace syrof::lab::scenario
