#include "syrof/wire/beacon_layout.h"

#include <gtest/gtest.h>

#include <array>
#include <string>

namespace syrof::wire {
namespace {

// One BLE legacy advertising payload (and so one nRF51822 advertisement).
constexpr size_t kBleLegacyAdvertisingBytes = 31;

static_assert(kMaxSwarmSize < 16 || EncodedSize(16) <= kBleLegacyAdvertisingBytes,
              "a beacon for 16 robots must fit one BLE legacy advertising payload");

std::string rendered_table(uint16_t swarm_size) {
  std::array<char, 4096> text{};
  const auto length = RenderLayoutTable(swarm_size, text);
  EXPECT_TRUE(length.ok()) << ToString(length.error());
  return length.ok() ? std::string(text.data(), length.value()) : std::string();
}

TEST(EncodedSizeTest, GrowsByOneByteEveryEightRobots) {
  struct Row {
    uint16_t swarm_size;
    size_t bytes;
  };
  const Row rows[] = {{1, 30},  {8, 30},   {9, 31},   {16, 31},  {17, 32},  {32, 33},   {48, 35},
                      {64, 37}, {128, 45}, {255, 61}, {256, 62}, {257, 64}, {1024, 159}};

  for (const Row& row : rows) {
    if (row.swarm_size > kMaxSwarmSize) continue;
    EXPECT_EQ(EncodedSize(row.swarm_size), row.bytes) << row.swarm_size;
  }
}

TEST(EncodedSizeTest, IsZeroForAnUnsupportedSwarmSize) {
  EXPECT_EQ(EncodedSize(0), 0u);
  if (kMaxSwarmSize < 65535) {
    EXPECT_EQ(EncodedSize(kMaxSwarmSize + 1), 0u);
  }
}

TEST(EncodedSizeTest, MaxBeaconBytesIsTheLargestSwarmsSize) {
  EXPECT_EQ(kMaxBeaconBytes, EncodedSize(kMaxSwarmSize));
}

TEST(RenderLayoutTableTest, ListsEveryFieldWithOffsetSizeAndRange) {
  const std::string table = rendered_table(32);

  EXPECT_EQ(table.rfind("| Offset | Size | Field | Meaning |\n| --- | --- | --- | --- |\n", 0), 0u);
  EXPECT_NE(table.find("| 0 | 1 byte | version | layout version; always 4 |\n"), std::string::npos);
  EXPECT_NE(table.find("| 1 | 1 byte | robot_id | sender's robot id; 0 to 31 |\n"),
            std::string::npos);
  EXPECT_NE(
      table.find(
          "| 4, bits 0-1 | 2 bits | phase | synchronizer phase; 0 PROGRESS, 1 WAIT, 2 VOTE |\n"),
      std::string::npos);
  EXPECT_NE(table.find("| 6 | 4 bytes | waiting |"), std::string::npos);
  EXPECT_NE(table.find("| 14 | 2 bytes | heading_mrad |"), std::string::npos);
  EXPECT_NE(table.find("-3142 to 3142 |\n"), std::string::npos);
  EXPECT_NE(table.find("| 20 | 9 bytes | payload |"), std::string::npos);
  EXPECT_NE(table.find("| 29 | 1 byte | relay |"), std::string::npos);
  EXPECT_NE(table.find("| bit 240 | 12 bits | relay_x |"), std::string::npos);
  EXPECT_NE(table.find("-2048 to 2047 |\n"), std::string::npos);
  EXPECT_NE(table.find("| | 33 bytes | total | for a swarm of 32 robots |\n"), std::string::npos);
}

TEST(RenderLayoutTableTest, ShowsTheWiderRobotIdAndPaddingOfLargeSwarms) {
  if (kMaxSwarmSize < 1001) {
    GTEST_SKIP() << "this build supports at most " << kMaxSwarmSize << " robots";
  }

  const std::string table = rendered_table(1001);

  EXPECT_NE(table.find("| 1 | 2 bytes | robot_id | sender's robot id; 0 to 1000 |\n"),
            std::string::npos);
  EXPECT_NE(table.find("for i from 0 to 1000, the other bits zero |\n"), std::string::npos);
  EXPECT_NE(table.find("relay | 0: nothing relayed; else 1 + the id of the robot whose position follows; 0 to 1001 |\n"),
            std::string::npos);
  EXPECT_NE(table.find("| | 157 bytes | total | for a swarm of 1001 robots |\n"),
            std::string::npos);
}

TEST(RenderLayoutTableTest, RejectsABufferTooSmallOrAnUnsupportedSwarm) {
  std::array<char, 64> text{};

  EXPECT_EQ(RenderLayoutTable(32, text).error(), WireError::kBufferTooSmall);
  EXPECT_EQ(RenderLayoutTable(0, text).error(), WireError::kSwarmSizeOutOfRange);
}

}  // namespace
}  // namespace syrof::wire
