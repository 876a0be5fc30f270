// Each robot is told its kind and, in a swarm of mixed kinds, the swarm's:
// by default in its own image's configuration block (WriteRobotImages, the
// block syrof-firmware-config writes), with --config-on-boot-line on its
// boot line (qemu_launcher.h, ImageAppend; boot_words.h). The robot image
// runs the motion layer of that kind (docs/firmware.md, "Robot kinds").
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include "syrof/firmware/config/elf_file.h"
#include "syrof/firmware/robot/config_block.h"
#include "syrof/firmware/swarm/qemu_launcher.h"
#include "syrof/firmware/swarm/swarm_options.h"
#include "test_elf.h"

namespace syrof::firmware::swarm {
namespace {

lab::scenario::Scenario KindsScenario(const std::string& text) {
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

TEST(BootKindsTest, OnTheBootLineEachRobotIsToldItsKindAndAMixedSwarmItsKinds) {
  const lab::scenario::Scenario mixed = KindsScenario(R"(robots:
  kind: omni
  poses:
    - { x_m: 1.0, y_m: 1.0 }
    - { x_m: 2.0, y_m: 1.0, kind: rover }
    - { x_m: 3.0, y_m: 1.0, kind: drone }
app: builtin:circle
)");
  Options options;
  options.config_on_boot_line = true;
  EXPECT_NE(ImageAppend(options, mixed, 0).find(" kind omni swarm_kinds omni,rover,drone member_kinds ord"), std::string::npos)
      << ImageAppend(options, mixed, 0);
  EXPECT_NE(ImageAppend(options, mixed, 1).find(" kind rover swarm_kinds omni,rover,drone member_kinds ord"), std::string::npos);
  EXPECT_NE(ImageAppend(options, mixed, 2).find(" kind drone swarm_kinds omni,rover,drone member_kinds ord"), std::string::npos);

  const lab::scenario::Scenario drones =
      KindsScenario("robots: { count: 2, kind: drone, placement: grid, spacing_m: 0.6 }\napp: builtin:circle\n");
  const std::string drone = ImageAppend(options, drones, 1);
  EXPECT_NE(drone.find(" kind drone"), std::string::npos) << drone;
  EXPECT_EQ(drone.find("swarm_kinds"), std::string::npos) << drone;  // its own kind alone
  EXPECT_EQ(drone.find("member_kinds"), std::string::npos) << drone;  // every robot is of it

  // Omni robots among omni robots: the line every image had before.
  const lab::scenario::Scenario omni =
      KindsScenario("robots: { count: 2, placement: grid, spacing_m: 0.6 }\napp: builtin:circle\n");
  EXPECT_EQ(ImageAppend(options, omni, 0).find("kind"), std::string::npos) << ImageAppend(options, omni, 0);
}

const char* const kMixedInputs = R"(name: mixed
robots:
  kind: omni
  poses:
    - { x_m: 1.0, y_m: 1.0 }
    - { x_m: 2.0, y_m: 1.0, kind: rover }
    - { x_m: 3.0, y_m: 1.0, kind: drone }
app: builtin:circle
inputs:
  charge: [10, 20, 30]
)";

// By default the boot line says only what drives the emulation; who the
// robot is, its kind and its inputs are in its own copy of the image, as
// syrof-firmware-config writes it, and nowhere on the line.
TEST(BootKindsTest, ByDefaultEachRobotsOwnImageHoldsItsBlockAndTheLineOnlyDrives) {
  const lab::scenario::Scenario mixed = KindsScenario(kMixedInputs);
  const std::string dir = std::filesystem::temp_directory_path() / ("syrof_boot_kinds_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::vector<uint8_t> built = config::testing::MakeTestElf();
  ASSERT_FALSE(config::WriteFile(dir + "/built.elf", built).has_value());
  Options options;
  options.image = dir + "/built.elf";
  options.out = dir + "/run";
  std::filesystem::create_directories(options.out);

  for (uint16_t id = 0; id < 3; ++id) {
    const std::string line = ImageAppend(options, mixed, id);
    EXPECT_EQ(line.rfind("hold 1 report 1 sensors 1 align 1 x_mm ", 0), 0u) << line;
    for (const char* word : {"id ", "swarm ", "kind", "input"}) {
      EXPECT_EQ((" " + line).find(std::string(" ") + word), std::string::npos) << word << " in " << line;
    }
    EXPECT_EQ(RobotImagePath(options, id), options.out + "/robot_" + std::to_string(id) + ".elf");
  }
  ASSERT_TRUE(WriteRobotImages(options, mixed));
  const robot::KindSet all = robot::KindBit(motion::RobotKind::kOmni) | robot::KindBit(motion::RobotKind::kRover) |
                             robot::KindBit(motion::RobotKind::kDrone);
  const motion::RobotKind kinds[] = {motion::RobotKind::kOmni, motion::RobotKind::kRover, motion::RobotKind::kDrone};
  for (uint16_t id = 0; id < 3; ++id) {
    const config::ElfOrError copy = config::ReadElfFile(RobotImagePath(options, id));
    ASSERT_TRUE(copy.ok()) << copy.error->ToString();
    const config::ElfSection* section = copy.elf->Find(robot::kConfigBlockSection);
    ASSERT_NE(section, nullptr);
    std::array<uint8_t, robot::kConfigBlockBytes> bytes{};
    std::copy_n(copy.elf->bytes.begin() + section->file_offset, bytes.size(), bytes.begin());
    robot::BootConfigBlock block;
    ASSERT_EQ(block.Read(bytes), robot::ConfigBlockState::kFilled) << block.error();
    EXPECT_EQ(block.robot_id(), id);
    EXPECT_EQ(block.swarm_size(), 3);
    EXPECT_EQ(block.kind(), kinds[id]);
    EXPECT_EQ(block.swarm_kinds(), all);
    ASSERT_EQ(block.inputs().size(), 1u);
    EXPECT_EQ(block.inputs()[0].name, "charge");
    EXPECT_EQ(block.inputs()[0].value, 10.0 * (id + 1));  // its own value, no other robot's
    // Everything else of the image is the built one's.
    std::vector<uint8_t> rest = copy.elf->bytes;
    std::fill_n(rest.begin() + section->file_offset, bytes.size(), 0);
    EXPECT_EQ(rest, built);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace syrof::firmware::swarm
