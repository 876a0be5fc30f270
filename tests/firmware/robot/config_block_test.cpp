// The configuration block (firmware/robot config_block.h): what
// syrof-firmware-config encodes reads back on the image into the same id,
// swarm size, scenario id, kinds and inputs, bit for bit; the kinds are the
// words the emulated swarm's host writes on a boot line (FormatKindWords); the layout is the
// documented one; and a block that is damaged, not of this format, or whose
// words do not make a robot is refused with a line naming why.
#include "syrof/firmware/robot/config_block.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace syrof::firmware::robot {
namespace {

using Block = std::array<uint8_t, kConfigBlockBytes>;

// CRC-32 written out here from its definition (reflected polynomial
// 0xEDB88320, initial and final XOR 0xFFFFFFFF), table-driven, to check the
// block's own bit-by-bit one.
uint32_t ReferenceCrc32(const std::vector<uint8_t>& bytes) {
  std::array<uint32_t, 256> table{};
  for (uint32_t n = 0; n < 256; ++n) {
    uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1) != 0 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[n] = c;
  }
  uint32_t crc = 0xFFFFFFFFu;
  for (const uint8_t byte : bytes) crc = table[(crc ^ byte) & 0xff] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

uint64_t Le(const Block& block, size_t offset, size_t bytes) {
  uint64_t value = 0;
  for (size_t i = 0; i < bytes; ++i) value |= uint64_t{block[offset + i]} << (8 * i);
  return value;
}

void PutLe(Block& block, size_t offset, uint64_t value, size_t bytes) {
  for (size_t i = 0; i < bytes; ++i) block[offset + i] = static_cast<uint8_t>(value >> (8 * i));
}

// A block holding `words` as given, with a header that is right for them
// (or `version`), and the checksum they give: what a damaged or hand-made
// block looks like once its checksum is right.
Block HandMade(const std::string& words, uint16_t version = kConfigBlockVersion) {
  Block block{};
  PutLe(block, 0, kConfigBlockMagic, 4);
  PutLe(block, 4, version, 2);
  PutLe(block, 6, words.size(), 2);
  PutLe(block, 8, 0x0123456789abcdefull, 8);
  std::memcpy(block.data() + kConfigBlockHeaderBytes, words.data(), words.size());
  PutLe(block, 16, ConfigBlockChecksum(block, words.size()), 4);
  return block;
}

std::string Refusal(const Block& block) {
  BootConfigBlock boot;
  EXPECT_EQ(boot.Read(block), ConfigBlockState::kRefused);
  return boot.error();
}

TEST(ConfigBlockTest, AnEncodedBlockReadsBackBitForBit) {
  const double third = 1.0 / 3.0;
  const std::vector<app::Parameter> inputs = {{"charge", 866}, {"key", 0.3}, {"third", third}, {"_tiny", 5e-324},
                                              {"big", -1.7976931348623157e308}};
  Block block{};
  size_t length = 0;
  ASSERT_EQ(EncodeConfigBlock({2, 4, 0xfedcba9876543210ull, inputs}, block, length), ConfigBlockError::kOk);
  BootConfigBlock boot;
  ASSERT_EQ(boot.Read(block), ConfigBlockState::kFilled) << boot.error();
  EXPECT_EQ(boot.robot_id(), 2);
  EXPECT_EQ(boot.swarm_size(), 4);
  EXPECT_EQ(boot.scenario_id(), 0xfedcba9876543210ull);
  ASSERT_EQ(boot.inputs().size(), inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) {
    EXPECT_EQ(boot.inputs()[i].name, inputs[i].name);
    // Bit for bit, not just close.
    uint64_t want = 0, got = 0;
    std::memcpy(&want, &inputs[i].value, 8);
    std::memcpy(&got, &boot.inputs()[i].value, 8);
    EXPECT_EQ(got, want) << inputs[i].name;
  }
}

TEST(ConfigBlockTest, TheLayoutIsTheDocumentedOne) {
  const std::vector<app::Parameter> inputs = {{"charge", 734}};
  Block block{};
  size_t length = 0;
  ASSERT_EQ(EncodeConfigBlock({1, 3, 0x1122334455667788ull, inputs}, block, length), ConfigBlockError::kOk);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(block.data()), 4), "SYCF");
  EXPECT_EQ(Le(block, 4, 2), 1u);
  const std::string words = "id 1 swarm 3 inputs 1:1 input charge=734";
  EXPECT_EQ(length, words.size());
  EXPECT_EQ(Le(block, 6, 2), words.size());
  EXPECT_EQ(Le(block, 8, 8), 0x1122334455667788ull);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(block.data() + 20)), words);
  std::vector<uint8_t> covered(block.begin(), block.begin() + 16);
  covered.insert(covered.end(), block.begin() + 20, block.begin() + 20 + static_cast<long>(words.size()));
  EXPECT_EQ(Le(block, 16, 4), ReferenceCrc32(covered));
  for (size_t i = 20 + words.size(); i < block.size(); ++i) ASSERT_EQ(block[i], 0) << "byte " << i;
}

TEST(ConfigBlockTest, TheChecksumIsCrc32) {
  // The standard check value: CRC-32 of "123456789" is 0xCBF43926.
  const std::string check = "123456789";
  EXPECT_EQ(ReferenceCrc32(std::vector<uint8_t>(check.begin(), check.end())), 0xCBF43926u);
  Block block{};
  std::memcpy(block.data() + kConfigBlockHeaderBytes, check.data(), check.size());
  std::vector<uint8_t> covered(16, 0);
  covered.insert(covered.end(), check.begin(), check.end());
  EXPECT_EQ(ConfigBlockChecksum(block, check.size()), ReferenceCrc32(covered));
}

TEST(ConfigBlockTest, ARobotWithoutInputsGetsOnlyItsIdAndSwarm) {
  Block block{};
  size_t length = 0;
  ASSERT_EQ(EncodeConfigBlock({0, 1, 7, {}}, block, length), ConfigBlockError::kOk);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(block.data() + 20)), "id 0 swarm 1");
  BootConfigBlock boot;
  ASSERT_EQ(boot.Read(block), ConfigBlockState::kFilled) << boot.error();
  EXPECT_TRUE(boot.inputs().empty());
}

TEST(ConfigBlockTest, AllZerosIsEmpty) {
  BootConfigBlock boot;
  EXPECT_EQ(boot.Read(Block{}), ConfigBlockState::kEmpty);
  EXPECT_EQ(boot.robot_id(), 0);
  EXPECT_TRUE(boot.inputs().empty());
}

TEST(ConfigBlockTest, ADamagedBlockIsRefusedByWhatIsWrong) {
  Block block{};
  size_t length = 0;
  const std::vector<app::Parameter> inputs = {{"charge", 734}};
  ASSERT_EQ(EncodeConfigBlock({1, 3, 5, inputs}, block, length), ConfigBlockError::kOk);

  Block flipped = block;
  flipped[kConfigBlockHeaderBytes + 3] ^= 0x01;  // "id 1" -> "id 0": words the checksum does not match
  EXPECT_NE(Refusal(flipped).find("the configuration block's checksum is 0x"), std::string::npos);
  EXPECT_NE(Refusal(flipped).find("(the block is damaged: write it again)"), std::string::npos);

  Block stray{};
  stray[700] = 0xff;  // not all zeros, no magic
  EXPECT_EQ(Refusal(stray), "the configuration block is not empty and its magic is 0x00000000, not 0x46435953 "
                            "(damaged, or not written by syrof-firmware-config)");

  Block version = block;
  PutLe(version, 4, 2, 2);
  EXPECT_EQ(Refusal(version), "the configuration block is format version 2; this image reads version 1 (write it "
                              "again with this image's syrof-firmware-config)");

  Block long_words = block;
  PutLe(long_words, 6, 1004, 2);
  EXPECT_EQ(Refusal(long_words), "the configuration block's words take 1004 bytes; at most 1003 fit");

  Block after_words = block;
  after_words[1000] = 1;  // past the words, where the checksum does not look
  EXPECT_EQ(Refusal(after_words), "the configuration block's byte 1000, after its words, is 0x01, not 0 (the block "
                                  "is damaged: write it again)");
}

TEST(ConfigBlockTest, WordsThatMakeNoRobotAreRefusedByName) {
  EXPECT_EQ(Refusal(HandMade("id 2 swarm 4 inputs 1:1 input charge=3")),
            "the configuration block: the inputs were written for robot 1; this is robot 2");
  EXPECT_EQ(Refusal(HandMade("id 2 swarm 4 inputs 2:2 input charge=3")),
            "the configuration block: inputs 2:2 announced 2 inputs; 1 came (an input is missing)");
  EXPECT_EQ(Refusal(HandMade("id 2 swarm 4 inputs 2:1 input charge=nan")),
            "the configuration block's word 8 'input': 'charge=nan' is not a value it takes (inputs ID:N first, then "
            "N input NAME=VALUE, each name once, each value a finite number)");
  EXPECT_EQ(Refusal(HandMade("id 2 swarm 4 colour 3")),
            "the configuration block's word 5: unknown key 'colour' (id, swarm, kind, swarm_kinds, member_kinds, inputs, input)");
  EXPECT_EQ(Refusal(HandMade("id 2")), "the configuration block gives no swarm");
  EXPECT_EQ(Refusal(HandMade("swarm 4")), "the configuration block gives no id");
  EXPECT_EQ(Refusal(HandMade("id 4 swarm 4")), "the configuration block's id 4 is not below its swarm 4");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 4 id 2")),
            "the configuration block's word 6 'id': '2' is not a value it takes (id 0..31, swarm 1..32, each once)");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 0")),
            "the configuration block's word 4 'swarm': '0' is not a value it takes (id 0..31, swarm 1..32, each once)");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm")), "the configuration block's word 3 'swarm' has no value");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 4 ")), "the configuration block's words end with a space");
  EXPECT_EQ(Refusal(HandMade("id 1  swarm 4")),
            "the configuration block's word 3 is empty (two spaces, or a space at an end)");
  EXPECT_EQ(Refusal(HandMade(std::string("id 1 swarm 4\tx 1"))),
            "the configuration block's word 4 holds the byte 0x09 (printable words only)");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 4", 0)),
            "the configuration block is format version 0; this image reads version 1 (write it again with this "
            "image's syrof-firmware-config)");
}

TEST(ConfigBlockTest, WhatTheBlockCannotHoldIsNotEncoded) {
  Block block{};
  size_t length = 0;
  EXPECT_EQ(EncodeConfigBlock({4, 4, 0, {}}, block, length), ConfigBlockError::kRobotOutOfRange);
  EXPECT_EQ(EncodeConfigBlock({0, 0, 0, {}}, block, length), ConfigBlockError::kRobotOutOfRange);
  EXPECT_EQ(EncodeConfigBlock({0, 33, 0, {}}, block, length), ConfigBlockError::kRobotOutOfRange);
  const std::vector<app::Parameter> infinite = {{"charge", std::numeric_limits<double>::infinity()}};
  EXPECT_EQ(EncodeConfigBlock({0, 4, 0, infinite}, block, length), ConfigBlockError::kInvalidInput);
  const std::vector<app::Parameter> bad_name = {{"2charge", 1}};
  EXPECT_EQ(EncodeConfigBlock({0, 4, 0, bad_name}, block, length), ConfigBlockError::kInvalidInput);
  // Sixteen inputs with 63-byte names and 17-digit values: 1,500 bytes of words.
  std::vector<std::string> names;
  for (int i = 0; i < 16; ++i) names.push_back("input_" + std::to_string(10 + i) + std::string(55, 'x'));
  std::vector<app::Parameter> long_inputs;
  for (const std::string& name : names) long_inputs.push_back({name, 1.0 / 3.0});
  EXPECT_EQ(EncodeConfigBlock({0, 4, 0, long_inputs}, block, length), ConfigBlockError::kDoesNotFit);
  EXPECT_EQ(length, 0u);
  for (const uint8_t byte : block) ASSERT_EQ(byte, 0);  // nothing half-written
  long_inputs.push_back({"one_more", 1});
  EXPECT_EQ(EncodeConfigBlock({0, 4, 0, long_inputs}, block, length), ConfigBlockError::kTooManyInputs);
}

constexpr KindSet kOmniKinds = KindBit(motion::RobotKind::kOmni);
constexpr KindSet kRoverKinds = KindBit(motion::RobotKind::kRover);
constexpr KindSet kDroneKinds = KindBit(motion::RobotKind::kDrone);

std::string BlockWords(const Block& block) { return reinterpret_cast<const char*>(block.data() + kConfigBlockHeaderBytes); }

TEST(ConfigBlockTest, ADronesBlockCarriesTheKindWordsTheSwarmHostWrites) {
  const std::vector<app::Parameter> inputs = {{"charge", 791}};
  const std::vector<motion::RobotKind> members = {motion::RobotKind::kOmni, motion::RobotKind::kOmni,
                                                  motion::RobotKind::kDrone, motion::RobotKind::kOmni};
  Block block{};
  size_t length = 0;
  ASSERT_EQ(EncodeConfigBlock({.robot_id = 2,
                               .swarm_size = 4,
                               .scenario_id = 9,
                               .inputs = inputs,
                               .kind = motion::RobotKind::kDrone,
                               .swarm_kinds = static_cast<KindSet>(kOmniKinds | kDroneKinds),
                               .member_kinds = members},
                              block, length),
            ConfigBlockError::kOk);
  // The same words as the host's boot line: FormatKindWords, then the inputs'.
  std::array<char, 128> kinds{};
  size_t kinds_length = 0;
  ASSERT_EQ(FormatKindWords(motion::RobotKind::kDrone, kOmniKinds | kDroneKinds, members, kinds, kinds_length),
            BootWordsError::kOk);
  EXPECT_EQ(std::string(kinds.data(), kinds_length), " kind drone swarm_kinds omni,drone member_kinds oodo");
  EXPECT_EQ(BlockWords(block),
            "id 2 swarm 4 kind drone swarm_kinds omni,drone member_kinds oodo inputs 2:1 input charge=791");
  BootConfigBlock boot;
  ASSERT_EQ(boot.Read(block), ConfigBlockState::kFilled) << boot.error();
  EXPECT_EQ(boot.kind(), motion::RobotKind::kDrone);
  EXPECT_EQ(boot.swarm_kinds(), kOmniKinds | kDroneKinds);
  EXPECT_EQ(std::vector<motion::RobotKind>(boot.member_kinds().begin(), boot.member_kinds().end()), members);
  EXPECT_EQ(boot.robot_id(), 2);
  ASSERT_EQ(boot.inputs().size(), 1u);
  EXPECT_EQ(boot.inputs()[0].value, 791);
}

TEST(ConfigBlockTest, EveryKindInEverySwarmOfItReadsBack) {
  for (size_t k = 0; k < motion::kRobotKindCount; ++k) {
    const auto kind = static_cast<motion::RobotKind>(k);
    for (unsigned swarm = 1; swarm < (1u << motion::kRobotKindCount); ++swarm) {
      if ((swarm & KindBit(kind)) == 0) continue;
      // One robot of each kind, this one first.
      std::vector<motion::RobotKind> members = {kind};
      for (size_t other = 0; other < motion::kRobotKindCount; ++other) {
        if (other != k && (swarm & KindBit(static_cast<motion::RobotKind>(other))) != 0) {
          members.push_back(static_cast<motion::RobotKind>(other));
        }
      }
      Block block{};
      size_t length = 0;
      ASSERT_EQ(EncodeConfigBlock({.robot_id = 0,
                                   .swarm_size = static_cast<uint16_t>(members.size()),
                                   .scenario_id = 1,
                                   .inputs = {},
                                   .kind = kind,
                                   .swarm_kinds = static_cast<KindSet>(swarm),
                                   .member_kinds = members},
                                  block, length),
                ConfigBlockError::kOk);
      BootConfigBlock boot;
      ASSERT_EQ(boot.Read(block), ConfigBlockState::kFilled) << boot.error();
      EXPECT_EQ(boot.kind(), kind) << BlockWords(block);
      EXPECT_EQ(boot.swarm_kinds(), swarm) << BlockWords(block);
    }
  }
  // An omni robot among omni robots has no kind words (the block before the
  // kinds); a rover among rovers only its own; swarm_kinds 0 is its own alone.
  Block block{};
  size_t length = 0;
  ASSERT_EQ(EncodeConfigBlock({.robot_id = 0, .swarm_size = 2, .scenario_id = 1, .swarm_kinds = kOmniKinds}, block, length),
            ConfigBlockError::kOk);
  EXPECT_EQ(BlockWords(block), "id 0 swarm 2");
  ASSERT_EQ(EncodeConfigBlock({.robot_id = 0, .swarm_size = 2, .scenario_id = 1, .kind = motion::RobotKind::kRover},
                              block, length),
            ConfigBlockError::kOk);
  EXPECT_EQ(BlockWords(block), "id 0 swarm 2 kind rover");
  BootConfigBlock boot;
  ASSERT_EQ(boot.Read(block), ConfigBlockState::kFilled) << boot.error();
  EXPECT_EQ(boot.swarm_kinds(), kRoverKinds);
  BootConfigBlock no_kind;
  ASSERT_EQ(no_kind.Read(HandMade("id 1 swarm 4")), ConfigBlockState::kFilled) << no_kind.error();
  EXPECT_EQ(no_kind.kind(), motion::RobotKind::kOmni);
  EXPECT_EQ(no_kind.swarm_kinds(), kOmniKinds);
}

TEST(ConfigBlockTest, AMixedSwarmsBlockWithoutEveryRobotsKindIsRefusedByName) {
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 4 kind drone swarm_kinds omni,drone")),
            "the configuration block names a swarm of more than one kind and no member_kinds (write it again with "
            "this image's syrof-firmware-config)");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 4 kind drone swarm_kinds omni,drone member_kinds odo")),
            "the configuration block's member_kinds names 3 robots; its swarm has 4");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 4 kind drone swarm_kinds omni,drone member_kinds oodo")),
            "the configuration block's member_kinds gives robot 1 the kind omni; its kind word says drone");
  EXPECT_EQ(Refusal(HandMade("id 1 swarm 4 kind drone swarm_kinds omni,drone member_kinds odxo")),
            "the configuration block's word 10 'member_kinds': 'odxo' is not a value it takes (a robot kind this "
            "image knows: omni, rover or drone; swarm_kinds lists them, each once; member_kinds a letter o, r or d "
            "for each robot; each word once)");
  BootConfigBlock good;
  ASSERT_EQ(good.Read(HandMade("id 1 swarm 4 kind drone swarm_kinds omni,drone member_kinds odoo")),
            ConfigBlockState::kFilled)
      << good.error();
  ASSERT_EQ(good.member_kinds().size(), 4u);
  EXPECT_EQ(good.member_kinds()[1], motion::RobotKind::kDrone);
  // The encoder refuses what the image would.
  Block block{};
  size_t length = 0;
  const std::vector<motion::RobotKind> three = {motion::RobotKind::kOmni, motion::RobotKind::kDrone,
                                                motion::RobotKind::kOmni};
  EXPECT_EQ(EncodeConfigBlock({.robot_id = 1,
                               .swarm_size = 4,
                               .scenario_id = 1,
                               .kind = motion::RobotKind::kDrone,
                               .swarm_kinds = static_cast<KindSet>(kOmniKinds | kDroneKinds),
                               .member_kinds = three},
                              block, length),
            ConfigBlockError::kNoSuchKind);
  EXPECT_EQ(EncodeConfigBlock({.robot_id = 1,
                               .swarm_size = 4,
                               .scenario_id = 1,
                               .kind = motion::RobotKind::kDrone,
                               .swarm_kinds = static_cast<KindSet>(kOmniKinds | kDroneKinds)},
                              block, length),
            ConfigBlockError::kNoSuchKind);
}

TEST(ConfigBlockTest, AKindTheImageDoesNotKnowIsRefusedByName) {
  EXPECT_EQ(Refusal(HandMade("id 0 swarm 4 kind tank")),
            "the configuration block's word 6 'kind': 'tank' is not a value it takes (a robot kind this image knows: "
            "omni, rover or drone; swarm_kinds lists them, each once; member_kinds a letter o, r or d for each robot; each "
            "word once)");
  EXPECT_EQ(Refusal(HandMade("id 0 swarm 4 kind drone swarm_kinds omni,tank")),
            "the configuration block's word 8 'swarm_kinds': 'omni,tank' is not a value it takes (a robot kind this "
            "image knows: omni, rover or drone; swarm_kinds lists them, each once; member_kinds a letter o, r or d for each robot; each "
            "word once)");
  EXPECT_EQ(Refusal(HandMade("id 0 swarm 4 kind drone swarm_kinds drone,drone")),
            "the configuration block's word 8 'swarm_kinds': 'drone,drone' is not a value it takes (a robot kind "
            "this image knows: omni, rover or drone; swarm_kinds lists them, each once; member_kinds a letter o, r or d for each robot; each "
            "word once)");
  EXPECT_EQ(Refusal(HandMade("id 0 swarm 4 kind drone kind rover")),
            "the configuration block's word 8 'kind': 'rover' is not a value it takes (a robot kind this image "
            "knows: omni, rover or drone; swarm_kinds lists them, each once; member_kinds a letter o, r or d for each robot; each "
            "word once)");
  EXPECT_EQ(Refusal(HandMade("id 0 swarm 4 kind drone swarm_kinds omni,rover")),
            "the configuration block: kind drone is not among its swarm_kinds (a robot is of its swarm)");
  // And the encoder writes none of these.
  Block block{};
  size_t length = 0;
  EXPECT_EQ(EncodeConfigBlock({.robot_id = 0,
                               .swarm_size = 4,
                               .scenario_id = 1,
                               .kind = motion::RobotKind::kDrone,
                               .swarm_kinds = static_cast<KindSet>(kOmniKinds | kRoverKinds)},
                              block, length),
            ConfigBlockError::kNoSuchKind);
  EXPECT_EQ(EncodeConfigBlock({.robot_id = 0, .swarm_size = 4, .scenario_id = 1, .kind = motion::RobotKind{7}}, block,
                              length),
            ConfigBlockError::kNoSuchKind);
  EXPECT_EQ(EncodeConfigBlock({.robot_id = 0, .swarm_size = 4, .scenario_id = 1, .swarm_kinds = 0x80}, block, length),
            ConfigBlockError::kNoSuchKind);
  for (const uint8_t byte : block) ASSERT_EQ(byte, 0);  // nothing half-written
}

TEST(ConfigBlockTest, AScenarioIdPrintsAsSixteenHexDigits) {
  std::array<char, 17> text{};
  FormatScenarioId(0x00a1b2c3d4e5f607ull, text);
  EXPECT_STREQ(text.data(), "00a1b2c3d4e5f607");
}

}  // namespace
}  // namespace syrof::firmware::robot
