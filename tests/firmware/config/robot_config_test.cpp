// syrof-firmware-config's work (firmware/config robot_config.h): a robot's
// block from a scenario holds its id, the swarm's size, its own inputs and
// the scenario's id, and reads back on the image (BootConfigBlock) into
// them; what a robot cannot be told is refused by name; the block goes into
// the image's own section and nowhere else.
#include "syrof/firmware/config/robot_config.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "test_elf.h"

namespace syrof::firmware::config {
namespace {

lab::scenario::Scenario Load(const std::string& file, lab::scenario::Overrides overrides = {}) {
  const lab::scenario::LoadResult loaded =
      lab::scenario::LoadScenarioFile(std::string(SYROF_TEST_DIR) + "/" + file, overrides);
  EXPECT_TRUE(loaded.ok()) << loaded.error->ToString();
  return *loaded.scenario;
}

TEST(RobotConfigTest, ARobotsBlockHoldsItsOwnInputsAndReadsBack) {
  const lab::scenario::Scenario scenario = Load("four_robots.yaml");
  const RobotBlockOrError made = MakeRobotBlock(scenario, 2);
  ASSERT_TRUE(made.ok()) << made.error->ToString();
  EXPECT_EQ(made.block->robot_id, 2);
  EXPECT_EQ(made.block->swarm_size, 4);
  EXPECT_EQ(made.block->inputs, 2u);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(made.block->bytes.data() + robot::kConfigBlockHeaderBytes)),
            "id 2 swarm 4 inputs 2:2 input charge=791 input key=0.3333333333333333");
  robot::BootConfigBlock boot;
  ASSERT_EQ(boot.Read(made.block->bytes), robot::ConfigBlockState::kFilled) << boot.error();
  EXPECT_EQ(boot.robot_id(), 2);
  EXPECT_EQ(boot.scenario_id(), ScenarioId(scenario));
  ASSERT_EQ(boot.inputs().size(), 2u);
  EXPECT_EQ(boot.inputs()[0].name, "charge");
  EXPECT_EQ(boot.inputs()[0].value, 791);
  EXPECT_EQ(boot.inputs()[1].value, 1.0 / 3.0);
}

TEST(RobotConfigTest, ARobotsBlockHoldsItsKindAndTheSwarmsAsTheSwarmHostWritesThem) {
  const lab::scenario::Scenario scenario = Load("drone_among_omni.yaml");
  const RobotBlockOrError drone = MakeRobotBlock(scenario, 2);
  ASSERT_TRUE(drone.ok()) << drone.error->ToString();
  EXPECT_EQ(drone.block->kind, motion::RobotKind::kDrone);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(drone.block->bytes.data() + robot::kConfigBlockHeaderBytes)),
            "id 2 swarm 4 kind drone swarm_kinds omni,drone member_kinds oodo inputs 2:1 input charge=791");
  robot::BootConfigBlock boot;
  ASSERT_EQ(boot.Read(drone.block->bytes), robot::ConfigBlockState::kFilled) << boot.error();
  EXPECT_EQ(boot.kind(), motion::RobotKind::kDrone);
  EXPECT_EQ(boot.swarm_kinds(), robot::KindBit(motion::RobotKind::kOmni) | robot::KindBit(motion::RobotKind::kDrone));
  // An omni robot of the same swarm is told its kind and the swarm's too.
  const RobotBlockOrError omni = MakeRobotBlock(scenario, 0);
  ASSERT_TRUE(omni.ok());
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(omni.block->bytes.data() + robot::kConfigBlockHeaderBytes)),
            "id 0 swarm 4 kind omni swarm_kinds omni,drone member_kinds oodo inputs 0:1 input charge=38");
  // The kinds are part of the scenario's id: the same robots all omni give another.
  lab::scenario::Scenario all_omni = scenario;
  all_omni.robots[2].kind = motion::RobotKind::kOmni;
  EXPECT_NE(ScenarioId(all_omni), ScenarioId(scenario));
}

TEST(RobotConfigTest, TheScenarioIdIsTheSameForEveryRobotAndChangesWithTheInputs) {
  const lab::scenario::Scenario scenario = Load("four_robots.yaml");
  const uint64_t id = ScenarioId(scenario);
  for (int robot = 0; robot < 4; ++robot) EXPECT_EQ(MakeRobotBlock(scenario, robot).block->scenario_id, id);
  lab::scenario::Scenario other = scenario;
  other.inputs["charge"][3] = 657;
  EXPECT_NE(ScenarioId(other), id);
  other = scenario;
  other.name = "four_robots_b";
  EXPECT_NE(ScenarioId(other), id);
  // Drawn inputs: another seed draws others, so another id.
  lab::scenario::Overrides seed_2;
  seed_2.seed = 2;
  EXPECT_NE(ScenarioId(Load("inputs_do_not_fit.yaml")), ScenarioId(Load("inputs_do_not_fit.yaml", seed_2)));
  EXPECT_EQ(ScenarioId(Load("four_robots.yaml")), id);  // and the same file, the same id
}

TEST(RobotConfigTest, WhatARobotCannotBeToldIsRefusedByName) {
  const lab::scenario::Scenario scenario = Load("four_robots.yaml");
  const std::string file = std::string(SYROF_TEST_DIR) + "/four_robots.yaml";
  EXPECT_EQ(MakeRobotBlock(scenario, 4).error->ToString(),
            file + ": robot 4 is not in the scenario (it has robots 0 to 3)");
  EXPECT_EQ(MakeRobotBlock(scenario, -1).error->ToString(),
            file + ": robot -1 is not in the scenario (it has robots 0 to 3)");
  lab::scenario::Scenario short_list = scenario;
  short_list.inputs["key"].resize(2);
  EXPECT_EQ(MakeRobotBlock(short_list, 3).error->ToString(),
            file + ": inputs.key gives 2 values; robot 3 has none (one value per robot, in id order)");
  lab::scenario::Scenario infinite = scenario;
  infinite.inputs["charge"][1] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(MakeRobotBlock(infinite, 1).error->ToString(),
            file + ": inputs.charge: robot 1's value inf is not a finite number");
  infinite.inputs["charge"][1] = std::nan("");
  EXPECT_EQ(MakeRobotBlock(infinite, 1).error->ToString(),
            file + ": inputs.charge: robot 1's value nan is not a finite number");
  EXPECT_TRUE(MakeRobotBlock(infinite, 0).ok());  // only the robot's own values matter
  const RobotBlockOrError long_inputs = MakeRobotBlock(Load("inputs_do_not_fit.yaml"), 0);
  ASSERT_FALSE(long_inputs.ok());
  EXPECT_NE(long_inputs.error->message.find("inputs: robot 0's 16 inputs take "), std::string::npos)
      << long_inputs.error->message;
  EXPECT_NE(long_inputs.error->message.find(" bytes of words, with its id and swarm more than the 1003 the "
                                            "configuration block holds (shorter input names fit)"),
            std::string::npos)
      << long_inputs.error->message;
}

// The image has the default kinds' limits compiled in: a scenario that
// changes a present kind's is refused for every robot, the omni robots of
// a swarm with faster drones too (they brake for the drone they believe
// in), in the emulated swarm's host's words (lab/scenario fits_the_image.h).
TEST(RobotConfigTest, LimitsOtherThanTheImagesAreRefusedForEveryRobot) {
  const std::string file = std::string(SYROF_TEST_DIR) + "/kind_limits.yaml";
  const lab::scenario::Scenario scenario = Load("kind_limits.yaml");
  for (int robot = 0; robot < 4; ++robot) {
    const RobotBlockOrError made = MakeRobotBlock(scenario, robot);
    ASSERT_FALSE(made.ok()) << "robot " << robot;
    EXPECT_EQ(made.error->ToString(),
              file + ": kinds.drone.max_speed_mps is 1; the robot image has 0.8 compiled in (the default kinds, "
                     "docs/scenarios.md) and would drive its robots with other limits");
  }
  // With the drone's default limits, the same swarm is written.
  lab::scenario::Scenario defaults = scenario;
  defaults.drone = lab::world::DefaultKindSpec(lab::world::RobotKind::kDrone);
  EXPECT_TRUE(MakeRobotBlock(defaults, 2).ok());
  // A robot not in the scenario is still named as such first.
  EXPECT_EQ(MakeRobotBlock(scenario, 4).error->ToString(),
            file + ": robot 4 is not in the scenario (it has robots 0 to 3)");
}

// The image has the default 4 m arena's anchors and the 50 ms radio round
// compiled in: a scenario on another arena or round is refused for every
// robot (before, the blocks were written and the robots' estimates were off,
// silently), in the emulated swarm's host's words.
TEST(RobotConfigTest, AnotherArenaOrRadioRoundIsRefusedForEveryRobot) {
  const std::string file = std::string(SYROF_TEST_DIR) + "/arena_5m.yaml";
  const lab::scenario::Scenario scenario = Load("arena_5m.yaml");
  for (int robot = 0; robot < 4; ++robot) {
    const RobotBlockOrError made = MakeRobotBlock(scenario, robot);
    ASSERT_FALSE(made.ok()) << "robot " << robot;
    EXPECT_EQ(made.error->ToString(),
              file + ": the arena is 5 m x 5 m; the robot image has the default arena compiled in (4 m x 4 m, "
                     "tag_height_m 0.10, the four default anchors; docs/scenarios.md) and its estimates would be off");
  }
  // On the default arena the same swarm is written.
  EXPECT_TRUE(MakeRobotBlock(Load("four_robots.yaml"), 0).ok());
  // Another radio round.
  lab::scenario::Scenario slow = Load("four_robots.yaml");
  slow.timing.radio_round_s = 0.1;
  const RobotBlockOrError made = MakeRobotBlock(slow, 1);
  ASSERT_FALSE(made.ok());
  EXPECT_EQ(made.error->message, "timing.radio_round_s must be 0.05 (the robot image's radio round)");
  // A robot not in the scenario is still named as such first.
  EXPECT_EQ(MakeRobotBlock(scenario, 4).error->ToString(),
            file + ": robot 4 is not in the scenario (it has robots 0 to 3)");
}

TEST(RobotConfigTest, TheBlockGoesIntoItsSectionAndNowhereElse) {
  const std::vector<uint8_t> original = testing::MakeTestElf();
  ElfOrError image = ParseElf(original, "robot.elf");
  ASSERT_TRUE(image.ok());
  const RobotBlockOrError made = MakeRobotBlock(Load("four_robots.yaml"), 1);
  ASSERT_TRUE(made.ok());
  ASSERT_FALSE(WriteBlock(*image.elf, "robot.elf", *made.block).has_value());
  const ElfSection* section = image.elf->Find(".syrof_config");
  for (size_t i = 0; i < original.size(); ++i) {
    const bool inside = i >= section->file_offset && i < section->file_offset + section->size;
    ASSERT_EQ(image.elf->bytes[i], inside ? made.block->bytes[i - section->file_offset] : original[i]) << "byte " << i;
  }
  // And the written file reads as the same ELF, its block filled.
  const ElfOrError again = ParseElf(image.elf->bytes, "robot2.elf");
  ASSERT_TRUE(again.ok());
  robot::BootConfigBlock boot;
  const auto block = std::span<const uint8_t, robot::kConfigBlockBytes>(
      again.elf->bytes.data() + again.elf->Find(".syrof_config")->file_offset, robot::kConfigBlockBytes);
  EXPECT_EQ(boot.Read(block), robot::ConfigBlockState::kFilled) << boot.error();
  EXPECT_EQ(boot.robot_id(), 1);
}

TEST(RobotConfigTest, AnImageWithoutTheBlocksSectionIsRefused) {
  const RobotBlockOrError made = MakeRobotBlock(Load("four_robots.yaml"), 1);
  ASSERT_TRUE(made.ok());
  ElfOrError none = ParseElf(testing::MakeTestElf({.config_section = false}), "old.elf");
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(WriteBlock(*none.elf, "old.elf", *made.block)->ToString(),
            "old.elf: the image has no .syrof_config section (the configuration block): build it from this tree "
            "(make firmware, or the M4 build's syrof-robot-mps2)");
  ElfOrError no_contents = ParseElf(testing::MakeTestElf({.config_contents = false}), "noload.elf");
  ASSERT_TRUE(no_contents.ok()) << no_contents.error->ToString();
  EXPECT_EQ(WriteBlock(*no_contents.elf, "noload.elf", *made.block)->ToString(),
            "noload.elf: its .syrof_config section is 1024 bytes without contents; the block is 1024 bytes of flash");
  ElfOrError small = ParseElf(testing::MakeTestElf({.config_size = 512}), "small.elf");
  ASSERT_TRUE(small.ok());
  EXPECT_EQ(WriteBlock(*small.elf, "small.elf", *made.block)->ToString(),
            "small.elf: its .syrof_config section is 512 bytes; the block is 1024 bytes of flash");
}

}  // namespace
}  // namespace syrof::firmware::config
