// libFuzzer target for the robot image's configuration block
// (firmware/robot config_block.h), the bytes a robot reads from its flash at
// boot.
//
// Input: any bytes. They are read three ways: as a whole block (mostly
// refused by its magic or checksum); as the words of a block whose header
// and checksum are made right for them, so the word parser sees them; and as
// the content of a block to encode (an id, a swarm size, a kind and the
// swarm's kinds, a few inputs), which must read back to the same values bit
// for bit. A block that is read as filled must describe a robot: an id
// below a swarm of 1 to 32, a kind the image knows among its swarm's kinds,
// finite inputs with names. Anything else stops the run.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "syrof/firmware/robot/config_block.h"

namespace {

namespace robot = syrof::firmware::robot;
using Block = std::array<uint8_t, robot::kConfigBlockBytes>;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void RequireARobot(const robot::BootConfigBlock& boot) {
  require(boot.swarm_size() >= 1 && boot.swarm_size() <= robot::kConfigBlockMaxSwarmSize);
  require(boot.robot_id() < boot.swarm_size());
  require(static_cast<size_t>(boot.kind()) < syrof::motion::kRobotKindCount);
  require((boot.swarm_kinds() & robot::KindBit(boot.kind())) != 0);
  require(boot.swarm_kinds() < (1u << syrof::motion::kRobotKindCount));
  for (const syrof::app::Parameter& input : boot.inputs()) {
    require(!input.name.empty() && std::isfinite(input.value));
  }
}

void ReadAsBlock(const Block& block) {
  robot::BootConfigBlock boot;
  const robot::ConfigBlockState state = boot.Read(block);
  if (state == robot::ConfigBlockState::kFilled) RequireARobot(boot);
  if (state == robot::ConfigBlockState::kRefused) require(std::strlen(boot.error()) > 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // 1. The bytes as a whole block.
  Block raw{};
  std::memcpy(raw.data(), data, std::min(size, raw.size()));
  ReadAsBlock(raw);

  // 2. The bytes as words, with a header and checksum made right.
  Block words{};
  const size_t length = std::min(size, robot::kConfigBlockMaxWordsBytes);
  const uint32_t magic = robot::kConfigBlockMagic;
  for (int i = 0; i < 4; ++i) words[static_cast<size_t>(i)] = static_cast<uint8_t>(magic >> (8 * i));
  words[4] = static_cast<uint8_t>(robot::kConfigBlockVersion);
  words[6] = static_cast<uint8_t>(length);
  words[7] = static_cast<uint8_t>(length >> 8);
  std::memcpy(words.data() + robot::kConfigBlockHeaderBytes, data, length);
  const uint32_t checksum = robot::ConfigBlockChecksum(words, length);
  for (int i = 0; i < 4; ++i) words[16 + static_cast<size_t>(i)] = static_cast<uint8_t>(checksum >> (8 * i));
  ReadAsBlock(words);

  // 3. The bytes as content to encode: the first two say the id and the
  // swarm, then up to four inputs of a name length byte, the name, and 8
  // bytes of a double; the input's size says the kind (size % 4: 3 is no
  // kind) and the swarm's kinds ((size / 4) % 16: a bit mask, 8 none).
  if (size < 2) return 0;
  robot::ConfigBlockContent content;
  content.robot_id = data[0];
  content.swarm_size = data[1];
  content.scenario_id = size;
  content.kind = static_cast<syrof::motion::RobotKind>(size % 4);
  content.swarm_kinds = static_cast<robot::KindSet>((size / 4) % 16);
  std::vector<std::string> names;
  std::vector<syrof::app::Parameter> inputs;
  names.reserve(4);
  for (size_t at = 2; at < size && inputs.size() < 4;) {
    const size_t name_length = std::min<size_t>(data[at] % 70, size - at - 1);
    names.emplace_back(reinterpret_cast<const char*>(data + at + 1), name_length);
    at += 1 + name_length;
    double value = 0;
    if (at + 8 <= size) std::memcpy(&value, data + at, 8);
    at += 8;
    inputs.push_back({names.back(), value});
  }
  content.inputs = inputs;
  Block encoded{};
  size_t words_length = 0;
  if (robot::EncodeConfigBlock(content, encoded, words_length) != robot::ConfigBlockError::kOk) return 0;
  robot::BootConfigBlock boot;
  require(boot.Read(encoded) == robot::ConfigBlockState::kFilled);
  RequireARobot(boot);
  require(boot.robot_id() == content.robot_id && boot.swarm_size() == content.swarm_size);
  require(boot.scenario_id() == content.scenario_id);
  require(boot.kind() == content.kind);
  require(boot.swarm_kinds() == (content.swarm_kinds == 0 ? robot::KindBit(content.kind) : content.swarm_kinds));
  require(boot.inputs().size() == inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) {
    require(boot.inputs()[i].name == inputs[i].name);
    require(std::memcmp(&boot.inputs()[i].value, &inputs[i].value, 8) == 0);
  }
  return 0;
}
