// A run of the size the format is meant for stays compact.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <vector>

#include "syrof/base/split_mix64.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/replay/writer.h"

namespace syrof::lab::replay {
namespace {

constexpr uint16_t kRobots = 1000;
constexpr uint32_t kRounds = 100;
constexpr size_t kTargetBytesPerFrame = 32;

float Jitter(base::SplitMix64& random) { return static_cast<float>(random.Between(-1000, 1000)) * 1e-5f; }

// Every robot moves and re-estimates every round (each pose field changes),
// the worst case for the unchanged-field encoding; epochs change every 20 rounds.
TEST(ReplaySize, ThousandRobotsHundredRoundsStayUnderTarget) {
  Header header;
  header.seed = 7;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 40;
  header.arena_height_m = 40;
  header.scenario_name = "size";
  header.app_name = "builtin:idle";
  for (uint16_t id = 0; id < kRobots; ++id) header.robots.push_back({id, 0, 0.1f, {}});
  base::SplitMix64 random(99);
  std::vector<RobotFrame> frames(kRobots);
  for (uint16_t id = 0; id < kRobots; ++id) {
    frames[id] = RobotFrame{.id = id, .presence = Presence::kRunning};
    frames[id].true_x_m = static_cast<float>(id % 40);
    frames[id].true_y_m = static_cast<float>(id / 40);
  }
  std::ostringstream out;
  Writer writer(out, header);

  for (uint32_t round = 0; round < kRounds; ++round) {
    for (RobotFrame& frame : frames) {
      frame.epoch = static_cast<uint16_t>(round / 20);
      frame.phase = static_cast<uint8_t>(round % 3);
      frame.true_x_m += 0.01f;
      frame.true_y_m += Jitter(random);
      frame.true_heading_rad = Jitter(random);
      frame.est_x_m = frame.true_x_m + Jitter(random);
      frame.est_y_m = frame.true_y_m + Jitter(random);
      frame.est_heading_rad = frame.true_heading_rad + Jitter(random);
    }
    const Event event{EventKind::kEpochStart, 0, kNoRobot, frames[0].epoch, 0, round * 50'000'000ll};
    writer.WriteRound(round, round * 50'000'000ll, frames, {&event, round % 20 == 0 ? 1u : 0u});
  }
  writer.Finish();

  ASSERT_TRUE(writer.ok()) << writer.error();
  const double bytes_per_frame = static_cast<double>(out.str().size()) / (double{kRobots} * kRounds);
  std::printf("replay: %u robots x %u rounds, every field changing: %zu bytes, %.2f bytes per robot-frame\n",
              unsigned{kRobots}, kRounds, out.str().size(), bytes_per_frame);
  EXPECT_LE(bytes_per_frame, kTargetBytesPerFrame);

  std::istringstream in(out.str());
  Reader reader(in);
  Header read_header;
  ASSERT_TRUE(reader.ReadHeader(read_header)) << reader.error();
  Round read_round;
  uint32_t rounds = 0;
  size_t frames_read = 0;
  while (reader.Next(read_round)) {
    ++rounds;
    frames_read += read_round.robots.size();
  }
  EXPECT_TRUE(reader.complete()) << reader.error();
  EXPECT_EQ(rounds, kRounds);
  EXPECT_EQ(frames_read, size_t{kRobots} * kRounds);
}

}  // namespace
}  // namespace syrof::lab::replay
