// The activation schedule (core/sync/activation.h): FSYNC, and SSYNC's
// random, round-robin and scripted schedules; fairness, determinism and the
// never-empty rule.
#include "syrof/sync/activation.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace syrof::sync {
namespace {

wire::MemberSet Members(std::initializer_list<uint16_t> ids) {
  wire::MemberSet members;
  for (const uint16_t id : ids) members.set(id);
  return members;
}

ActivationConfig Ssync(ActivationSchedule schedule, uint64_t seed = 7, uint16_t fair_within = 3) {
  ActivationConfig config;
  config.model = ActivationModel::kSsync;
  config.schedule = schedule;
  config.seed = seed;
  config.fair_within = fair_within;
  return config;
}

TEST(ActivationTest, FsyncActivatesEveryMemberAndNobodyElse) {
  const ActivationConfig config;  // the default
  const wire::MemberSet members = Members({0, 2, 5});
  for (uint16_t epoch = 0; epoch < 50; ++epoch) {
    EXPECT_TRUE(IsActive(config, epoch, members, 0));
    EXPECT_TRUE(IsActive(config, epoch, members, 2));
    EXPECT_TRUE(IsActive(config, epoch, members, 5));
    EXPECT_FALSE(IsActive(config, epoch, members, 1));
    EXPECT_EQ(ActiveCount(config, epoch, members), 3);
  }
}

TEST(ActivationTest, RandomScheduleIsFairWithinItsBound) {
  const wire::MemberSet members = Members({0, 1, 2, 3, 4, 5, 6});
  for (const uint16_t bound : {1, 2, 3, 5, 8}) {
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      const ActivationConfig config = Ssync(ActivationSchedule::kRandom, seed, bound);
      std::vector<int> since_active(7, 0);
      for (uint32_t epoch = 0; epoch < 600; ++epoch) {
        for (const uint16_t robot : members) {
          since_active[robot] = IsActive(config, static_cast<uint16_t>(epoch), members, robot) ? 0 : since_active[robot] + 1;
          ASSERT_LT(since_active[robot], bound) << "robot " << robot << " epoch " << epoch << " seed " << seed;
        }
      }
    }
  }
}

TEST(ActivationTest, RandomScheduleLeavesSomeRobotsOutAndIsNeverEmpty) {
  const wire::MemberSet members = Members({0, 1, 2, 3});
  const ActivationConfig config = Ssync(ActivationSchedule::kRandom, 3, 6);
  int partial_epochs = 0;
  for (uint16_t epoch = 0; epoch < 200; ++epoch) {
    const uint16_t active = ActiveCount(config, epoch, members);
    EXPECT_GE(active, 1);
    partial_epochs += active < 4 ? 1 : 0;
  }
  // With a draw of 1/2 per robot, most epochs leave someone out.
  EXPECT_GT(partial_epochs, 100);
}

TEST(ActivationTest, RandomScheduleIsAFunctionOfSeedEpochAndMembers) {
  const wire::MemberSet members = Members({1, 3, 4, 9});
  const ActivationConfig a = Ssync(ActivationSchedule::kRandom, 42, 4);
  const ActivationConfig b = Ssync(ActivationSchedule::kRandom, 42, 4);
  const ActivationConfig other_seed = Ssync(ActivationSchedule::kRandom, 43, 4);
  int differing = 0;
  for (uint16_t epoch = 0; epoch < 100; ++epoch) {
    for (const uint16_t robot : members) {
      EXPECT_EQ(IsActive(a, epoch, members, robot), IsActive(b, epoch, members, robot));
      differing += IsActive(a, epoch, members, robot) != IsActive(other_seed, epoch, members, robot) ? 1 : 0;
    }
  }
  EXPECT_GT(differing, 0);
}

TEST(ActivationTest, RandomScheduleWithBoundOneIsEveryMember) {
  const wire::MemberSet members = Members({0, 1, 2});
  const ActivationConfig config = Ssync(ActivationSchedule::kRandom, 9, 1);
  for (uint16_t epoch = 0; epoch < 30; ++epoch) EXPECT_EQ(ActiveCount(config, epoch, members), 3);
}

TEST(ActivationTest, RoundRobinActivatesOneMemberAtATimeInIdOrder) {
  const wire::MemberSet members = Members({2, 4, 7});
  const ActivationConfig config = Ssync(ActivationSchedule::kRoundRobin);
  const uint16_t expected[] = {2, 4, 7, 2, 4, 7};
  for (uint16_t epoch = 0; epoch < 6; ++epoch) {
    EXPECT_EQ(ActiveCount(config, epoch, members), 1);
    EXPECT_TRUE(IsActive(config, epoch, members, expected[epoch])) << "epoch " << epoch;
  }
}

TEST(ActivationTest, ScriptedScheduleActivatesTheListedMembersOnly) {
  const std::vector<ScriptedActivation> script = {{3, 0}, {3, 2}, {4, 1}};
  ActivationConfig config = Ssync(ActivationSchedule::kScripted);
  config.script = script;
  ASSERT_TRUE(IsValid(config));
  const wire::MemberSet members = Members({0, 1, 2});
  EXPECT_TRUE(IsActive(config, 3, members, 0));
  EXPECT_FALSE(IsActive(config, 3, members, 1));
  EXPECT_TRUE(IsActive(config, 3, members, 2));
  EXPECT_FALSE(IsActive(config, 4, members, 0));
  EXPECT_TRUE(IsActive(config, 4, members, 1));
  EXPECT_FALSE(IsActive(config, 4, members, 2));
  // An epoch the script does not list: every member.
  EXPECT_EQ(ActiveCount(config, 5, members), 3);
  EXPECT_EQ(ActiveCount(config, 2, members), 3);
}

TEST(ActivationTest, ScriptNamingOnlyAbsentRobotsFallsBackToOneSeededMember) {
  const std::vector<ScriptedActivation> script = {{6, 3}};
  ActivationConfig config = Ssync(ActivationSchedule::kScripted, 5);
  config.script = script;
  const wire::MemberSet members = Members({0, 1, 2});  // robot 3 is not a member in epoch 6
  EXPECT_EQ(ActiveCount(config, 6, members), 1);
  EXPECT_FALSE(IsActive(config, 6, members, 3));
  // The same members and seed give the same one, every time.
  uint16_t chosen = wire::MemberSet::kCapacity;
  for (const uint16_t robot : members) {
    if (IsActive(config, 6, members, robot)) chosen = robot;
  }
  for (int repeat = 0; repeat < 3; ++repeat) EXPECT_TRUE(IsActive(config, 6, members, chosen));
}

TEST(ActivationTest, NobodyIsActiveWithoutMembers) {
  const ActivationConfig config = Ssync(ActivationSchedule::kRoundRobin);
  EXPECT_EQ(ActiveCount(config, 1, wire::MemberSet{}), 0);
  EXPECT_FALSE(IsActive(config, 1, wire::MemberSet{}, 0));
}

TEST(ActivationTest, ValidityRefusesZeroBoundAndUnsortedScripts) {
  ActivationConfig config = Ssync(ActivationSchedule::kRandom, 1, 0);
  EXPECT_FALSE(IsValid(config));
  config.fair_within = 1;
  EXPECT_TRUE(IsValid(config));
  const std::vector<ScriptedActivation> unsorted = {{4, 1}, {3, 0}};
  config.script = unsorted;
  EXPECT_FALSE(IsValid(config));
  const std::vector<ScriptedActivation> duplicate = {{3, 1}, {3, 1}};
  config.script = duplicate;
  EXPECT_FALSE(IsValid(config));
}

ActivationConfig Async(uint8_t max_delay, uint64_t seed = 7, uint32_t min_move_mm = 0) {
  ActivationConfig config;
  config.model = ActivationModel::kAsync;
  config.schedule = ActivationSchedule::kRandom;
  config.seed = seed;
  config.max_delay_epochs = max_delay;
  config.min_move_mm = min_move_mm;
  return config;
}

TEST(AsyncActivationTest, RandomCyclesStayWithinTheBoundAndTakeEveryValue) {
  const ActivationConfig config = Async(2);
  std::vector<int> starts(3, 0);
  std::vector<int> lengths(4, 0);
  for (uint16_t epoch = 1; epoch < 400; ++epoch) {
    for (uint16_t robot = 0; robot < 4; ++robot) {
      const AsyncCycle cycle = CycleFor(config, epoch, robot);
      ASSERT_LE(cycle.start_delay, 2);
      ASSERT_GE(cycle.move_epochs, 1);
      ASSERT_LE(cycle.move_epochs, 3);
      EXPECT_FALSE(cycle.cut);  // rigid: min_move_mm 0
      ++starts[cycle.start_delay];
      ++lengths[cycle.move_epochs];
      // A pure function of the seed, the epoch and the robot.
      const AsyncCycle again = CycleFor(config, epoch, robot);
      EXPECT_EQ(again.start_delay, cycle.start_delay);
      EXPECT_EQ(again.move_epochs, cycle.move_epochs);
    }
  }
  for (int value : starts) EXPECT_GT(value, 300);  // about 532 of 1,596 each
  EXPECT_EQ(lengths[0], 0);
  for (int i = 1; i <= 3; ++i) EXPECT_GT(lengths[i], 300);
}

TEST(AsyncActivationTest, NonRigidCutsAboutHalfTheMoves) {
  const ActivationConfig config = Async(1, 7, 50);
  int cut = 0;
  for (uint16_t epoch = 1; epoch <= 200; ++epoch) cut += CycleFor(config, epoch, 3).cut ? 1 : 0;
  EXPECT_GT(cut, 70);
  EXPECT_LT(cut, 130);
}

TEST(AsyncActivationTest, ScriptedCyclesAreLookedUpAndTheRestTakeOneEpoch) {
  ActivationConfig config = Async(3);
  config.schedule = ActivationSchedule::kScripted;
  config.min_move_mm = 20;
  const std::vector<ScriptedCycle> cycles = {{2, 0, 1, 2, false}, {2, 1, 0, 4, true}, {5, 0, 3, 1, false}};
  config.cycles = cycles;
  ASSERT_TRUE(IsValid(config));
  const AsyncCycle a = CycleFor(config, 2, 0);
  EXPECT_EQ(a.start_delay, 1);
  EXPECT_EQ(a.move_epochs, 2);
  const AsyncCycle b = CycleFor(config, 2, 1);
  EXPECT_EQ(b.move_epochs, 4);
  EXPECT_TRUE(b.cut);
  EXPECT_EQ(CycleFor(config, 5, 0).start_delay, 3);
  const AsyncCycle unlisted = CycleFor(config, 3, 0);
  EXPECT_EQ(unlisted.start_delay, 0);
  EXPECT_EQ(unlisted.move_epochs, 1);
  EXPECT_FALSE(unlisted.cut);
}

TEST(AsyncActivationTest, ValidityRefusesCyclesBeyondTheBoundOrUnsorted) {
  ActivationConfig config = Async(2);
  config.schedule = ActivationSchedule::kScripted;
  const std::vector<ScriptedCycle> late = {{2, 0, 3, 1, false}};
  config.cycles = late;
  EXPECT_FALSE(IsValid(config));
  const std::vector<ScriptedCycle> long_move = {{2, 0, 0, 4, false}};
  config.cycles = long_move;
  EXPECT_FALSE(IsValid(config));
  const std::vector<ScriptedCycle> no_move = {{2, 0, 0, 0, false}};
  config.cycles = no_move;
  EXPECT_FALSE(IsValid(config));
  const std::vector<ScriptedCycle> unsorted = {{3, 0, 0, 1, false}, {2, 0, 0, 1, false}};
  config.cycles = unsorted;
  EXPECT_FALSE(IsValid(config));
  config.cycles = {};
  config.max_delay_epochs = kMaxAsyncDelayEpochs + 1;
  EXPECT_FALSE(IsValid(config));
}

// A cycle looked in epoch 2 that starts its move one epoch later and lasts
// two: look (wait), move, move (last); the next start looks again.
TEST(AsyncActivationTest, TheTrackerFollowsACycleFromLookToTheMovesLastEpoch) {
  ActivationConfig config = Async(2);
  config.schedule = ActivationSchedule::kScripted;
  const std::vector<ScriptedCycle> cycles = {{2, 0, 1, 2, false}};
  config.cycles = cycles;
  AsyncTracker tracker;
  AsyncTracker::Step step = tracker.OnEpochStart(config, 1, 0);  // unlisted: one epoch
  EXPECT_TRUE(step.looks && step.moves && step.first_move_epoch && step.last_move_epoch);
  step = tracker.OnEpochStart(config, 2, 0);
  EXPECT_TRUE(step.looks);
  EXPECT_FALSE(step.moves);
  EXPECT_EQ(step.look_epoch, 2);
  step = tracker.OnEpochStart(config, 3, 0);
  EXPECT_FALSE(step.looks);
  EXPECT_TRUE(step.moves && step.first_move_epoch);
  EXPECT_FALSE(step.last_move_epoch);
  EXPECT_EQ(step.look_epoch, 2);
  const uint64_t mid_move = tracker.Packed();
  step = tracker.OnEpochStart(config, 4, 0);
  EXPECT_FALSE(step.looks);
  EXPECT_TRUE(step.moves && step.last_move_epoch);
  EXPECT_NE(tracker.Packed(), mid_move);
  step = tracker.OnEpochStart(config, 5, 0);
  EXPECT_TRUE(step.looks && step.moves && step.last_move_epoch);
  EXPECT_EQ(step.look_epoch, 5);
}

TEST(AsyncActivationTest, EveryMemberIsActiveForIsActive) {
  const ActivationConfig config = Async(2);
  const wire::MemberSet members = Members({0, 2});
  EXPECT_TRUE(IsActive(config, 4, members, 0));
  EXPECT_TRUE(IsActive(config, 4, members, 2));
  EXPECT_FALSE(IsActive(config, 4, members, 1));
}

TEST(ActivationTest, NamesMatchTheScenarioWords) {
  EXPECT_STREQ(ToString(ActivationModel::kFsync), "fsync");
  EXPECT_STREQ(ToString(ActivationModel::kSsync), "ssync");
  EXPECT_STREQ(ToString(ActivationModel::kAsync), "async");
  EXPECT_STREQ(ToString(ActivationSchedule::kRandom), "random");
  EXPECT_STREQ(ToString(ActivationSchedule::kRoundRobin), "round_robin");
  EXPECT_STREQ(ToString(ActivationSchedule::kScripted), "scripted");
}

}  // namespace
}  // namespace syrof::sync
