// `activation:`: the model, the schedule and its settings, and each bad
// input named at its place.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenario_test_util.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::kMinimal;
using testing::Load;

// kMinimal (4 robots, 60 s of 1 s maneuvers: at most 60 epochs) and an
// `activation:` section starting on line 3.
LoadResult LoadActivation(const std::string& body) { return Load(std::string(kMinimal) + "activation:\n" + body); }

TEST(ReadActivation, FsyncByDefault) {
  const LoadResult result = Load(kMinimal);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.scenario->activation.model, sync::ActivationModel::kFsync);
  EXPECT_TRUE(result.scenario->activation.script.empty());
}

TEST(ReadActivation, RandomScheduleWithItsBound) {
  const LoadResult result = LoadActivation("  model: ssync\n  schedule: random\n  fair_within: 5\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->activation.model, sync::ActivationModel::kSsync);
  EXPECT_EQ(result.scenario->activation.schedule, sync::ActivationSchedule::kRandom);
  EXPECT_EQ(result.scenario->activation.fair_within, 5);
}

TEST(ReadActivation, ScriptedScheduleIsSortedByEpochThenRobot) {
  const LoadResult result = LoadActivation("  model: ssync\n  schedule: scripted\n  active: [[4, [3, 1]], [2, [0]]]\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<sync::ScriptedActivation>& script = result.scenario->activation.script;
  ASSERT_EQ(script.size(), 3u);
  EXPECT_EQ(script[0].epoch, 2);
  EXPECT_EQ(script[0].robot, 0);
  EXPECT_EQ(script[1].epoch, 4);
  EXPECT_EQ(script[1].robot, 1);
  EXPECT_EQ(script[2].robot, 3);
}

TEST(ReadActivation, AsyncRandomWithItsBoundAndNonRigidMoves) {
  const LoadResult result =
      LoadActivation("  model: async\n  schedule: random\n  max_delay_epochs: 3\n  min_move_m: 0.05\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->activation.model, sync::ActivationModel::kAsync);
  EXPECT_EQ(result.scenario->activation.max_delay_epochs, 3);
  EXPECT_DOUBLE_EQ(result.scenario->activation.min_move_m, 0.05);
}

TEST(ReadActivation, AsyncScriptedCyclesAreSortedAndChecked) {
  const LoadResult result = LoadActivation(
      "  model: async\n  schedule: scripted\n  max_delay_epochs: 2\n  min_move_m: 0.1\n"
      "  cycles: [[4, 1, 0, 3, 1], [2, 3, 2, 1]]\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<sync::ScriptedCycle>& cycles = result.scenario->activation.cycles;
  ASSERT_EQ(cycles.size(), 2u);
  EXPECT_EQ(cycles[0].epoch, 2);
  EXPECT_EQ(cycles[0].robot, 3);
  EXPECT_EQ(cycles[0].start_delay, 2);
  EXPECT_FALSE(cycles[0].cut);
  EXPECT_EQ(cycles[1].move_epochs, 3);
  EXPECT_TRUE(cycles[1].cut);
}

TEST(ReadActivation, AsyncBadInputIsNamed) {
  EXPECT_TRUE(FailsAt(LoadActivation("  model: async\n  schedule: random\n"), 4, 3,
                      {"activation", "max_delay_epochs"}));
  EXPECT_TRUE(FailsAt(LoadActivation("  model: async\n  schedule: random\n  max_delay_epochs: 9\n"), 6, 21,
                      {"activation.max_delay_epochs", "[1, 8]"}));
  EXPECT_TRUE(FailsAt(LoadActivation("  model: async\n  schedule: round_robin\n  max_delay_epochs: 1\n"), 5, 13,
                      {"activation.schedule", "round_robin applies to model ssync only"}));
  EXPECT_TRUE(FailsAt(LoadActivation("  model: async\n  schedule: random\n  max_delay_epochs: 1\n  fair_within: 2\n"),
                      7, 3, {"'fair_within' applies to model ssync only"}));
  EXPECT_TRUE(FailsAt(LoadActivation("  model: ssync\n  schedule: random\n  max_delay_epochs: 1\n"), 6, 3,
                      {"'max_delay_epochs' applies to model async only"}));
  const std::string scripted = "  model: async\n  schedule: scripted\n  max_delay_epochs: 2\n";
  EXPECT_TRUE(FailsAt(LoadActivation(scripted + "  cycles: [[2, 9, 0, 1]]\n"), 7, 16, {"activation.cycles[0][1]"}));
  EXPECT_TRUE(FailsAt(LoadActivation(scripted + "  cycles: [[61, 0, 0, 1]]\n"), 7, 13,
                      {"activation.cycles[0][0]", "[1, 60]"}));
  EXPECT_TRUE(FailsAt(LoadActivation(scripted + "  cycles: [[2, 0, 3, 1]]\n"), 7, 19,
                      {"activation.cycles[0][2]", "[0, 2]"}));
  EXPECT_TRUE(FailsAt(LoadActivation(scripted + "  cycles: [[2, 0, 0, 0]]\n"), 7, 22,
                      {"activation.cycles[0][3]", "[1, 3]"}));
  EXPECT_TRUE(FailsAt(LoadActivation(scripted + "  cycles: [[2, 0, 0, 1, 1]]\n"), 7, 25,
                      {"activation.cycles[0][4]", "a cut needs min_move_m"}));
  EXPECT_TRUE(FailsAt(LoadActivation(scripted + "  cycles: [[2, 0, 0, 1], [2, 0, 1, 1]]\n"), 7, 26,
                      {"activation.cycles[1]", "listed twice"}));
  EXPECT_TRUE(FailsAt(LoadActivation(scripted + "  cycles: [[2, 0, 1]]\n"), 7, 12,
                      {"activation.cycles[0]", "got 3 values"}));
  EXPECT_TRUE(FailsAt(LoadActivation(scripted), 4, 3, {"activation", "cycles"}));
}

TEST(ReadActivation, UnknownModelNamesTheField) {
  EXPECT_TRUE(FailsAt(LoadActivation("  model: sync\n"), 4, 10, {"activation.model", "ssync"}));
}

TEST(ReadActivation, FairWithinBelowOneIsRefused) {
  EXPECT_TRUE(FailsAt(LoadActivation("  model: ssync\n  schedule: random\n  fair_within: 0\n"), 6, 16,
                      {"activation.fair_within", "[1, 60]"}));
}

TEST(ReadActivation, FairWithinAboveTheRunsEpochsIsRefused) {
  EXPECT_TRUE(FailsAt(LoadActivation("  model: ssync\n  schedule: random\n  fair_within: 61\n"), 6, 16,
                      {"activation.fair_within", "[1, 60]"}));
}

TEST(ReadActivation, ScriptNamingAnAbsentRobotIsRefused) {
  // Column 17: the 9 in "  active: [[3, [9]]]".
  EXPECT_TRUE(FailsAt(LoadActivation("  model: ssync\n  schedule: scripted\n  active: [[3, [9]]]\n"), 6, 17,
                      {"activation.active[0][1][0]", "robot id 9 is out of range"}));
}

TEST(ReadActivation, ScriptEpochOutOfRangeIsRefused) {
  EXPECT_TRUE(FailsAt(LoadActivation("  model: ssync\n  schedule: scripted\n  active: [[61, [0]]]\n"), 6, 13,
                      {"activation.active[0][0]", "[1, 60]"}));
  EXPECT_TRUE(FailsAt(LoadActivation("  model: ssync\n  schedule: scripted\n  active: [[0, [0]]]\n"), 6, 13,
                      {"activation.active[0][0]", "[1, 60]"}));
}

TEST(ReadActivation, ScriptEpochWithNoRobotIsRefused) {
  EXPECT_FALSE(LoadActivation("  model: ssync\n  schedule: scripted\n  active: [[3, []]]\n").ok());
}

TEST(ReadActivation, KeysOfAnotherScheduleAreRefused) {
  EXPECT_TRUE(FailsAt(LoadActivation("  model: ssync\n  schedule: round_robin\n  fair_within: 3\n"), 6, 3,
                      {"'fair_within' applies to schedule random only"}));
  EXPECT_TRUE(FailsAt(LoadActivation("  model: fsync\n  schedule: random\n"), 5, 3,
                      {"'schedule' applies to models ssync and async only"}));
}

TEST(ReadActivation, SsyncNeedsASchedule) {
  const LoadResult result = LoadActivation("  model: ssync\n");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error->message.find("schedule"), std::string::npos) << result.error->ToString();
}

}  // namespace
}  // namespace syrof::lab::scenario
