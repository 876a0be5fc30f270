// syrof-firmware-config's work (docs/demo-day.md, "Flashing each robot with
// its inputs"): one robot's configuration block (firmware/robot
// config_block.h) from a scenario, written into a copy of a built robot
// image. The main only parses the command line and calls these.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/firmware/config/elf_file.h"
#include "syrof/firmware/robot/config_block.h"
#include "syrof/lab/base/error.h"
#include "syrof/lab/scenario/scenario.h"

namespace syrof::firmware::config {

/// The scenario's identifier: FNV-1a (64 bits) of its name, its robot
/// count, every robot's kind, and every input's name and every robot's value of it (in name
/// order, each value as the 17 significant digits that read back to it).
/// Every robot of one scenario gets the same one; another seed that draws
/// other inputs, another robot count or another name gives another.
uint64_t ScenarioId(const lab::scenario::Scenario& scenario);

/// One robot's block, encoded.
struct RobotBlock {
  uint16_t robot_id = 0;
  uint16_t swarm_size = 0;
  uint64_t scenario_id = 0;
  size_t inputs = 0;        ///< how many
  motion::RobotKind kind = motion::RobotKind::kOmni;  ///< the robot's own
  robot::KindSet swarm_kinds = 0;                     ///< every robot's of the scenario (KindBit)
  size_t words_length = 0;  ///< bytes of words (at most kConfigBlockMaxWordsBytes)
  std::array<uint8_t, robot::kConfigBlockBytes> bytes{};
};

struct RobotBlockOrError {
  std::optional<RobotBlock> block;
  std::optional<lab::Error> error;
  bool ok() const { return block.has_value(); }
};

/// Robot `robot_id`'s block from `scenario` (its kind and the swarm's kinds,
/// as the emulated swarm's host writes them on a boot line, and its own
/// inputs only). Refused, by name: a robot id not in the scenario, a radio
/// round, an arena or a present kind's limits other than the image's
/// compiled-in defaults (lab/scenario fits_the_image.h, the emulated swarm's
/// check), an input with no value for the robot, a value that is not finite,
/// more inputs than the image holds, a name the image does not take, and
/// words that do not fit the block (the bytes they take).
RobotBlockOrError MakeRobotBlock(const lab::scenario::Scenario& scenario, int robot_id);

/// Writes `block` into `image`'s configuration section (in place, in the
/// file's bytes). Refused: an image with no `.syrof_config` section, or one
/// that is not 1024 bytes of contents in flash.
std::optional<lab::Error> WriteBlock(ElfFile& image, const std::string& image_path, const RobotBlock& block);

/// `image` as an ELF file, or as Intel HEX when `path` ends in ".hex".
std::optional<lab::Error> WriteImage(const ElfFile& image, const std::string& path);

}  // namespace syrof::firmware::config
