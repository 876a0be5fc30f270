// syrof-firmware-config's ELF reading and Intel HEX writing
// (firmware/config elf_file.h, intel_hex.h): sections by name, each
// allocated section's bytes at its load address, the same bytes the
// Teensy board test's independent reader takes from the file
// (tests/firmware/boards/teensy32 image_reader.h), and HEX that reads back
// to them; damaged files refused by what is wrong.
#include "syrof/firmware/config/elf_file.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "image_reader.h"
#include "syrof/firmware/config/intel_hex.h"
#include "test_elf.h"

namespace syrof::firmware::config {
namespace {

using testing::MakeTestElf;
using testing::TestElfOptions;
namespace reader = syrof::board::teensy32::testing;

std::map<uint32_t, uint8_t> Memory(const std::vector<LoadChunk>& chunks) {
  std::map<uint32_t, uint8_t> memory;
  for (const LoadChunk& chunk : chunks) {
    for (size_t i = 0; i < chunk.bytes.size(); ++i) memory[chunk.address + static_cast<uint32_t>(i)] = chunk.bytes[i];
  }
  return memory;
}

TEST(ElfFileTest, SectionsAndTheirLoadAddresses) {
  const ElfOrError parsed = ParseElf(MakeTestElf(), "robot.elf");
  ASSERT_TRUE(parsed.ok()) << parsed.error->ToString();
  const ElfFile& elf = *parsed.elf;
  EXPECT_EQ(elf.machine, 40);
  EXPECT_EQ(elf.entry, 0x411u);
  const ElfSection* block = elf.Find(".syrof_config");
  ASSERT_NE(block, nullptr);
  EXPECT_EQ(block->address, 0x10u);
  EXPECT_EQ(block->load_address, 0x10u);
  EXPECT_EQ(block->size, 1024u);
  const ElfSection* data = elf.Find(".data");
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(data->address, 0x20000000u);
  EXPECT_EQ(data->load_address, 0x438u);  // flashed after the code, copied to RAM at start
  EXPECT_EQ(elf.Find(".nothing"), nullptr);
  const std::vector<LoadChunk> chunks = elf.LoadChunks();
  ASSERT_EQ(chunks.size(), 4u);  // vectors, block, text, data; not bss
  EXPECT_EQ(chunks[3].address, 0x438u);
  EXPECT_EQ(chunks[3].bytes, (std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(ElfFileTest, TheLoadBytesAreWhatAnotherReaderTakesFromTheFile) {
  const std::vector<uint8_t> bytes = MakeTestElf();
  reader::ElfImage other;
  std::string error;
  ASSERT_TRUE(reader::ParseElf32(bytes, other, error)) << error;
  const ElfOrError parsed = ParseElf(bytes, "robot.elf");
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(Memory(parsed.elf->LoadChunks()), other.loadable);
}

TEST(ElfFileTest, ItsIntelHexReadsBackToTheSameBytesAndEntry) {
  const ElfOrError parsed = ParseElf(MakeTestElf(), "robot.elf");
  ASSERT_TRUE(parsed.ok());
  const std::vector<LoadChunk> chunks = parsed.elf->LoadChunks();
  reader::HexImage hex;
  std::string error;
  ASSERT_TRUE(reader::ParseIntelHex(WriteIntelHex(chunks, parsed.elf->entry), hex, error)) << error;
  EXPECT_EQ(hex.data, Memory(chunks));
  EXPECT_TRUE(hex.has_start_address);
  EXPECT_EQ(hex.start_address, 0x411u);
}

TEST(ElfFileTest, DamagedFilesAreRefusedByWhatIsWrong) {
  EXPECT_EQ(ParseElf({1, 2, 3}, "x.elf").error->ToString(), "x.elf: not an ELF file (no \\x7fELF at its start)");
  std::vector<uint8_t> elf64 = MakeTestElf();
  elf64[4] = 2;
  EXPECT_EQ(ParseElf(elf64, "x.elf").error->ToString(),
            "x.elf: not a 32-bit little-endian ELF file (a robot image for the Cortex-M4 is one)");
  std::vector<uint8_t> cut = MakeTestElf();
  cut.resize(cut.size() - 10);  // the section header table runs past the end
  EXPECT_EQ(ParseElf(cut, "x.elf").error->ToString(),
            "x.elf: its section header table is missing or lies outside the file");
  std::vector<uint8_t> far = MakeTestElf();
  testing::Put32(far, 52 + 4, 0xfffffff0);  // the first segment's offset
  EXPECT_EQ(ParseElf(far, "x.elf").error->ToString(), "x.elf: program header 0 lies outside the file");
  EXPECT_EQ(ReadElfFile("/nonexistent/robot.elf").error->ToString(), "/nonexistent/robot.elf: cannot read the file");
}

TEST(IntelHexTest, RecordsAsTheFormatDefinesThem) {
  std::vector<uint8_t> bytes;
  for (uint8_t i = 0; i < 20; ++i) bytes.push_back(i);
  const std::vector<LoadChunk> chunks = {{0xfff8, bytes}};
  // The checksums worked out by hand: the two's complement of the bytes' sum.
  EXPECT_EQ(WriteIntelHex(chunks, 0x411),
            ":020000040000FA\r\n"
            ":08FFF8000001020304050607E5\r\n"  // up to the 64 KiB boundary, not across it
            ":020000040001F9\r\n"
            ":0C00000008090A0B0C0D0E0F1011121352\r\n"
            ":0400000300000411E4\r\n"
            ":00000001FF\r\n");
  EXPECT_EQ(WriteIntelHex({}, std::nullopt), ":00000001FF\r\n");
  const std::vector<LoadChunk> high = {{0x20000000, {0xaa}}};
  EXPECT_EQ(WriteIntelHex(high, 0x20000001),
            ":020000042000DA\r\n"
            ":01000000AA55\r\n"
            ":0400000520000001D6\r\n"
            ":00000001FF\r\n");
}

TEST(IntelHexTest, SixteenBytesARecord) {
  const std::vector<LoadChunk> chunks = {{0x400, std::vector<uint8_t>(40, 0x11)}};
  reader::HexImage hex;
  std::string error;
  const std::string text = WriteIntelHex(chunks, std::nullopt);
  ASSERT_TRUE(reader::ParseIntelHex(text, hex, error)) << error;
  EXPECT_EQ(hex.data.size(), 40u);
  EXPECT_NE(text.find(":10040000"), std::string::npos);
  EXPECT_NE(text.find(":10041000"), std::string::npos);
  EXPECT_NE(text.find(":08042000"), std::string::npos);
  EXPECT_FALSE(hex.has_start_address);
}

}  // namespace
}  // namespace syrof::firmware::config
