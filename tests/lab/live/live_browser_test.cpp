// The live page in a real browser (headless Chromium), fed by a lab run in
// this process, paced to the wall clock as `syrof run --live` paces it: the
// robots move between two screenshots, a crash shows within a second, and
// the end shows the replay's link. Chromium's virtual time waits while the
// stream is open, so the page's fragment `live-until=` closes it at the
// moment under test and Chromium then dumps the page or its screenshot.
//
// Skipped when Chromium is absent (as tests/lab/view/browser_test.cpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "syrof/lab/live/live_server.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/lab/view/view.h"
#include "headless_chromium.h"
#include "png_image.h"

namespace syrof::lab::live {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

fs::path Artifacts() {
  const fs::path dir = SYROF_LIVE_ARTIFACTS;
  fs::create_directories(dir);
  return dir;
}

bool HaveChromium() { return access(SYROF_CHROMIUM, X_OK) == 0; }

using testing::WallMicroseconds;

// Chromium (headless_chromium.h) on `url`, its profile a fresh folder in
// the artifacts named after `name`.
class Browser : public testing::Browser {
 public:
  Browser(const std::string& what, const std::string& url, const std::string& name)
      : testing::Browser(SYROF_CHROMIUM, Artifacts() / ("profile-" + name + "-" + std::to_string(getpid())), what,
                         url) {}
};

// Passes the rounds on to the live server and remembers, for the checks,
// each round's frames and when (wall clock) the first CRASH was recorded.
class Tee : public replay::RoundSink {
 public:
  explicit Tee(LiveServer& server) : server_(server) {}
  void OnHeader(const replay::Header& header) override { server_.OnHeader(header); }
  void OnRound(uint32_t index, int64_t time_ns, std::span<const replay::RobotFrame> robots,
               std::span<const replay::Event> events, std::span<const replay::RobotMap> maps) override {
    for (const replay::Event& event : events) {
      if (event.kind == replay::EventKind::kCrash && crash_us == 0) crash_us = WallMicroseconds();
    }
    frames.emplace_back(robots.begin(), robots.end());
    server_.OnRound(index, time_ns, robots, events, maps);
  }
  void OnFinish(bool complete) override { server_.OnFinish(complete); }

  std::vector<std::vector<replay::RobotFrame>> frames;
  int64_t crash_us = 0;

 private:
  LiveServer& server_;
};

constexpr const char* kScenario = R"(name: live_browser
robots: { count: 4, placement: circle, radius_m: 1.0 }
timing: { duration_s: 5 }
faults:
  - { crash: 1, at_s: 2 }
app: builtin:circle
)";

struct Run {
  std::unique_ptr<LiveServer> server;
  std::unique_ptr<Tee> tee;
  std::unique_ptr<sim::Simulation> simulation;
  std::ostringstream replay;
  scenario::Scenario scenario;
};

std::unique_ptr<Run> MakeRun() {
  auto run = std::make_unique<Run>();
  const scenario::LoadResult loaded = scenario::LoadScenarioText(kScenario, "live_browser.yaml");
  EXPECT_TRUE(loaded.ok());
  run->scenario = *loaded.scenario;
  LiveOptions options;
  options.replay_page_follows = true;
  run->server = std::make_unique<LiveServer>(options);
  EXPECT_FALSE(run->server->Start("127.0.0.1", 0).has_value());
  run->tee = std::make_unique<Tee>(*run->server);
  sim::SimulationOptions sim_options;
  sim_options.sinks = {run->tee.get()};
  sim_options.replay = &run->replay;
  run->simulation = std::make_unique<sim::Simulation>(run->scenario, sim_options);
  return run;
}

// Waits for `browsers` streams, then runs to the end at the wall clock's
// pace and gives the server the replay's page.
bool PlayWhenWatched(Run& run, size_t browsers) {
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(60);
  while (run.server->clients() < browsers) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const Clock::time_point start = Clock::now();
  const double step_s = run.scenario.timing.radio_round_s;
  for (int64_t round = 1;; ++round) {
    const double until_s = std::min(run.scenario.timing.duration_s, static_cast<double>(round) * step_s);
    run.simulation->RunUntil(until_s);
    std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(until_s)));
    if (until_s >= run.scenario.timing.duration_s) break;
  }
  run.simulation->Finish(0);
  std::istringstream in(run.replay.str());
  run.server->SetReplayPage(view::BuildPage(in, "replay").html);
  return true;
}

using lab::testing::Image;
using lab::testing::ReadPng;

TEST(LiveBrowser, RobotsMoveBetweenTwoScreenshotsOfARunningRun) {
  if (!HaveChromium()) GTEST_SKIP() << "no Chromium at " << SYROF_CHROMIUM;
  auto run = MakeRun();
  const std::string url = run->server->listening().url;
  const fs::path early = Artifacts() / "live_round_20.png";
  const fs::path late = Artifacts() / "live_round_90.png";
  fs::remove(early);
  fs::remove(late);
  Browser geometry("--dump-dom", url + "#live-until=rounds:20", "geometry");
  Browser first("--screenshot=" + early.string(), url + "#live-until=rounds:20", "early");
  Browser second("--screenshot=" + late.string(), url + "#live-until=rounds:90", "late");
  ASSERT_TRUE(PlayWhenWatched(*run, 3)) << "the browsers never connected";
  geometry.Join();
  first.Join();
  second.Join();

  const json report = geometry.Report();
  ASSERT_TRUE(report.is_object()) << geometry.output().substr(0, 2000);
  EXPECT_EQ(report["live"]["rounds"], 20);
  const json& arena = report["arena"];
  const Image a = ReadPng(early);
  const Image b = ReadPng(late);
  ASSERT_GT(a.width, 0u);
  ASSERT_EQ(a.width, b.width);
  ASSERT_GE(run->tee->frames.size(), 90u);
  const double scale = arena["scale"];
  auto pixel = [&](const replay::RobotFrame& frame) {
    return std::pair{arena["left"].get<double>() + arena["ox"].get<double>() + frame.true_x_m * scale,
                     arena["top"].get<double>() + arena["oy"].get<double>() - frame.true_y_m * scale};
  };
  // Where each robot that moved more than its body's diameter was at round
  // 20, the two screenshots differ; where it is at round 90 too.
  int moved = 0;
  for (size_t slot = 0; slot < run->tee->frames[19].size(); ++slot) {
    const replay::RobotFrame& then = run->tee->frames[19][slot];
    const replay::RobotFrame& now = run->tee->frames[89][slot];
    if (std::hypot(then.true_x_m - now.true_x_m, then.true_y_m - now.true_y_m) < 0.2) continue;
    ++moved;
    const auto [x0, y0] = pixel(then);
    const auto [x1, y1] = pixel(now);
    EXPECT_NE(a.At(x0, y0), b.At(x0, y0)) << "robot " << then.id << " at round 20";
    EXPECT_NE(a.At(x1, y1), b.At(x1, y1)) << "robot " << now.id << " at round 90";
  }
  EXPECT_GE(moved, 2);
}

TEST(LiveBrowser, ACrashShowsWithinASecond) {
  if (!HaveChromium()) GTEST_SKIP() << "no Chromium at " << SYROF_CHROMIUM;
  auto run = MakeRun();
  Browser browser("--dump-dom", run->server->listening().url + "#live-until=crash:1", "crash");
  ASSERT_TRUE(PlayWhenWatched(*run, 1)) << "the browser never connected";
  browser.Join();
  const json report = browser.Report();
  ASSERT_TRUE(report.is_object()) << browser.output().substr(0, 2000);
  ASSERT_TRUE(report["live"]["crash_shown_w_us"].contains("1")) << report.dump();
  EXPECT_EQ(report["live"]["positions"][1][2], 3);  // drawn CRASHED
  ASSERT_GT(run->tee->crash_us, 0);
  // From the crash's round being recorded to the page, drawn, reaching this
  // process: an upper bound on what a person watching would wait.
  const double latency_s = static_cast<double>(browser.done_us() - run->tee->crash_us) * 1e-6;
  EXPECT_LT(latency_s, 1.0) << "the page drew it with the round recorded "
                            << (report["live"]["crash_shown_w_us"]["1"].get<int64_t>() - run->tee->crash_us) * 1e-6
                            << " s after the crash's";
  std::ofstream(Artifacts() / "crash_latency.txt") << latency_s << " s\n";
}

TEST(LiveBrowser, TheEndSaysSoAndLinksTheReplay) {
  if (!HaveChromium()) GTEST_SKIP() << "no Chromium at " << SYROF_CHROMIUM;
  auto run = MakeRun();
  Browser browser("--dump-dom", run->server->listening().url, "end");
  ASSERT_TRUE(PlayWhenWatched(*run, 1)) << "the browser never connected";
  browser.Join();
  const json report = browser.Report();
  ASSERT_TRUE(report.is_object()) << browser.output().substr(0, 2000);
  EXPECT_EQ(report["live"]["ended"]["replay"], "replay.html");
  EXPECT_EQ(report["live"]["rounds"], 100);  // 5 s of 50 ms rounds, none skipped
  EXPECT_NE(browser.output().find("id=\"replay-link\""), std::string::npos);
  EXPECT_NE(browser.output().find("Run ended"), std::string::npos);
}

}  // namespace
}  // namespace syrof::lab::live
