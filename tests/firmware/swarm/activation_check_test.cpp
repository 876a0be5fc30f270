// ActivationCheck: each robot's own word on whether it looked at an epoch
// start, held against what its activation schedule says.
#include "syrof/firmware/swarm/activation_check.h"

#include <gtest/gtest.h>

namespace syrof::firmware::swarm {
namespace {

EpochLine Start(uint16_t robot, uint16_t epoch, bool active, uint16_t members = 4) {
  EpochLine line;
  line.robot = robot;
  line.active = active;
  line.map.epoch = epoch;
  for (uint16_t id = 0; id < members; ++id) line.map.members.set(id);
  return line;
}

sync::ActivationConfig RoundRobin() {
  sync::ActivationConfig config;
  config.model = sync::ActivationModel::kSsync;
  config.schedule = sync::ActivationSchedule::kRoundRobin;
  return config;
}

TEST(ActivationCheckTest, SsyncStartsAsTheScheduleSaysPass) {
  ActivationCheck check(RoundRobin(), 4);
  // Round robin over members 0-3: epoch e activates robot e mod 4.
  for (uint16_t epoch = 1; epoch <= 8; ++epoch) {
    for (uint16_t robot = 0; robot < 4; ++robot) check.OnEpochLine(Start(robot, epoch, robot == epoch % 4));
  }
  EXPECT_EQ(check.figures().model, "ssync");
  EXPECT_EQ(check.figures().starts, 32);
  EXPECT_EQ(check.figures().looked, 8);
  EXPECT_EQ(check.figures().against_schedule, 0);
  EXPECT_TRUE(check.figures().first_difference.empty());
}

// An image that ignored its schedule and ran every robot every epoch.
TEST(ActivationCheckTest, ARobotLookingInEveryEpochIsAgainstAnSsyncSchedule) {
  ActivationCheck check(RoundRobin(), 4);
  for (uint16_t robot = 0; robot < 4; ++robot) check.OnEpochLine(Start(robot, 5, true));
  EXPECT_EQ(check.figures().against_schedule, 3);
  EXPECT_EQ(check.figures().first_difference,
            "robot 0 at its start of epoch 5 looked; its ssync schedule says it does not");
}

TEST(ActivationCheckTest, FsyncExpectsEveryStartToLook) {
  ActivationCheck check(sync::ActivationConfig{}, 2);
  check.OnEpochLine(Start(0, 1, true, 2));
  check.OnEpochLine(Start(1, 1, false, 2));
  EXPECT_EQ(check.figures().model, "fsync");
  EXPECT_EQ(check.figures().against_schedule, 1);
}

// ASYNC: the check follows each robot's cycles with the robot's own tracker.
TEST(ActivationCheckTest, AsyncFollowsEachRobotsCycles) {
  sync::ActivationConfig config;
  config.model = sync::ActivationModel::kAsync;
  config.schedule = sync::ActivationSchedule::kRandom;
  config.seed = 3;
  config.max_delay_epochs = 2;
  sync::AsyncTracker robot_tracker;  // what robot 1 itself decides
  ActivationCheck check(config, 4);
  int64_t looked = 0;
  for (uint16_t epoch = 1; epoch <= 30; ++epoch) {
    const bool looks = robot_tracker.OnEpochStart(config, epoch, 1).looks;
    looked += looks ? 1 : 0;
    check.OnEpochLine(Start(1, epoch, looks));
  }
  EXPECT_EQ(check.figures().against_schedule, 0);
  EXPECT_EQ(check.figures().looked, looked);
  EXPECT_LT(looked, 30) << "with delays up to 2 epochs some starts fall inside a cycle";
  check.OnEpochLine(Start(1, 31, true));
  check.OnEpochLine(Start(1, 32, true));
  check.OnEpochLine(Start(1, 33, true));
  EXPECT_GT(check.figures().against_schedule, 0);
}

}  // namespace
}  // namespace syrof::firmware::swarm
