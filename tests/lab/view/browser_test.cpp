// The viewer's page in a real browser (headless Chromium): it is written for
// a fixed scenario and seed (or a replay made by hand), loaded from file://,
// and what it reports and draws is compared with what the C++ reader reads
// from the same replay. The page says it is ready with <body data-ready="1">
// and a JSON summary in #report (viewer.js); the test reads the DOM Chromium
// dumps after the page's scripts ran, and the pixels of a screenshot.
//
// Pages and screenshots stay in SYROF_VIEW_ARTIFACTS for a person to look at.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "replay_test_support.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/lab/view/verdict.h"
#include "syrof/lab/view/view.h"
#include "png_image.h"

namespace syrof::lab::view {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The browser window: large enough that the arena is at the top of the
// screenshot, the same for the DOM dump and the screenshot so the layout is.
constexpr const char* kWindow = "1280,1000";

fs::path Artifacts() {
  const fs::path dir = SYROF_VIEW_ARTIFACTS;
  fs::create_directories(dir);
  return dir;
}

std::string Chromium(const std::string& what, const fs::path& page, const std::string& fragment) {
  // A profile folder per process and page: ctest runs each test as its own
  // process, in parallel, and two Chromiums cannot share a profile.
  const fs::path profile = Artifacts() / ("profile-" + page.stem().string() + "-" + std::to_string(getpid()));
  return std::string(SYROF_CHROMIUM) + " --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run" +
         " --disable-extensions --disable-dev-shm-usage --user-data-dir=" + profile.string() +
         " --window-size=" + kWindow + " --virtual-time-budget=3000 " + what + " 'file://" + page.string() +
         fragment + "' 2>/dev/null";
}

// The DOM after the page's scripts ran.
std::string DumpDom(const fs::path& page, const std::string& fragment = "") {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(Chromium("--dump-dom", page, fragment).c_str(), "r"), pclose);
  if (!pipe) return {};
  std::string dom;
  std::array<char, 65536> buffer;
  size_t got = 0;
  while ((got = fread(buffer.data(), 1, buffer.size(), pipe.get())) > 0) dom.append(buffer.data(), got);
  return dom;
}

std::string Unescape(std::string text) {
  for (const auto& [from, to] : std::array<std::pair<std::string, std::string>, 3>{
           {{"&lt;", "<"}, {"&gt;", ">"}, {"&amp;", "&"}}}) {
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
  }
  return text;
}

// What the page reported, and the DOM it is in.
struct Loaded {
  std::string dom;
  json report;
};

Loaded Load(const fs::path& page, const std::string& fragment = "") {
  Loaded loaded;
  loaded.dom = DumpDom(page, fragment);
  std::smatch match;
  if (std::regex_search(loaded.dom, match, std::regex(R"re(<pre id="report" hidden="">([^<]*)</pre>)re"))) {
    loaded.report = json::parse(Unescape(match[1].str()), nullptr, false);
  }
  return loaded;
}

size_t Count(const std::string& text, const std::string& what) {
  size_t count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

fs::path WritePage(const std::string& replay_bytes, const std::string& name, const PageOptions& options = {}) {
  std::istringstream in(replay_bytes);
  const Page page = BuildPage(in, name, options);
  const fs::path path = Artifacts() / (name + ".html");
  std::ofstream(path, std::ios::binary) << page.html;
  return path;
}

// ---- The replay as the C++ reader sees it ---------------------------------

struct Replay {
  replay::Header header;
  std::vector<replay::Round> rounds;  // frames carried forward: every robot in every round
  size_t events = 0;
};

Replay ReadAll(const std::string& bytes) {
  std::istringstream in(bytes);
  replay::Reader reader(in);
  Replay result;
  EXPECT_TRUE(reader.ReadHeader(result.header)) << reader.error();
  std::vector<replay::RobotFrame> current(result.header.robots.size());
  for (size_t i = 0; i < current.size(); ++i) current[i].id = result.header.robots[i].id;
  replay::Round round;
  while (reader.Next(round)) {
    for (const replay::RobotFrame& frame : round.robots) {
      for (replay::RobotFrame& slot : current) {
        if (slot.id == frame.id) slot = frame;
      }
    }
    result.events += round.events.size();
    round.robots = current;
    result.rounds.push_back(round);
  }
  EXPECT_TRUE(reader.complete()) << reader.error();
  return result;
}

// ---- A scenario run: demo_circle, 12 s, seed 7 -------------------------------

class ScenarioPage : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scenario::Overrides overrides;
    overrides.duration_s = 12;
    overrides.seed = 7;
    const scenario::LoadResult loaded =
        scenario::LoadScenarioFile(std::string(SYROF_SCENARIOS_DIR) + "/demo_circle.yaml", overrides);
    ASSERT_TRUE(loaded.ok());
    std::ostringstream bytes;
    sim::SimulationOptions options;
    options.replay = &bytes;
    (void)sim::Run(*loaded.scenario, options, 0.0);
    bytes_ = new std::string(bytes.str());
    replay_ = new Replay(ReadAll(*bytes_));
  }
  static void TearDownTestSuite() {
    delete replay_;
    delete bytes_;
  }
  // Each test its own page file: tests run in parallel processes.
  void SetUp() override {
    page_ = WritePage(*bytes_, std::string("demo_circle_12s_") +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }

  // A round, after the first seconds, where robots are in both modes (the
  // demo loses 10% of beacons), so the screenshot holds both colours.
  static const replay::Round& MixedRound() {
    for (const replay::Round& round : replay_->rounds) {
      if (round.index < 60) continue;
      bool cooperative = false, autonomous = false;
      for (const replay::RobotFrame& frame : round.robots) (frame.mode == 0 ? cooperative : autonomous) = true;
      if (cooperative && autonomous) return round;
    }
    return replay_->rounds[100];
  }

  static Replay* replay_;
  static std::string* bytes_;
  fs::path page_;
};
Replay* ScenarioPage::replay_ = nullptr;
std::string* ScenarioPage::bytes_ = nullptr;

TEST_F(ScenarioPage, DrawsEveryRobotAndListsEveryEvent) {
  const replay::Round& round = replay_->rounds[150];

  const Loaded loaded = Load(page_, "#round=" + std::to_string(round.index));

  ASSERT_NE(loaded.dom.find("data-ready=\"1\""), std::string::npos) << "the page never reported ready";
  ASSERT_TRUE(loaded.report.is_object()) << loaded.dom.substr(0, 2000);
  EXPECT_EQ(loaded.report["status"], "complete");
  EXPECT_EQ(loaded.report["round"], round.index);
  size_t present = 0;
  for (const replay::RobotFrame& frame : round.robots) present += frame.presence != replay::Presence::kAbsent;
  EXPECT_EQ(loaded.report["robots_drawn"], present);
  EXPECT_EQ(present, 10u);
  // Counted in the DOM itself, not in the page's own summary.
  EXPECT_EQ(Count(loaded.dom, "<li class=\"ev "), replay_->events);
  EXPECT_EQ(loaded.report["events_listed"], replay_->events);
}

TEST_F(ScenarioPage, InspectorShowsTheMapTheRobotStartedItsEpochWith) {
  // Robot 3's latest epoch start at or before round 200, from the reader.
  const uint16_t robot = 3;
  std::shared_ptr<const replay::EpochMap> map;
  uint32_t at_round = 0;
  for (const replay::Round& round : replay_->rounds) {
    if (round.index > 200) break;
    for (const replay::RobotMap& entry : round.maps) {
      if (entry.robot == robot) map = entry.map;
    }
    at_round = round.index;
  }
  ASSERT_NE(map, nullptr);

  const Loaded loaded = Load(page_, "#round=" + std::to_string(at_round) + "&robot=3");

  const json& inspector = loaded.report["inspector"];
  ASSERT_TRUE(inspector.is_object()) << loaded.report.dump();
  EXPECT_EQ(inspector["robot"], robot);
  EXPECT_EQ(inspector["epoch"], map->epoch);
  std::vector<int> members;
  for (const replay::MapMember& member : map->members) members.push_back(member.id);
  EXPECT_EQ(inspector["members"].get<std::vector<int>>(), members);
  // And the DOM's table has a row per member.
  EXPECT_EQ(Count(loaded.dom, "<tr data-member="), members.size());
}

using testing::Image;
using testing::ReadPng;

TEST_F(ScenarioPage, ScreenshotHasEachRobotsColourWhereTheRobotIs) {
  const replay::Round& round = MixedRound();
  const std::string fragment = "#round=" + std::to_string(round.index);
  const Loaded loaded = Load(page_, fragment);
  const fs::path shot = Artifacts() / "demo_circle_12s.png";
  fs::remove(shot);
  ASSERT_EQ(std::system(Chromium("--screenshot=" + shot.string(), page_, fragment).c_str()), 0);

  const Image image = ReadPng(shot);
  ASSERT_GT(image.width, 0u) << "no screenshot at " << shot;
  const json& arena = loaded.report["arena"];
  const json& colours = loaded.report["colours"];
  ASSERT_TRUE(arena.is_object() && colours.is_object()) << loaded.report.dump();
  const double scale = arena["scale"];
  int checked = 0;
  for (const replay::RobotFrame& frame : round.robots) {
    ASSERT_EQ(frame.presence, replay::Presence::kRunning);
    const double radius = replay_->header.robots[frame.id].body_radius_m * scale;
    // Inside the body, behind the heading line (which is white), away from the label.
    const double x = arena["left"].get<double>() + arena["ox"].get<double>() + frame.true_x_m * scale -
                     0.45 * radius * std::cos(frame.true_heading_rad);
    const double y = arena["top"].get<double>() + arena["oy"].get<double>() - frame.true_y_m * scale +
                     0.45 * radius * std::sin(frame.true_heading_rad);
    const json& want = frame.status == 1 ? colours["joining"]
                                         : frame.mode == 0 ? colours["cooperative"] : colours["autonomous"];
    const std::array<int, 3> got = image.At(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
    for (int channel = 0; channel < 3; ++channel) {
      EXPECT_NEAR(got[channel], want[channel].get<int>(), 6)
          << "robot " << frame.id << " (mode " << int{frame.mode} << ") at pixel (" << x << ", " << y << ")";
    }
    ++checked;
  }
  EXPECT_EQ(checked, 10);
}

// ---- A replay made by hand: two robots that collide in round 30 ------------

// `kind` in round 30: COLLISION, or BEACON_LOST (robot 0's beacon that
// robot 1 did not hear).
std::string CollisionReplay(replay::EventKind kind = replay::EventKind::kCollision) {
  replay::Header header;
  header.seed = 1;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 4;
  header.arena_height_m = 2;
  header.scenario_name = "collision";
  header.app_name = "by hand";
  header.robots = {{0, 0, 0.1f, {}}, {1, 0, 0.1f, {}}};
  std::ostringstream bytes;
  replay::Writer writer(bytes, header);
  auto map = std::make_shared<replay::EpochMap>();
  map->epoch = 1;
  map->members = {replay::MapMember{0, 0, 1000, 1000, 0, 0, 0, {}}, replay::MapMember{1, 0, 3000, 1000, 0, 0, 0, {}}};
  for (uint32_t index = 1; index <= 60; ++index) {
    const float gap = std::max(0.2f, 2.0f - 0.06f * static_cast<float>(index));  // they meet in round 30
    std::vector<replay::RobotFrame> frames(2);
    for (uint16_t id = 0; id < 2; ++id) {
      frames[id] = replay::RobotFrame{.id = id, .presence = replay::Presence::kRunning, .epoch = 1};
      frames[id].true_x_m = frames[id].est_x_m = 2.0f + (id == 0 ? -gap : gap) / 2;
      frames[id].true_y_m = frames[id].est_y_m = 1.0f;
    }
    std::vector<replay::Event> events;
    std::vector<replay::RobotMap> maps;
    const int64_t time_ns = int64_t{index} * 50'000'000;
    if (index == 1) {
      events = {{replay::EventKind::kEpochStart, 0, replay::kNoRobot, 1, 0, time_ns},
                {replay::EventKind::kEpochStart, 1, replay::kNoRobot, 1, 0, time_ns}};
      maps = {{0, map}, {1, map}};
    }
    if (index == 30) events = {{kind, 0, 1, 1, 0, time_ns}};
    writer.WriteRound(index, time_ns, frames, events, maps);
  }
  writer.Finish();
  EXPECT_TRUE(writer.ok()) << writer.error();
  return bytes.str();
}

// The page at round 30 marks one `kind` event of robot 0 with robot 1.
void ExpectOneMarkInRound30(const Loaded& at, const std::string& kind) {
  ASSERT_EQ(at.report["marks"].size(), 1u) << at.report.dump();
  EXPECT_EQ(at.report["marks"][0]["kind"], kind);
  EXPECT_EQ(at.report["marks"][0]["robot"], 0);
  EXPECT_EQ(at.report["marks"][0]["other"], 1);
  EXPECT_EQ(at.report["marks"][0]["round"], 30);
}

TEST(CollisionPage, SteppingToTheCollisionRoundShowsItMarked) {
  const fs::path page = WritePage(CollisionReplay(), "collision");

  const Loaded before = Load(page, "#round=29");
  const Loaded at = Load(page, "#round=30");

  EXPECT_EQ(before.report["marks"], json::array()) << before.report.dump();
  ExpectOneMarkInRound30(at, "COLLISION");
  EXPECT_NE(at.dom.find("<li class=\"ev k4 now\""), std::string::npos);  // listed (kind 4), as happening now
}

TEST(LostBeaconPage, ALostBeaconIsMarkedFromSenderToReceiver) {
  const fs::path page = WritePage(CollisionReplay(replay::EventKind::kBeaconLost), "lost_beacon");

  const Loaded before = Load(page, "#round=29");
  const Loaded at = Load(page, "#round=30");
  const Loaded later = Load(page, "#round=50");  // 20 rounds on: gone

  EXPECT_EQ(before.report["marks"], json::array()) << before.report.dump();
  ExpectOneMarkInRound30(at, "BEACON_LOST");
  EXPECT_EQ(later.report["marks"], json::array()) << later.report.dump();
  EXPECT_NE(at.dom.find("<li class=\"ev k17 now\""), std::string::npos);  // listed (kind 17), as happening now
  EXPECT_NE(at.dom.find("BEACON_LOST"), std::string::npos);
}

// ---- The verdict: how the run went, first on the page ---------------------------

// The verdict banner's class and headline, from the DOM itself.
struct Banner {
  std::string state, headline;
};
Banner VerdictBanner(const Loaded& loaded) {
  std::smatch match;
  if (!std::regex_search(loaded.dom, match,
                         std::regex(R"re(<div id="verdict" class="([^"]*)"><div class="headline">([^<]*)</div>)re"))) {
    return {};
  }
  return {match[1].str(), Unescape(match[2].str())};
}

// The banner is above the arena and within the window (1000 px high): seen
// without scrolling.
void ExpectSeenFirst(const Loaded& loaded) {
  const json verdict = loaded.report.value("verdict", json());
  ASSERT_TRUE(verdict.is_object()) << loaded.report.dump();
  EXPECT_LT(verdict["bottom"].get<double>(), 1000.0);
  EXPECT_LT(verdict["bottom"].get<double>(), loaded.report["arena"]["top"].get<double>());
}

// Metrics of a run (seed 1, as the hand-made replays) that broke nothing.
metrics::Metrics CleanMetrics() {
  metrics::Metrics m;
  m.seed = 1;
  m.goal.app = "builtin:gather";
  m.goal.reached = true;
  m.goal.source = "scenario";
  metrics::GoalCheckResult check;
  check.name = check.check = "gathered";
  check.passed = true;
  check.reason = "radius 0.210 m <= 0.300 m";
  m.goal.checks = {check};
  m.agreement.emplace();
  m.agreement->cooperative_epochs = 3;
  m.agreement->agreed_epochs = 3;
  return m;
}

TEST(VerdictPage, ARunThatMetItsGoalSaysOkFirst) {
  PageOptions options;
  options.metrics = CleanMetrics();
  const fs::path page = WritePage(CollisionReplay(replay::EventKind::kEpochStart), "verdict_ok", options);

  const Loaded loaded = Load(page);

  const Banner banner = VerdictBanner(loaded);
  EXPECT_EQ(banner.state, "ok") << loaded.dom.substr(0, 3000);
  EXPECT_EQ(banner.headline, "Goal met: 1 of 1 checks held; gathered held: radius 0.210 m <= 0.300 m");
  ExpectSeenFirst(loaded);
}

TEST(VerdictPage, AMissedGoalSaysWhichCheckAndWhy) {
  PageOptions options;
  options.metrics = CleanMetrics();
  options.metrics->goal.reached = false;
  options.metrics->goal.checks[0].passed = false;
  options.metrics->goal.checks[0].reason = "robot 3 is 0.420 m from the centre, radius 0.300 m";
  const fs::path page = WritePage(CollisionReplay(replay::EventKind::kEpochStart), "verdict_missed", options);

  const Loaded loaded = Load(page);

  const Banner banner = VerdictBanner(loaded);
  EXPECT_EQ(banner.state, "missed");
  EXPECT_EQ(banner.headline, "Goal missed: gathered: robot 3 is 0.420 m from the centre, radius 0.300 m");
  ExpectSeenFirst(loaded);
}

TEST(VerdictPage, ACounterexampleSaysWhatBrokeAndTheBeaconsItLost) {
  // A search's counterexample: robot 0's beacon of round 30 lost on the way
  // to robot 1, and the app's state split in epoch 1.
  PageOptions options;
  options.metrics = CleanMetrics();
  options.metrics->agreement->agreed_epochs = 2;
  options.metrics->agreement->disagreeing_calls = 4;
  options.metrics->agreement->first_disagreement =
      metrics::Disagreement{.epoch = 1, .round = 31, .callback = "new_round", .robot = 1, .state = 3,
                            .reference_robot = 0, .reference_state = 1};
  const fs::path page = WritePage(CollisionReplay(replay::EventKind::kBeaconLost), "verdict_counterexample", options);

  const Loaded loaded = Load(page);

  const Banner banner = VerdictBanner(loaded);
  EXPECT_EQ(banner.state, "broken");
  EXPECT_EQ(banner.headline, "BROKEN: agreement split in epoch 1: robot 1 holds 3, robot 0 holds 1 (newRound, round "
                             "31); lost beacon at round 30, 0 → 1");
  ExpectSeenFirst(loaded);
}

TEST(VerdictPage, WithoutMetricsTheReplaysCollisionsStillBreakIt) {
  const fs::path page = WritePage(CollisionReplay(), "verdict_replay_only");

  const Loaded loaded = Load(page);

  const Banner banner = VerdictBanner(loaded);
  EXPECT_EQ(banner.state, "broken");
  EXPECT_EQ(banner.headline, "BROKEN: 1 collision in the replay");
}

// ---- The goal's target -------------------------------------------------------

TEST(TargetPage, TheGatheredChecksCircleIsDrawnWhereItIs) {
  // A 4 x 2 m arena (as the hand-made replay's) whose goal gathers the robots
  // within 0.3 m of (1, 0.5), away from where the robots are.
  const scenario::LoadResult loaded_scenario = scenario::LoadScenarioText(
      "name: target\napp: builtin:idle\narena: { width_m: 4, height_m: 2 }\nrobots: { count: 2 }\n"
      "goal:\n  - { check: gathered, radius_m: 0.3, centre: { x_m: 1, y_m: 0.5 } }\n"
      "  - { check: line, spacing_m: 0.5 }\n",
      "target.yaml");
  ASSERT_TRUE(loaded_scenario.ok()) << *loaded_scenario.error;
  PageOptions options;
  options.scenario = &*loaded_scenario.scenario;
  const fs::path page = WritePage(CollisionReplay(replay::EventKind::kEpochStart), "target", options);

  const Loaded loaded = Load(page, "#round=5");
  const fs::path shot = Artifacts() / "target.png";
  fs::remove(shot);
  ASSERT_EQ(std::system(Chromium("--screenshot=" + shot.string(), page, "#round=5").c_str()), 0);

  const json targets = loaded.report.value("targets", json::array());
  ASSERT_EQ(targets.size(), 1u) << loaded.report.dump();
  EXPECT_EQ(targets[0]["shape"], "ring");
  EXPECT_EQ(targets[0]["x"], 1.0);
  EXPECT_EQ(targets[0]["r_max"], 0.3);
  EXPECT_NE(loaded.dom.find("goal target: gathered"), std::string::npos);  // the legend
  EXPECT_NE(loaded.dom.find("goal line: not drawn"), std::string::npos);
  // The ring's stroke, in the target's green, right of the centre and above it.
  const Image image = ReadPng(shot);
  ASSERT_GT(image.width, 0u);
  const json& arena = loaded.report["arena"];
  const double scale = arena["scale"];
  const double left = arena["left"].get<double>() + arena["ox"].get<double>();
  const double top = arena["top"].get<double>() + arena["oy"].get<double>();
  for (const auto& [x_m, y_m] : std::vector<std::pair<double, double>>{{1.3, 0.5}, {1.0, 0.8}, {0.7, 0.5}}) {
    const std::array<int, 3> got =
        image.At(static_cast<int>(std::lround(left + x_m * scale)), static_cast<int>(std::lround(top - y_m * scale)));
    SCOPED_TRACE(::testing::Message() << "(" << x_m << ", " << y_m << ")");
    EXPECT_LT(got[0], 110);  // green: the background and the grid are near white, the walls grey
    EXPECT_GT(got[1], got[0] + 40);
    EXPECT_GT(got[1], got[2] + 25);
  }
}

// ---- Labels before the first epoch, the events list ----------------------------

TEST_F(ScenarioPage, BeforeTheirFirstEpochRobotsAreLabelledStarting) {
  const Loaded loaded = Load(page_, "#round=1");

  const json labels = loaded.report.value("labels", json::array());
  ASSERT_EQ(labels.size(), 10u) << loaded.report.dump();
  for (const json& label : labels) {
    EXPECT_EQ(label["label"], "starting") << label.dump();
    EXPECT_EQ(label["colour"], loaded.report["colours"]["starting"]) << label.dump();  // not a mode's colour
  }
  EXPECT_NE(loaded.dom.find("epoch none yet (starting)"), std::string::npos);
}

TEST(EventsList, EveryKindFitsItsColumnAndAJoinWaitIsNamed) {
  // A safety intervention (the longest kind's name) and a join wait.
  const fs::path safety = WritePage(CollisionReplay(replay::EventKind::kSafetyIntervention), "events_safety");
  const fs::path join_wait = WritePage(CollisionReplay(replay::EventKind::kJoinWait), "events_join_wait");

  const Loaded with_safety = Load(safety);
  const Loaded with_join_wait = Load(join_wait);

  EXPECT_NE(with_safety.dom.find(">SAFETY_INTERVENTION<"), std::string::npos);
  EXPECT_EQ(with_safety.report.value("events_overflowing", json()), json::array()) << with_safety.report.dump();
  EXPECT_EQ(with_join_wait.report.value("events_overflowing", json()), json::array());
  EXPECT_NE(with_join_wait.dom.find("robot 0 waits to join: its start disc is not clear"), std::string::npos);
}

// ---- A replay made by hand with private inputs and a message format --------

std::string MessageReplay() {
  replay::Header header;
  header.seed = 1;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 4;
  header.arena_height_m = 2;
  header.scenario_name = "message";
  header.app_name = "by hand";
  header.robots = {{0, 0, 0.1f, {{"charge", 870}}}, {1, 0, 0.1f, {{"charge", 12}}}};
  message::MessageFormat format;
  format.none = false;
  format.fields = {{"charge", message::FieldType::kU16Be, 0}};
  format.length = 2;
  header.message = format;
  std::ostringstream bytes;
  replay::Writer writer(bytes, header);
  auto map = std::make_shared<replay::EpochMap>();
  map->epoch = 1;
  // Robot 0 told its charge as the format says; robot 1 sent one byte.
  map->members = {replay::MapMember{0, 0, 1000, 1000, 0, 0, 0, {0x03, 0x66}},
                  replay::MapMember{1, 0, 3000, 1000, 0, 0, 0, {0xAB}}};
  for (uint32_t index = 1; index <= 5; ++index) {
    std::vector<replay::RobotFrame> frames(2);
    for (uint16_t id = 0; id < 2; ++id) {
      frames[id] = replay::RobotFrame{.id = id, .presence = replay::Presence::kRunning, .epoch = 1};
      frames[id].true_x_m = frames[id].est_x_m = id == 0 ? 1.0f : 3.0f;
      frames[id].true_y_m = frames[id].est_y_m = 1.0f;
    }
    std::vector<replay::Event> events;
    std::vector<replay::RobotMap> maps;
    const int64_t time_ns = int64_t{index} * 50'000'000;
    if (index == 1) {
      events = {{replay::EventKind::kEpochStart, 0, replay::kNoRobot, 1, 0, time_ns},
                {replay::EventKind::kEpochStart, 1, replay::kNoRobot, 1, 0, time_ns}};
      maps = {{0, map}, {1, map}};
    }
    writer.WriteRound(index, time_ns, frames, events, maps);
  }
  writer.Finish();
  EXPECT_TRUE(writer.ok()) << writer.error();
  return bytes.str();
}

TEST(MessagePage, InspectorShowsPrivateInputsAndDecodedPayloads) {
  const fs::path page = WritePage(MessageReplay(), "message");

  const Loaded robot1 = Load(page, "#round=3&robot=1");

  const json& inspector = robot1.report["inspector"];
  ASSERT_TRUE(inspector.is_object()) << robot1.report.dump();
  EXPECT_EQ(inspector["inputs"], "charge 12");
  EXPECT_EQ(inspector["payloads"], json::array({"charge 870", "ab (bad length)"})) << inspector.dump();
  EXPECT_NE(robot1.dom.find("Message format: 2 bytes: charge u16be."), std::string::npos);
  EXPECT_NE(robot1.dom.find("<td>charge 870</td>"), std::string::npos);
  EXPECT_NE(robot1.dom.find("<td>charge 12</td>"), std::string::npos);  // the facts row
}

TEST(MessagePage, WithoutAFormatPayloadsAreHexAndInputsSayNone) {
  // The collision replay: no inputs, no format, empty payloads.
  const fs::path page = WritePage(CollisionReplay(), "collision_inputs");

  const Loaded loaded = Load(page, "#round=3&robot=0");

  const json& inspector = loaded.report["inspector"];
  ASSERT_TRUE(inspector.is_object()) << loaded.report.dump();
  EXPECT_EQ(inspector["inputs"], "none");
  EXPECT_EQ(inspector["payloads"], json::array({"–", "–"})) << inspector.dump();
}

// ---- SSYNC: robots the schedule left out (docs/activation.md) --------------------

// Three robots gathering, robot 0 left out of epochs 1 and 2 (a scripted
// schedule): its starts of those epochs carry active 0 in the page's data,
// it is drawn with the dotted ring while those epochs last and not after,
// the events list says so, and the legend names the model.
// A scheduled run for the activation pages: the scenario (3 robots
// gathering from a circle, seed 5) with `activation`, its replay's bytes,
// and the page's data drawn with the scenario.
struct ScheduledRun {
  scenario::Scenario scenario;
  std::string bytes;
  json data;
};

ScheduledRun RunForThePage(const std::string& name, double duration_s, const std::string& activation) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(
      "name: " + name + "\nseed: 5\nrobots: {count: 3, placement: circle, radius_m: 0.8}\ntiming: {duration_s: " +
          std::to_string(duration_s) + "}\napp: builtin:gather\nactivation: " + activation + "\n",
      name + ".yaml");
  EXPECT_TRUE(loaded.ok()) << loaded.error->ToString();
  ScheduledRun run{*loaded.scenario, {}, {}};
  std::ostringstream bytes;
  sim::SimulationOptions sim_options;
  sim_options.replay = &bytes;
  (void)sim::Run(run.scenario, sim_options, 0.0);
  run.bytes = bytes.str();
  PageOptions options;
  options.scenario = &run.scenario;
  std::istringstream in(run.bytes);
  Page page;
  run.data = json::parse(ReplayJson(in, name, options, page));
  return run;
}

TEST(ActivationPage, ARobotLeftOutOfAnEpochIsMarkedWhileItLasts) {
  const ScheduledRun run =
      RunForThePage("ssync_page", 6, "{model: ssync, schedule: scripted, active: [[1, [1, 2]], [2, [1, 2]]]}");
  PageOptions options;
  options.scenario = &run.scenario;
  const std::string& bytes_text = run.bytes;
  const json& data = run.data;

  // The data: robot 0's starts of epochs 1 and 2 are left out, no other.
  EXPECT_EQ(data["activation"], json::parse(R"({"model": "ssync", "schedule": "scripted"})"));
  std::vector<int64_t> left_out_positions;
  int64_t epoch3_position = -1;
  for (const json& start : data["starts"]) {
    ASSERT_EQ(start.size(), 4u) << start.dump();
    const int epoch = data["maps"][start[2].get<size_t>()][0].get<int>();
    const bool left_out = start[3] == 0;
    EXPECT_EQ(left_out, start[1] == 0 && (epoch == 1 || epoch == 2)) << start.dump() << " epoch " << epoch;
    if (left_out) left_out_positions.push_back(start[0].get<int64_t>());
    if (start[1] == 0 && epoch == 3) epoch3_position = start[0].get<int64_t>();
  }
  ASSERT_EQ(left_out_positions.size(), 2u);
  ASSERT_GT(epoch3_position, left_out_positions[1]);

  // The page, in the browser: during epoch 1 robot 0 has the ring; in
  // epoch 3 nobody has it.
  const fs::path path = WritePage(bytes_text, "ssync_left_out", options);
  const Replay replay = ReadAll(bytes_text);
  auto round_at = [&](int64_t position) { return replay.rounds.at(static_cast<size_t>(position)).index; };
  const Loaded during = Load(path, "#round=" + std::to_string(round_at(left_out_positions[0] + 2)));
  const Loaded after = Load(path, "#round=" + std::to_string(round_at(epoch3_position + 2)));
  ASSERT_TRUE(during.report.is_object()) << during.dom.substr(0, 2000);
  EXPECT_EQ(during.report["left_out"], json::array({0})) << during.report.dump();
  EXPECT_EQ(after.report["left_out"], json::array()) << after.report.dump();
  EXPECT_EQ(Count(during.dom, "left out (inactive)</span>"), 2u);  // the two starts, in the events list
  EXPECT_NE(during.dom.find("dotted ring: left out of this epoch (SSYNC, scripted)"), std::string::npos);
}

// Under ASYNC robot 0 looks in epoch 2, waits one epoch and moves over two:
// its starts of epochs 3 and 4 carry no look, the look's epoch (2), and
// whether it moves; the page rings it and says why.
TEST(ActivationPage, AnAsyncRobotMovingOnAStaleLookIsMarked) {
  const ScheduledRun run =
      RunForThePage("async_page", 7, "{model: async, schedule: scripted, max_delay_epochs: 2, cycles: [[2, 0, 1, 2]]}");
  PageOptions options;
  options.scenario = &run.scenario;
  const std::string& bytes_text = run.bytes;
  const json& data = run.data;
  EXPECT_EQ(data["activation"], json::parse(R"({"model": "async", "schedule": "scripted"})"));
  int64_t waiting_position = -1;
  int64_t moving_position = -1;
  for (const json& start : data["starts"]) {
    ASSERT_EQ(start.size(), 7u) << start.dump();
    const int epoch = data["maps"][start[2].get<size_t>()][0].get<int>();
    const bool looks = start[3] == 1;
    EXPECT_EQ(looks, start[1] != 0 || (epoch != 3 && epoch != 4)) << start.dump() << " epoch " << epoch;
    if (start[1] == 0 && epoch == 2) {
      EXPECT_EQ(start[5], 0) << "looked in epoch 2, its move starts in 3";
    }
    if (start[1] == 0 && epoch == 3) {
      EXPECT_EQ(start[4], 2);
      EXPECT_EQ(start[5], 1);
      moving_position = start[0].get<int64_t>();
    }
    if (start[1] == 0 && epoch == 2) waiting_position = start[0].get<int64_t>();
  }
  ASSERT_GE(waiting_position, 0);
  ASSERT_GT(moving_position, waiting_position);

  const fs::path path = WritePage(bytes_text, "async_stale_look", options);
  const Replay replay = ReadAll(bytes_text);
  auto round_at = [&](int64_t position) { return replay.rounds.at(static_cast<size_t>(position)).index; };
  const Loaded moving = Load(path, "#round=" + std::to_string(round_at(moving_position + 2)));
  ASSERT_TRUE(moving.report.is_object()) << moving.dom.substr(0, 2000);
  EXPECT_EQ(moving.report["left_out"], json::array({0})) << moving.report.dump();
  EXPECT_EQ(Count(moving.dom, "no look: moving on its look of epoch 2 (stale)</span>"), 2u);  // epochs 3 and 4
  EXPECT_NE(moving.dom.find("dotted ring: did not look this epoch (ASYNC, scripted)"), std::string::npos);
}

// ---- Replays the page cannot show whole ------------------------------------

TEST(ProblemPages, SayClearlyWhatIsWrong) {
  const std::string good = replay::testing::WriteSample().bytes;
  std::string newer = good;
  replay::testing::PutU16At(newer, 8, replay::kFormatVersion + 1);
  struct Case {
    std::string name, bytes, status, title, detail;
  };
  const std::vector<Case> cases = {
      {"empty", "", "empty", "Nothing to show", "The replay file is empty (0 bytes)"},
      {"truncated", good.substr(0, good.size() - 25), "truncated", "This replay is cut short",
       "cut short after 3 rounds"},
      {"newer", newer, "newer", "This replay is from a newer SyROF", "is newer than this reader"},
  };
  for (const Case& c : cases) {
    const Loaded loaded = Load(WritePage(c.bytes, "problem_" + c.name));

    SCOPED_TRACE(c.name);
    ASSERT_NE(loaded.dom.find("data-ready=\"1\""), std::string::npos);
    EXPECT_EQ(loaded.report["status"], c.status);
    std::smatch banner;
    ASSERT_TRUE(std::regex_search(loaded.dom, banner, std::regex(R"re(<div id="banner" class="([^"]*)"><h2>([^<]*)</h2><div>([^<]*)</div>)re")))
        << loaded.dom.substr(0, 3000);
    EXPECT_NE(banner[1].str().find(c.status), std::string::npos);
    EXPECT_EQ(banner[2].str(), c.title);
    EXPECT_NE(Unescape(banner[3].str()).find(c.detail), std::string::npos) << banner[3].str();
  }
}

}  // namespace
}  // namespace syrof::lab::view
