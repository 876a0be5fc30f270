#include "syrof/firmware/config/robot_config.h"

#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>

#include "syrof/firmware/config/intel_hex.h"
#include "syrof/lab/scenario/fits_the_image.h"

namespace syrof::firmware::config {

namespace {

constexpr uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr uint64_t kFnvPrime = 0x100000001b3ull;

void Hash(uint64_t& hash, std::string_view text) {
  for (const char c : text) {
    hash ^= static_cast<uint8_t>(c);
    hash *= kFnvPrime;
  }
}

lab::Error ScenarioError(const lab::scenario::Scenario& scenario, std::string message) {
  return lab::Error{.where = scenario.source.empty() ? scenario.name : scenario.source, .message = std::move(message)};
}

std::string SeventeenDigits(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

}  // namespace

uint64_t ScenarioId(const lab::scenario::Scenario& scenario) {
  uint64_t hash = kFnvOffset;
  Hash(hash, "syrof scenario id 1\n");
  Hash(hash, scenario.name);
  Hash(hash, "\nrobots " + std::to_string(scenario.robots.size()) + "\n");
  // Each robot's kind (its motion layer on the image, from its block).
  for (const lab::scenario::RobotSpec& robot : scenario.robots) {
    Hash(hash, std::string(motion::ToString(robot.kind)) + " ");
  }
  Hash(hash, "\n");
  for (const auto& [name, values] : scenario.inputs) {
    Hash(hash, name);
    for (const double value : values) Hash(hash, " " + SeventeenDigits(value));
    Hash(hash, "\n");
  }
  return hash;
}

RobotBlockOrError MakeRobotBlock(const lab::scenario::Scenario& scenario, int robot_id) {
  const auto robots = static_cast<int>(scenario.robots.size());
  if (robot_id < 0 || robot_id >= robots) {
    return {std::nullopt, ScenarioError(scenario, "robot " + std::to_string(robot_id) +
                                                      " is not in the scenario (it has robots 0 to " +
                                                      std::to_string(robots - 1) + ")")};
  }
  // The image has the radio round, the default arena's anchors and the
  // default kinds' limits compiled in and cannot be told others: refused as
  // the emulated swarm's host refuses them (a robot on a 5 m arena would
  // range against the 4 m one's anchors, its estimates off, silently).
  if (auto error = lab::scenario::CheckScenarioFitsTheImage(scenario)) return {std::nullopt, std::move(error)};
  if (robots > static_cast<int>(robot::kConfigBlockMaxSwarmSize)) {
    return {std::nullopt, ScenarioError(scenario, std::to_string(robots) + " robots; the robot image holds at most " +
                                                      std::to_string(robot::kConfigBlockMaxSwarmSize))};
  }
  if (scenario.inputs.size() > robot::kMaxBootInputs) {
    return {std::nullopt, ScenarioError(scenario, "inputs: " + std::to_string(scenario.inputs.size()) +
                                                      " private inputs; the robot image holds at most " +
                                                      std::to_string(robot::kMaxBootInputs))};
  }
  const auto id = static_cast<size_t>(robot_id);
  std::vector<app::Parameter> own;
  for (const auto& [name, values] : scenario.inputs) {
    if (values.size() <= id) {
      return {std::nullopt, ScenarioError(scenario, "inputs." + name + " gives " + std::to_string(values.size()) +
                                                        " values; robot " + std::to_string(robot_id) +
                                                        " has none (one value per robot, in id order)")};
    }
    if (!std::isfinite(values[id])) {
      return {std::nullopt, ScenarioError(scenario, "inputs." + name + ": robot " + std::to_string(robot_id) +
                                                        "'s value " + SeventeenDigits(values[id]) +
                                                        " is not a finite number")};
    }
    if (name.size() > robot::kMaxBootInputNameBytes) {
      return {std::nullopt, ScenarioError(scenario, "inputs." + name + ": the name takes " +
                                                        std::to_string(name.size()) +
                                                        " bytes; the robot image takes at most " +
                                                        std::to_string(robot::kMaxBootInputNameBytes))};
    }
    own.push_back(app::Parameter{name, values[id]});
  }
  RobotBlock block;
  block.robot_id = static_cast<uint16_t>(robot_id);
  block.swarm_size = static_cast<uint16_t>(robots);
  block.scenario_id = ScenarioId(scenario);
  block.inputs = own.size();
  block.kind = scenario.robots[id].kind;
  for (const lab::scenario::RobotSpec& spec : scenario.robots) {
    block.swarm_kinds = static_cast<robot::KindSet>(block.swarm_kinds | robot::KindBit(spec.kind));
  }
  std::vector<motion::RobotKind> member_kinds;
  for (const lab::scenario::RobotSpec& spec : scenario.robots) member_kinds.push_back(spec.kind);
  const robot::ConfigBlockContent content{.robot_id = block.robot_id,
                                          .swarm_size = block.swarm_size,
                                          .scenario_id = block.scenario_id,
                                          .inputs = own,
                                          .kind = block.kind,
                                          .swarm_kinds = block.swarm_kinds,
                                          .member_kinds = member_kinds};
  switch (robot::EncodeConfigBlock(content, block.bytes, block.words_length)) {
    case robot::ConfigBlockError::kOk: return {block, std::nullopt};
    case robot::ConfigBlockError::kDoesNotFit: {
      // The bytes the words would take, to say by how much.
      std::array<char, 8192> words{};
      size_t length = 0;
      (void)robot::FormatInputWords(block.robot_id, own, words, length);
      return {std::nullopt,
              ScenarioError(scenario, "inputs: robot " + std::to_string(robot_id) + "'s " +
                                          std::to_string(own.size()) + " inputs take " + std::to_string(length) +
                                          " bytes of words, with its id and swarm more than the " +
                                          std::to_string(robot::kConfigBlockMaxWordsBytes) +
                                          " the configuration block holds (shorter input names fit)")};
    }
    case robot::ConfigBlockError::kNoSuchKind:
      return {std::nullopt, ScenarioError(scenario, "robot " + std::to_string(robot_id) + "'s kind " +
                                                        motion::ToString(block.kind) +
                                                        " cannot be told the robot image (it knows omni, rover and "
                                                        "drone)")};
    case robot::ConfigBlockError::kTooManyInputs:
    case robot::ConfigBlockError::kInvalidInput:
    case robot::ConfigBlockError::kRobotOutOfRange: break;
  }
  return {std::nullopt, ScenarioError(scenario, "inputs: the robot image cannot be told robot " +
                                                    std::to_string(robot_id) +
                                                    "'s inputs (a name a letter or _, then letters, digits and _)")};
}

std::optional<lab::Error> WriteBlock(ElfFile& image, const std::string& image_path, const RobotBlock& block) {
  const ElfSection* section = image.Find(robot::kConfigBlockSection);
  if (section == nullptr) {
    return lab::Error{.where = image_path,
                      .message = std::string("the image has no ") + robot::kConfigBlockSection +
                                 " section (the configuration block): build it from this tree (make firmware, or "
                                 "the M4 build's syrof-robot-mps2)"};
  }
  constexpr uint32_t kSectionProgbits = 1, kSectionAlloc = 2;
  if (section->type != kSectionProgbits || (section->flags & kSectionAlloc) == 0 || section->size != block.bytes.size()) {
    return lab::Error{.where = image_path,
                      .message = std::string("its ") + robot::kConfigBlockSection + " section is " +
                                 std::to_string(section->size) + " bytes" +
                                 (section->type != kSectionProgbits ? " without contents" : "") + "; the block is " +
                                 std::to_string(block.bytes.size()) + " bytes of flash"};
  }
  std::copy(block.bytes.begin(), block.bytes.end(), image.bytes.begin() + section->file_offset);
  return std::nullopt;
}

std::optional<lab::Error> WriteImage(const ElfFile& image, const std::string& path) {
  const bool hex = path.size() >= 4 && path.compare(path.size() - 4, 4, ".hex") == 0;
  if (!hex) return WriteFile(path, image.bytes);
  const std::vector<LoadChunk> chunks = image.LoadChunks();
  const std::string text =
      WriteIntelHex(chunks, image.entry != 0 ? std::optional<uint32_t>(image.entry) : std::nullopt);
  return WriteFile(path, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

}  // namespace syrof::firmware::config
