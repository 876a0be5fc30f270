// The robot kinds as the motion layer knows them (motion/robot_kind.h) and
// their place in a robot's start-up config (runtime/robot_kinds.h is tested
// through the lab's RobotConfigFor and the image's ConfigureImageKinds).
#include "syrof/motion/robot_kind.h"

#include <gtest/gtest.h>

#include <array>

namespace syrof::motion {
namespace {

TEST(RobotKindTest, NamesReadBackAndNothingElseIsAKind) {
  for (size_t i = 0; i < kRobotKindCount; ++i) {
    const auto kind = static_cast<RobotKind>(i);
    RobotKind read = kind == RobotKind::kOmni ? RobotKind::kDrone : RobotKind::kOmni;
    ASSERT_TRUE(ParseRobotKind(ToString(kind), read)) << ToString(kind);
    EXPECT_EQ(read, kind);
  }
  EXPECT_STREQ(ToString(RobotKind::kDrone), "drone");
  EXPECT_STREQ(ToString(static_cast<RobotKind>(3)), "?");
  RobotKind kind = RobotKind::kRover;
  for (const char* name : {"tank", "Drone", "", "omni ", "?"}) {
    EXPECT_FALSE(ParseRobotKind(name, kind)) << name;
    EXPECT_EQ(kind, RobotKind::kRover) << name;  // unchanged
  }
}

TEST(RobotKindTest, ADroneHasItsLagGainAndHoldAndTheOthersHaveNone) {
  const ControllerConfig drone = ControllerConfigFor(RobotKind::kDrone, DefaultKindLimits(RobotKind::kDrone));
  EXPECT_EQ(drone.kind, DriveKind::kOmni);
  EXPECT_FLOAT_EQ(drone.limits.max_speed_mps, 0.8f);
  EXPECT_FLOAT_EQ(drone.limits.max_accel_mps2, 0.5f);
  EXPECT_FLOAT_EQ(drone.limits.response_lag_s, 0.25f);
  EXPECT_EQ(drone.position_gain_per_s, kDronePositionGainPerS);
  EXPECT_TRUE(drone.hold_position);

  const ControllerConfig omni = ControllerConfigFor(RobotKind::kOmni, DefaultKindLimits(RobotKind::kOmni));
  const ControllerConfig rover = ControllerConfigFor(RobotKind::kRover, DefaultKindLimits(RobotKind::kRover));
  EXPECT_EQ(omni.kind, DriveKind::kOmni);
  EXPECT_EQ(rover.kind, DriveKind::kWheels);
  EXPECT_FLOAT_EQ(rover.limits.max_speed_mps, 0.4f);
  for (const ControllerConfig& ground : {omni, rover}) {
    EXPECT_EQ(ground.limits.response_lag_s, 0.0f);
    EXPECT_EQ(ground.position_gain_per_s, ControllerConfig{}.position_gain_per_s);
    EXPECT_FALSE(ground.hold_position);
  }
}

TEST(RobotKindTest, TheSafetyFilterPlansForTheFastestLargestWeakestAndSlowestKindPresent) {
  const std::array<SwarmKind, 3> all = {SwarmKind{RobotKind::kOmni, DefaultKindLimits(RobotKind::kOmni)},
                                        SwarmKind{RobotKind::kRover, DefaultKindLimits(RobotKind::kRover)},
                                        SwarmKind{RobotKind::kDrone, DefaultKindLimits(RobotKind::kDrone)}};
  SafetyConfig mixed;
  SetOthers(mixed, all);
  EXPECT_FLOAT_EQ(mixed.others_max_speed_mps, 0.8f);      // the drone's
  EXPECT_FLOAT_EQ(mixed.others_radius_m, 0.12f);          // rover and drone
  EXPECT_FLOAT_EQ(mixed.others_braking_mps2, 0.8f * 0.5f);  // the drone's
  EXPECT_FLOAT_EQ(mixed.others_lag_s, 0.25f);             // the drone's tilt

  SafetyConfig omni;
  SetOthers(omni, std::span<const SwarmKind>(all.data(), 1));
  EXPECT_FLOAT_EQ(omni.others_max_speed_mps, 0.5f);
  EXPECT_FLOAT_EQ(omni.others_radius_m, 0.10f);
  EXPECT_FLOAT_EQ(omni.others_braking_mps2, 0.8f);
  EXPECT_EQ(omni.others_lag_s, 0.0f);

  // Order does not matter, and nothing else changes; no kinds change nothing.
  const std::array<SwarmKind, 3> reversed = {all[2], all[1], all[0]};
  SafetyConfig again;
  again.margin_m = 0.5f;
  SetOthers(again, reversed);
  EXPECT_EQ(again.others_max_speed_mps, mixed.others_max_speed_mps);
  EXPECT_EQ(again.others_radius_m, mixed.others_radius_m);
  EXPECT_EQ(again.others_braking_mps2, mixed.others_braking_mps2);
  EXPECT_EQ(again.others_lag_s, mixed.others_lag_s);
  EXPECT_EQ(again.margin_m, 0.5f);
  SafetyConfig untouched;
  SetOthers(untouched, {});
  EXPECT_EQ(untouched.others_radius_m, SafetyConfig{}.others_radius_m);
}

}  // namespace
}  // namespace syrof::motion
