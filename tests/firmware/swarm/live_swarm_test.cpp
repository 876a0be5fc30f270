// syrof-firmware-swarm --live: the emulated swarm serves the live page with
// the server `syrof swarm --live` uses (lab/live), fed by the rounds the
// host records from the qemu robots' reports. Read here as a browser reads
// it, through GET /events (Server-Sent Events, tests/lab/live/sse_client.h):
// the header, one round per radio round as the robots report it (the
// rounds the replay records), every robot RUNNING once it reports, and the
// end linking the replay.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "live_swarm.h"
#include "sse_client.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/view/page_data.h"

namespace syrof::firmware::swarm {
namespace {

using nlohmann::json;
using testing::LiveSwarm;

constexpr int kRobots = 4;
constexpr int kSeconds = 4;
constexpr int kRoundsPerSecond = 20;  // the image's radio round, 50 ms

// A frame's presence in the page's state word (lab/view page_data.h,
// FrameState: presence | status << 2 | ...).
int Presence(const json& frame) { return frame[0].get<int>() & 3; }

TEST(FirmwareSwarmLive, EventsCarryTheHeaderThenEveryRoundWithEveryRobotRunning) {
  if (!testing::HaveImage()) {
    if (testing::ImageRequired()) FAIL() << "no robot image " << testing::RobotImage();
    GTEST_SKIP() << "no robot image " << testing::RobotImage() << " (make test-firmware-swarm builds it)";
  }
  LiveSwarm swarm(SYROF_TEST_OUT "/events", kRobots, kSeconds);
  ASSERT_TRUE(swarm.started());
  const std::optional<int> port = swarm.WaitForPage(std::chrono::seconds(30));
  ASSERT_TRUE(port.has_value()) << swarm.output();

  lab::live::testing::SseClient client;
  ASSERT_TRUE(client.Get(*port, "/events"));
  // The whole run: its rounds arrive as the robots report, then the end.
  const bool ended = client.ReadUntil(
      [](const auto& events) { return !events.empty() && events.back().name == "end"; }, std::chrono::seconds(90));
  const int exit_code = swarm.Wait(std::chrono::seconds(60));
  ASSERT_TRUE(ended) << client.events().size() << " events; " << swarm.output();
  EXPECT_EQ(exit_code, 0) << swarm.output();
  EXPECT_EQ(client.status(), 200);

  const auto& events = client.events();
  ASSERT_GE(events.size(), 2u);
  ASSERT_EQ(events.front().name, "header");
  const json header = json::parse(events.front().data);
  EXPECT_EQ(header["robots"].size(), static_cast<size_t>(kRobots)) << header.dump();
  EXPECT_EQ(header["round_ns"], 50'000'000) << header.dump();

  // Every round of the run, in order, none skipped, each with every robot.
  std::vector<json> rounds;
  for (const auto& event : events) {
    if (event.name == "round") rounds.push_back(json::parse(event.data));
    EXPECT_NE(event.name, "skipped");
  }
  // As many as the replay holds (the run's last round may end past its
  // seconds: 80 or 81 for 4 s).
  const json report = json::parse(testing::ReadText(SYROF_TEST_OUT "/events/run/firmware-swarm.json"));
  ASSERT_EQ(rounds.size(), report["replay_rounds"].get<size_t>()) << swarm.output();
  ASSERT_GE(rounds.size(), static_cast<size_t>(kSeconds * kRoundsPerSecond)) << swarm.output();
  for (size_t i = 0; i < rounds.size(); ++i) {
    ASSERT_EQ(rounds[i]["i"], i);
    ASSERT_EQ(rounds[i]["f"].size(), static_cast<size_t>(kRobots)) << rounds[i].dump();
  }
  // The page is fed what the replay records: each round's robots in the
  // same presence and at the same true position (mm) as the replay's.
  std::ifstream replay_file(SYROF_TEST_OUT "/events/run/replay", std::ios::binary);
  lab::replay::Reader reader(replay_file);
  lab::replay::Header replay_header;
  ASSERT_TRUE(reader.ReadHeader(replay_header));
  lab::replay::Round replay_round;
  for (const json& round : rounds) {
    ASSERT_TRUE(reader.Next(replay_round)) << "round " << round["i"];
    ASSERT_EQ(replay_round.index, round["i"].get<uint32_t>());
    ASSERT_EQ(replay_round.robots.size(), round["f"].size());
    for (size_t slot = 0; slot < replay_round.robots.size(); ++slot) {
      const lab::replay::RobotFrame& frame = replay_round.robots[slot];
      EXPECT_EQ(Presence(round["f"][slot]), static_cast<int>(frame.presence)) << "round " << round["i"];
      EXPECT_EQ(round["f"][slot][2], lab::view::Milli(frame.true_x_m)) << "round " << round["i"];
    }
  }
  // A robot shows RUNNING once its qemu reports (absent before, and for a
  // round when its report is more than three rounds late: on a 2-core
  // machine busy with other builds, up to 1 round in 10 had one): after the
  // first second, every robot RUNNING in most rounds (all of them here
  // when the machine is otherwise idle).
  size_t all_running = 0;
  for (size_t i = kRoundsPerSecond; i < rounds.size(); ++i) {
    bool all = true;
    for (const json& frame : rounds[i]["f"]) all = all && Presence(frame) == static_cast<int>(lab::replay::Presence::kRunning);
    if (all) ++all_running;
  }
  const size_t after_first_second = rounds.size() - kRoundsPerSecond;
  EXPECT_GE(all_running * 2, after_first_second)
      << "every robot RUNNING in only " << all_running << " of the " << after_first_second
      << " rounds after the first second";

  // The end links the replay's page, as `syrof swarm --live`'s does.
  const json end = json::parse(events.back().data);
  EXPECT_EQ(end["complete"], true) << end.dump();
  EXPECT_EQ(end["replay"], "replay.html") << end.dump();
}

}  // namespace
}  // namespace syrof::firmware::swarm
