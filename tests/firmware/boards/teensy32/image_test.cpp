// The Teensy 3.2 image `make firmware` builds (build-teensy/bin/syrof-robot.elf
// and .hex), read without the cross tools: what the chip reads at reset
// (vector table, flash configuration field), the entry point, and the HEX
// file teensy-loader-cli writes against the ELF's loadable bytes.
//
// The image comes from another build (the Teensy cross build), so the test
// finds it through SYROF_TEENSY_IMAGE_DIR (environment, else the source
// tree's build-teensy/bin). Without an image it skips, unless
// SYROF_REQUIRE_TEENSY_IMAGE is set (CI, after `make firmware`).
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "image_reader.h"

namespace syrof::board::teensy32::testing {
namespace {

constexpr uint32_t kFlashStart = 0x00000000, kFlashEnd = 0x00040000;  // 256 KB
constexpr uint32_t kRamStart = 0x1FFF8000, kRamEnd = 0x20008000;      // 64 KB
constexpr int kVectors = 111;
constexpr uint16_t kMachineArm = 40;

std::string ImageDir() {
  const char* dir = std::getenv("SYROF_TEENSY_IMAGE_DIR");
  return dir != nullptr && *dir != 0 ? dir : SYROF_SOURCE_DIR "/build-teensy/bin";
}

class Teensy32ImageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string elf_path = ImageDir() + "/syrof-robot.elf";
    std::vector<uint8_t> bytes;
    if (!ReadFile(elf_path, bytes)) {
      if (std::getenv("SYROF_REQUIRE_TEENSY_IMAGE") != nullptr) FAIL() << "no image " << elf_path;
      GTEST_SKIP() << "no image " << elf_path << " (run `make firmware`, or set SYROF_TEENSY_IMAGE_DIR)";
    }
    std::string error;
    ASSERT_TRUE(ParseElf32(bytes, elf_, error)) << elf_path << ": " << error;
    std::vector<uint8_t> hex_bytes;
    ASSERT_TRUE(ReadFile(ImageDir() + "/syrof-robot.hex", hex_bytes)) << "no " << ImageDir() << "/syrof-robot.hex";
    ASSERT_TRUE(ParseIntelHex(std::string(hex_bytes.begin(), hex_bytes.end()), hex_, error))
        << ImageDir() << "/syrof-robot.hex: " << error;
  }

  // The little-endian word the chip reads at `address`; fails the test if
  // the image does not define all four bytes.
  uint32_t Word(uint32_t address) {
    uint32_t value = 0;
    for (uint32_t i = 0; i < 4; ++i) {
      const auto byte = elf_.loadable.find(address + i);
      EXPECT_NE(byte, elf_.loadable.end()) << "no byte at 0x" << std::hex << address + i;
      if (byte != elf_.loadable.end()) value |= static_cast<uint32_t>(byte->second) << (8 * i);
    }
    return value;
  }

  uint32_t Symbol(const std::string& name) {
    const auto found = elf_.symbols.find(name);
    EXPECT_NE(found, elf_.symbols.end()) << "no symbol " << name;
    return found == elf_.symbols.end() ? 0 : found->second;
  }

  ElfImage elf_;
  HexImage hex_;
};

TEST_F(Teensy32ImageTest, IsAnArmElf) { EXPECT_EQ(elf_.machine, kMachineArm); }

TEST_F(Teensy32ImageTest, VectorTableAtZeroStartsWithStackPointerAndResetHandler) {
  EXPECT_EQ(Symbol("vector_table"), 0u);
  const uint32_t stack_pointer = Word(0);
  EXPECT_GT(stack_pointer, kRamStart);
  EXPECT_LE(stack_pointer, kRamEnd);
  EXPECT_EQ(stack_pointer % 8, 0u) << "AAPCS wants an 8-byte aligned stack";
  EXPECT_EQ(stack_pointer, Symbol("__stack_top"));

  const uint32_t reset = Word(4);
  EXPECT_EQ(reset & 1u, 1u) << "the reset vector must have the Thumb bit";
  EXPECT_GE(reset & ~1u, kFlashStart);
  EXPECT_LT(reset & ~1u, kFlashEnd);
  EXPECT_EQ(reset & ~1u, Symbol("reset_handler") & ~1u);
}

TEST_F(Teensy32ImageTest, EveryVectorIsAThumbAddressInFlash) {
  for (int vector = 1; vector < kVectors; ++vector) {
    const uint32_t handler = Word(4u * static_cast<uint32_t>(vector));
    EXPECT_EQ(handler & 1u, 1u) << "vector " << vector;
    EXPECT_LT(handler & ~1u, kFlashEnd) << "vector " << vector;
    EXPECT_GE(handler & ~1u, 0x410u) << "vector " << vector << " points into the vector table or flash configuration";
  }
}

TEST_F(Teensy32ImageTest, SysTickAndUartInterruptsReachTheirHandlers) {
  // Vector 15 is SysTick; the MK20DX256's interrupt 45 is UART0's status
  // (the radio link), 49 UART2's (the console): vectors 61 and 65.
  EXPECT_EQ(Word(4 * 15) & ~1u, Symbol("systick_handler") & ~1u);
  EXPECT_EQ(Word(4 * (16 + 45)) & ~1u, Symbol("uart0_status_handler") & ~1u);
  EXPECT_EQ(Word(4 * (16 + 49)) & ~1u, Symbol("uart2_status_handler") & ~1u);
  EXPECT_EQ(Word(4 * 3) & ~1u, Symbol("fault_handler") & ~1u);  // HardFault
}

TEST_F(Teensy32ImageTest, KernelInterruptsReachTheKernelsHandlers) {
  // The firmware kernel's levels are DMA channels 0-9's interrupts (vectors
  // 16-25) and its alarm PIT channel 0's (interrupt 68, vector 84): the
  // kernel's handlers, not the board's weak defaults, which would all be one
  // address (unrouted_interrupt_handler).
  std::set<uint32_t> level_handlers;
  for (int channel = 0; channel < 10; ++channel) {
    const std::string name = "dma_channel" + std::to_string(channel) + "_handler";
    EXPECT_EQ(Word(4 * (16 + channel)) & ~1u, Symbol(name) & ~1u) << name;
    level_handlers.insert(Word(4 * (16 + channel)) & ~1u);
  }
  EXPECT_EQ(level_handlers.size(), 10u) << "a level's vector is the weak default";
  EXPECT_EQ(Word(4 * (16 + 68)) & ~1u, Symbol("pit0_handler") & ~1u);
  EXPECT_EQ(level_handlers.count(Symbol("pit0_handler") & ~1u), 0u);
}

TEST_F(Teensy32ImageTest, FlashConfigurationFieldHoldsExactlyTheUnsecuredBytes) {
  // Backdoor key, FPROT0-3 (no protection), FSEC 0xDE (unsecured; another
  // value can lock the chip), FOPT 0xF9, FEPROT, FDPROT.
  constexpr std::array<uint8_t, 16> kExpected{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                              0xFF, 0xFF, 0xFF, 0xFF, 0xDE, 0xF9, 0xFF, 0xFF};
  for (uint32_t i = 0; i < kExpected.size(); ++i) {
    const auto byte = elf_.loadable.find(0x400 + i);
    ASSERT_NE(byte, elf_.loadable.end()) << "no byte at 0x" << std::hex << 0x400 + i;
    EXPECT_EQ(byte->second, kExpected[i]) << "at 0x" << std::hex << 0x400 + i;
  }
}

TEST_F(Teensy32ImageTest, EntryPointIsTheResetHandler) {
  EXPECT_EQ(elf_.entry, Word(4));
  EXPECT_EQ(elf_.entry & ~1u, Symbol("reset_handler") & ~1u);
}

TEST_F(Teensy32ImageTest, EverythingLoadableIsInFlash) {
  ASSERT_FALSE(elf_.loadable.empty());
  EXPECT_EQ(elf_.loadable.begin()->first, kFlashStart);
  EXPECT_LT(elf_.loadable.rbegin()->first, kFlashEnd);
}

TEST_F(Teensy32ImageTest, HexFileHoldsExactlyTheElfsLoadableBytes) {
  EXPECT_EQ(hex_.data.size(), elf_.loadable.size());
  size_t mismatches = 0;
  for (const auto& [address, byte] : elf_.loadable) {
    const auto in_hex = hex_.data.find(address);
    if (in_hex == hex_.data.end() || in_hex->second != byte) {
      if (++mismatches <= 5) ADD_FAILURE() << "HEX differs from the ELF at 0x" << std::hex << address;
    }
  }
  EXPECT_EQ(mismatches, 0u);
  if (hex_.has_start_address) {
    EXPECT_EQ(hex_.start_address, elf_.entry);
  }
}

// The readers themselves, on small inputs with known answers.
TEST(IntelHexReaderTest, ReadsDataAndExtendedAddresses) {
  const std::string text =
      ":020000040001F9\n"  // base 0x00010000
      ":0400100001020304E2\n"
      ":00000001FF\n";
  HexImage image;
  std::string error;
  ASSERT_TRUE(ParseIntelHex(text, image, error)) << error;
  ASSERT_EQ(image.data.size(), 4u);
  EXPECT_EQ(image.data.at(0x00010010), 0x01);
  EXPECT_EQ(image.data.at(0x00010013), 0x04);
}

TEST(IntelHexReaderTest, RefusesABadChecksumNamingTheLine) {
  HexImage image;
  std::string error;
  EXPECT_FALSE(ParseIntelHex(":0400100001020304E3\n:00000001FF\n", image, error));
  EXPECT_EQ(error, "line 1: checksum mismatch");
}

TEST(IntelHexReaderTest, RefusesAMissingEndRecord) {
  HexImage image;
  std::string error;
  EXPECT_FALSE(ParseIntelHex(":0400100001020304E2\n", image, error));
  EXPECT_EQ(error, "no end-of-file record");
}

TEST(ElfReaderTest, RefusesWhatIsNotElf) {
  ElfImage image;
  std::string error;
  EXPECT_FALSE(ParseElf32(std::vector<uint8_t>(64, 0), image, error));
  EXPECT_EQ(error, "not an ELF file");
}

}  // namespace
}  // namespace syrof::board::teensy32::testing
