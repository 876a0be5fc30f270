// The robot's report lines (firmware/robot/report_lines.h) read back by the
// swarm host's parser (firmware/swarm/console_lines.h): what one prints, the
// other understands, at the largest swarm.
#include "syrof/firmware/robot/report_lines.h"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <string_view>

#include "syrof/firmware/swarm/console_lines.h"

namespace syrof::firmware::robot {
namespace {

TEST(ReportLinesTest, RoundLineReadsBack) {
  sync::SyncState state;
  state.epoch = 513;
  state.epoch_mode = wire::Mode::kCooperative;
  state.phase = wire::Phase::kWait;
  std::array<char, 256> out{};
  const size_t length = FormatRoundLine(5, 12'345'678'901, state, true, -1.25f, 3.5f, 2, out);
  ASSERT_GT(length, 0u);
  ASSERT_EQ(out[length - 1], '\n');
  const swarm::ConsoleLine line = swarm::ParseConsoleLine(std::string_view(out.data(), length - 1), 8);
  const auto* round = std::get_if<swarm::RoundLine>(&line);
  ASSERT_NE(round, nullptr);
  EXPECT_EQ(round->t_ms, 12'345);
  EXPECT_EQ(round->robot, 5);
  EXPECT_EQ(round->epoch, 513);
  EXPECT_EQ(round->mode, wire::Mode::kCooperative);
  EXPECT_EQ(round->phase, wire::Phase::kWait);
  EXPECT_TRUE(round->member);
  EXPECT_DOUBLE_EQ(round->x_m, -1.25);
  EXPECT_DOUBLE_EQ(round->y_m, 3.5);
  EXPECT_EQ(round->epoch_lines_lost, 2u);
}

TEST(ReportLinesTest, EpochLineOfThirtyTwoMembersReadsBackWithTheSameKnowledge) {
  std::mt19937 random(20261126);
  std::uniform_int_distribution<int> coordinate(-32768, 32767);
  std::uniform_int_distribution<int> length_of(0, static_cast<int>(wire::kMaxPayloadBytes));
  std::uniform_int_distribution<int> byte_of(0, 255);
  sync::LDMap map;
  map.epoch = 65535;
  map.mode = wire::Mode::kCooperative;
  constexpr uint16_t kRobots = 32;  // the firmware's largest swarm (the host build allows more)
  for (uint16_t id = 0; id < kRobots; ++id) {
    map.members.set(id);
    wire::Snapshot& snapshot = map.snapshots[id];
    snapshot.x_mm = static_cast<int16_t>(coordinate(random));
    snapshot.y_mm = static_cast<int16_t>(coordinate(random));
    snapshot.heading_mrad = static_cast<int16_t>(coordinate(random) % 3142);
    snapshot.vx_mm_s = static_cast<int16_t>(coordinate(random));
    snapshot.vy_mm_s = static_cast<int16_t>(coordinate(random));
    std::array<uint8_t, wire::kMaxPayloadBytes> payload{};
    const auto payload_length = static_cast<size_t>(length_of(random));
    for (size_t i = 0; i < payload_length; ++i) payload[i] = static_cast<uint8_t>(byte_of(random));
    ASSERT_EQ(snapshot.SetPayload(std::span<const uint8_t>(payload.data(), payload_length)), wire::WireError::kOk);
  }
  std::array<char, 2048> out{};  // the mps2-an386 image's buffer
  const size_t length = FormatEpochLine(31, 7'000'000, map, /*active=*/false, out);
  ASSERT_GT(length, 0u) << "a 32-member line must fit the image's buffer";
  const swarm::ConsoleLine line = swarm::ParseConsoleLine(std::string_view(out.data(), length - 1), kRobots);
  const auto* epoch = std::get_if<swarm::EpochLine>(&line);
  ASSERT_NE(epoch, nullptr) << std::get<swarm::LineError>(line).what;
  EXPECT_EQ(epoch->robot, 31);
  EXPECT_EQ(epoch->t_ms, 7);
  EXPECT_FALSE(epoch->active);
  EXPECT_TRUE(epoch->map.SameKnowledge(map));
}

TEST(ReportLinesTest, TooSmallABufferWritesNothing) {
  sync::LDMap map;
  map.members.set(0);
  std::array<char, 40> out{};
  EXPECT_EQ(FormatEpochLine(0, 0, map, true, out), 0u);
  EXPECT_EQ(FormatRoundLine(0, 0, sync::SyncState{}, false, 0, 0, 0, std::span<char>(out.data(), 10)), 0u);
}

}  // namespace
}  // namespace syrof::firmware::robot
