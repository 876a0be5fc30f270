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

TEST(ActivationTest, NamesMatchTheScenarioWords) {
  EXPECT_STREQ(ToString(ActivationModel::kFsync), "fsync");
  EXPECT_STREQ(ToString(ActivationModel::kSsync), "ssync");
  EXPECT_STREQ(ToString(ActivationSchedule::kRandom), "random");
  EXPECT_STREQ(ToString(ActivationSchedule::kRoundRobin), "round_robin");
  EXPECT_STREQ(ToString(ActivationSchedule::kScripted), "scripted");
}

}  // namespace
}  // namespace syrof::sync
