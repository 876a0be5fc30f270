// syrof-firmware-swarm --live in a real browser (headless Chromium,
// tests/lab/live/headless_chromium.h): the page opened while the emulated
// robots run shows every robot RUNNING, as the page of `syrof swarm --live`
// (tests/lab/live/live_browser_test.cpp) shows the DDS robots. The page's
// fragment `live-until=rounds:N` closes its stream after N rounds, and
// Chromium dumps it with its own report (viewer.js's #report).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "headless_chromium.h"
#include "live_swarm.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/replay/replay.h"

namespace syrof::firmware::swarm {
namespace {

using nlohmann::json;
using testing::LiveSwarm;

constexpr int kRobots = 3;  // Chromium shares the 2 cores: one qemu fewer keeps the robots' reports on time
// Chromium takes seconds to start on a loaded machine: the run lasts long
// enough for it to open the page well before the end.
constexpr int kSeconds = 10;
constexpr int kRounds = 60;  // 3 s of the run: the page closes its stream there

// Round `index` of the replay at `path` (robots empty when it has none).
lab::replay::Round RecordedRound(const std::filesystem::path& path, uint32_t index) {
  std::ifstream in(path, std::ios::binary);
  lab::replay::Reader reader(in);
  lab::replay::Header header;
  lab::replay::Round round;
  if (!reader.ReadHeader(header)) return {};
  while (reader.Next(round)) {
    if (round.index == index) return round;
  }
  return {};
}

TEST(FirmwareSwarmLiveBrowser, ThePageOpenedWhileTheRobotsRunShowsEveryRobotRunning) {
  if (!testing::HaveImage()) {
    if (testing::ImageRequired()) FAIL() << "no robot image " << testing::RobotImage();
    GTEST_SKIP() << "no robot image " << testing::RobotImage() << " (make test-firmware-swarm builds it)";
  }
  ASSERT_EQ(access(SYROF_CHROMIUM, X_OK), 0) << "no Chromium at " << SYROF_CHROMIUM;
  const std::filesystem::path out = SYROF_TEST_OUT "/browser";
  LiveSwarm swarm(out, kRobots, kSeconds);
  ASSERT_TRUE(swarm.started());
  const std::optional<int> port = swarm.WaitForPage(std::chrono::seconds(30));
  ASSERT_TRUE(port.has_value()) << swarm.output();

  // Opened as soon as the page is up: Chromium starts while the qemu
  // robots boot, and draws their rounds as they come.
  lab::live::testing::Browser browser(
      SYROF_CHROMIUM, out / ("profile-" + std::to_string(getpid())), "--dump-dom",
      "http://127.0.0.1:" + std::to_string(*port) + "/#live-until=rounds:" + std::to_string(kRounds));
  browser.Join();
  EXPECT_EQ(swarm.Wait(std::chrono::seconds(90)), 0) << swarm.output();

  const json report = browser.Report();
  ASSERT_TRUE(report.is_object()) << browser.output().substr(0, 2000);
  // It watched the run: its fragment closed the stream before the end came.
  EXPECT_EQ(report["live"]["stopped"], true) << "the page did not see the run running: " << report.dump();
  // The page draws at most every 100 ms: it may take a few rounds past kRounds.
  EXPECT_GE(report["live"]["rounds"].get<int>(), kRounds) << report.dump();
  EXPECT_EQ(report["live"]["skipped"], 0) << report.dump();
  // The newest round's robots as drawn: [x, y, presence], presence 1 RUNNING,
  // as the replay recorded that round.
  const json& positions = report["live"]["positions"];
  ASSERT_EQ(positions.size(), static_cast<size_t>(kRobots)) << report.dump();
  const lab::replay::Round recorded = RecordedRound(out / "run" / "replay", report["live"]["newest_round"].get<uint32_t>());
  ASSERT_EQ(recorded.robots.size(), positions.size()) << report.dump();
  for (size_t robot = 0; robot < positions.size(); ++robot) {
    ASSERT_TRUE(positions[robot].is_array()) << "robot " << robot << " is not drawn: " << report.dump();
    EXPECT_EQ(positions[robot][2], static_cast<int>(lab::replay::Presence::kRunning))
        << "robot " << robot << " (" << lab::replay::ToString(recorded.robots[robot].presence)
        << " in the replay): " << report.dump();
    EXPECT_EQ(positions[robot][2], static_cast<int>(recorded.robots[robot].presence)) << "robot " << robot;
  }
}

}  // namespace
}  // namespace syrof::firmware::swarm
