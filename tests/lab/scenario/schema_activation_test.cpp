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

TEST(ReadActivation, AsyncIsRefusedByName) {
  EXPECT_TRUE(FailsAt(LoadActivation("  model: async\n"), 4, 10,
                      {"activation.model", "activation model async is not built yet"}));
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
                      {"'schedule' applies to model ssync only"}));
}

TEST(ReadActivation, SsyncNeedsASchedule) {
  const LoadResult result = LoadActivation("  model: ssync\n");
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error->message.find("schedule"), std::string::npos) << result.error->ToString();
}

}  // namespace
}  // namespace syrof::lab::scenario
