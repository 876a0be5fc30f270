// syrof-firmware-config: writes one robot's configuration block (its id,
// the swarm's size, its kind and its swarm's kinds, and its own private
// inputs from a scenario's `inputs:`;
// firmware/robot config_block.h) into a copy of a built robot image, as
// Intel HEX for teensy-loader-cli or as an ELF (docs/demo-day.md, "Flashing
// each robot with its inputs"):
//
//   syrof-firmware-config --scenario S.yaml --robot 2 --image build-teensy/bin/syrof-robot.elf --out robot2.hex
//
// Exit status 0 when written, 2 for bad input (named: the scenario, a robot
// it does not have, a radio round, an arena or a present kind's limits
// other than the defaults the image has compiled in, an input with no value
// for the robot or not finite, inputs that do not fit the block, an image
// without the block's section), 1 when the output cannot be written. This file only wires the command
// line to robot_config.h.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "syrof/firmware/config/robot_config.h"
#include "syrof/lab/scenario/scenario.h"

namespace {

namespace config = syrof::firmware::config;
namespace robot = syrof::firmware::robot;

constexpr int kOk = 0;
constexpr int kFailed = 1;
constexpr int kBadInput = 2;

struct Options {
  std::string scenario;
  int robot = -1;
  std::string image;
  std::string out;
  std::optional<uint64_t> seed;
};

int Fail(int status, const syrof::lab::Error& error) {
  std::fprintf(stderr, "syrof-firmware-config: %s\n", error.ToString().c_str());
  return status;
}

int Run(const Options& options) {
  syrof::lab::scenario::Overrides overrides;
  overrides.seed = options.seed;
  const syrof::lab::scenario::LoadResult loaded = syrof::lab::scenario::LoadScenarioFile(options.scenario, overrides);
  if (!loaded.ok()) return Fail(kBadInput, *loaded.error);
  const config::RobotBlockOrError block = config::MakeRobotBlock(*loaded.scenario, options.robot);
  if (!block.ok()) return Fail(kBadInput, *block.error);
  config::ElfOrError image = config::ReadElfFile(options.image);
  if (!image.ok()) return Fail(kBadInput, *image.error);
  if (const auto error = config::WriteBlock(*image.elf, options.image, *block.block)) return Fail(kBadInput, *error);
  if (const auto error = config::WriteImage(*image.elf, options.out)) return Fail(kFailed, *error);

  char scenario_id[17];
  robot::FormatScenarioId(block.block->scenario_id, scenario_id);
  std::string inputs;
  for (const auto& [name, values] : loaded.scenario->inputs) {
    // As the block holds it: the fewest digits (15 to 17) that read back.
    const double number = values[static_cast<size_t>(options.robot)];
    char value[40];
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(value, sizeof value, "%.*g", digits, number);
      if (std::strtod(value, nullptr) == number) break;
    }
    inputs += (inputs.empty() ? ": " : ", ") + name + "=" + value;
  }
  // The kinds as the block's words say them.
  std::string kinds = std::string("kind ") + syrof::motion::ToString(block.block->kind);
  if (block.block->swarm_kinds != robot::KindBit(block.block->kind)) {
    kinds += " (swarm_kinds ";
    bool first = true;
    for (size_t i = 0; i < syrof::motion::kRobotKindCount; ++i) {
      const auto kind = static_cast<syrof::motion::RobotKind>(i);
      if ((block.block->swarm_kinds & robot::KindBit(kind)) == 0) continue;
      kinds += std::string(first ? "" : ",") + syrof::motion::ToString(kind);
      first = false;
    }
    kinds += ")";
  }
  const config::ElfSection* section = image.elf->Find(robot::kConfigBlockSection);
  std::printf("%s: robot %u of %u, %s, scenario %s (id %s), %zu input%s%s; block at 0x%08x\n", options.out.c_str(),
              static_cast<unsigned>(block.block->robot_id), static_cast<unsigned>(block.block->swarm_size),
              kinds.c_str(), loaded.scenario->name.c_str(), scenario_id, block.block->inputs, block.block->inputs == 1 ? "" : "s",
              inputs.c_str(), static_cast<unsigned>(section->load_address));
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "syrof-firmware-config: writes one robot's configuration block (its id, the swarm's size, its kind and its "
      "swarm's kinds, and its own private inputs from the scenario's inputs:) into a copy of a built robot image, to flash onto that robot "
      "(docs/demo-day.md). Run it once per robot.",
      "syrof-firmware-config"};
  Options options;
  app.add_option("--scenario", options.scenario, "the scenario file whose robots and inputs: to use")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--robot", options.robot, "the robot's id in the scenario (0 .. robots - 1)")->required();
  app.add_option("--image", options.image,
                 "the built image (ELF): build-teensy/bin/syrof-robot.elf (make firmware), or the M4 build's "
                 "syrof-robot-mps2.elf")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--out", options.out,
                 "the robot's image to write: Intel HEX for teensy-loader-cli when it ends in .hex, else an ELF")
      ->required();
  app.add_option("--seed", options.seed, "the scenario's seed instead of the file's (the inputs it draws)");
  // A word the tool does not take is named first, before a required
  // option it may hide (`--bogus` alone said "--scenario is required").
  app.allow_extras();
  const auto unknown_word = [&app]() -> bool {
    const std::vector<std::string> words = app.remaining();
    if (words.empty()) return false;
    const std::string& word = words.front();
    std::cerr << "syrof-firmware-config: " << (word.starts_with("-") && word != "-" ? "unknown option '" : "unexpected argument '")
              << word << "'\n(syrof-firmware-config --help lists the options)\n";
    return true;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kOk;
  } catch (const CLI::ParseError& parse_error) {
    if (unknown_word()) return kBadInput;
    std::cerr << "syrof-firmware-config: " << parse_error.what() << "\n(syrof-firmware-config --help lists the options)\n";
    return kBadInput;
  }
  if (unknown_word()) return kBadInput;
  return Run(options);
}
