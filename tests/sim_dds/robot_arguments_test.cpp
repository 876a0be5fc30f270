#include <gtest/gtest.h>

#include "syrof/sim_dds/robot_process.h"

namespace syrof::sim_dds {
namespace {

TEST(RobotArgumentsTest, WhatTheWorldWritesTheRobotReadsBack) {
  RobotProcessOptions options;
  options.scenario_path = "/tmp/a b.yaml";
  options.robot = 31;
  options.run_id = 18446744073709551615ull;
  options.domain_id = 232;
  options.interface = "veth0";
  options.parent_pid = 4242;
  options.log_directory = "/tmp/out/robots";
  options.overrides.seed = 7;
  options.overrides.robots = 32;
  options.overrides.duration_s = 0.1;
  options.overrides.app = "/tmp/libmyapp.so";
  options.realtime = true;
  options.align_rounds = true;
  options.realtime_start = true;
  options.clock_offset_us = -41'000;
  const ParsedRobotArguments parsed = ParseRobotArguments(RobotArguments(options));
  ASSERT_TRUE(parsed.ok()) << parsed.error->ToString();
  const RobotProcessOptions& back = *parsed.options;
  EXPECT_EQ(back.scenario_path, options.scenario_path);
  EXPECT_EQ(back.robot, 31);
  EXPECT_EQ(back.run_id, options.run_id);
  EXPECT_EQ(back.domain_id, 232u);
  EXPECT_EQ(back.interface, "veth0");
  EXPECT_EQ(back.parent_pid, 4242);
  EXPECT_EQ(back.log_directory, options.log_directory);
  EXPECT_EQ(back.overrides.seed, 7u);
  EXPECT_EQ(back.overrides.robots, 32);
  EXPECT_EQ(back.overrides.duration_s, 0.1);  // printed with 17 digits: exact
  EXPECT_EQ(back.overrides.app, options.overrides.app);
  EXPECT_TRUE(back.realtime);
  EXPECT_TRUE(back.align_rounds);
  EXPECT_TRUE(back.realtime_start);
  EXPECT_EQ(back.clock_offset_us, -41'000);
  // Flags left off are not written, and read back off.
  RobotProcessOptions plain_options;
  plain_options.scenario_path = "s";
  const ParsedRobotArguments plain = ParseRobotArguments(RobotArguments(plain_options));
  ASSERT_TRUE(plain.ok()) << plain.error->ToString();
  EXPECT_FALSE(plain.options->realtime || plain.options->align_rounds || plain.options->realtime_start);
  EXPECT_EQ(plain.options->clock_offset_us, 0);
}

// The stress's late samples reach the robot (it plays them, RadioOptionsFor
// and WorldLink); without a seed nothing is passed.
TEST(RobotArgumentsTest, TheLateSamplesOfTheStressReachTheRobot) {
  RobotProcessOptions options;
  options.scenario_path = "s.yaml";
  options.stress.seed = 123456789012345ull;
  options.stress.delayed_fraction = 0.2;
  options.stress.min_delay_ms = 15;
  options.stress.max_delay_ms = 180;
  const ParsedRobotArguments parsed = ParseRobotArguments(RobotArguments(options));
  ASSERT_TRUE(parsed.ok()) << parsed.error->ToString();
  EXPECT_EQ(parsed.options->stress.seed, options.stress.seed);
  EXPECT_EQ(parsed.options->stress.delayed_fraction, 0.2);
  EXPECT_EQ(parsed.options->stress.min_delay_ms, 15);
  EXPECT_EQ(parsed.options->stress.max_delay_ms, 180);
  options.stress.seed = 0;
  const ParsedRobotArguments off = ParseRobotArguments(RobotArguments(options));
  ASSERT_TRUE(off.ok()) << off.error->ToString();
  EXPECT_FALSE(off.options->stress.on());
  const ParsedRobotArguments above_one =
      ParseRobotArguments({"--scenario", "s", "--robot", "0", "--run-id", "1", "--domain", "0", "--late-fraction", "2"});
  ASSERT_FALSE(above_one.ok());
  EXPECT_EQ(above_one.error->ToString(), "argument --late-fraction: \"2\" is not a valid value");
}

TEST(RobotArgumentsTest, BadArgumentsAreNamed) {
  auto error_of = [](const std::vector<std::string>& arguments) {
    const ParsedRobotArguments parsed = ParseRobotArguments(arguments);
    EXPECT_FALSE(parsed.ok());
    return parsed.error ? parsed.error->ToString() : std::string("(no error)");
  };
  EXPECT_EQ(error_of({"--robot", "70000", "--scenario", "s", "--run-id", "1", "--domain", "1"}),
            "argument --robot: \"70000\" is not a valid value");
  EXPECT_EQ(error_of({"--domain", "233"}), "argument --domain: \"233\" is not a valid value");
  EXPECT_EQ(error_of({"--robot", "-1"}), "argument --robot: \"-1\" is not a valid value");
  EXPECT_EQ(error_of({"--clock-offset-us", "10000001"}), "argument --clock-offset-us: \"10000001\" is not a valid value");
  EXPECT_EQ(error_of({"--clock-offset-us", "5ms"}), "argument --clock-offset-us: \"5ms\" is not a valid value");
  EXPECT_EQ(error_of({"--colour", "red"}), "unknown argument --colour");
  EXPECT_EQ(error_of({"--scenario"}), "argument --scenario has no value");
  EXPECT_EQ(error_of({"--scenario", "s"}), "--scenario, --robot, --run-id and --domain are required");
}

}  // namespace
}  // namespace syrof::sim_dds
