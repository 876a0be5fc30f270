// lab/view without a browser: the page's data is what the reader accepted,
// the template's markers are all filled, and the page refers to nothing
// outside itself.
#include "syrof/lab/view/view.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "replay_test_support.h"

namespace syrof::lab::view {
namespace {

using nlohmann::json;

json DataOf(const std::string& bytes, Page& page, const PageOptions& options = {}) {
  std::istringstream in(bytes);
  return json::parse(ReplayJson(in, "sample.replay", options, page));
}

TEST(ViewData, DecodesPayloadsWithTheMessageFormatAndCarriesInputs) {
  // The sample's robot i sends i bytes of 0xA0 + i: with a 2-byte format,
  // robot 2's payload decodes; robot 1's (1 byte) and robot 0's (none) do not.
  replay::Header header = replay::testing::SampleHeader();
  header.robots[1].inputs = {{"charge", 870}};
  message::MessageFormat format;
  format.none = false;
  format.fields = {{"charge", message::FieldType::kU16Be, 0}};
  format.length = 2;
  header.message = format;
  Page page;

  const json data = DataOf(replay::testing::Write(header, replay::testing::SampleRounds()).bytes, page);

  EXPECT_EQ(data["message"], "2 bytes: charge u16be");
  EXPECT_EQ(data["robots"][1]["inputs"], json::parse(R"([["charge", 870.0]])"));
  EXPECT_EQ(data["robots"][0]["inputs"], json::array());
  const json& shared = data["maps"][0][2];  // robots 0 and 1's map: members 0, 1
  const json& own = data["maps"][1][2];     // robot 2's: members 0, 2
  ASSERT_EQ(shared.size(), 2u) << data["maps"].dump();
  ASSERT_EQ(own.size(), 2u) << data["maps"].dump();
  EXPECT_EQ(shared[0][8], nullptr);
  EXPECT_EQ(shared[1][7], "a1");
  EXPECT_EQ(shared[1][8], nullptr);
  EXPECT_EQ(own[1][8], json::parse(R"([["charge", 41634]])"));  // 0xA2A2
}

TEST(ViewData, HoldsEveryEventMapAndRoundOfTheSample) {
  Page page;
  const json data = DataOf(replay::testing::WriteSample().bytes, page);

  EXPECT_TRUE(page.complete);
  EXPECT_EQ(data["status"], "complete");
  EXPECT_EQ(page.rounds, 3u);
  EXPECT_EQ(page.events, 6u);
  EXPECT_EQ(data["events"].size(), 6u);
  EXPECT_EQ(data["robots"].size(), 3u);
  EXPECT_EQ(data["anchors"].size(), 2u);
  EXPECT_EQ(data["rounds"]["index"], json::array({0, 1, 2}));  // deltas of 0, 1, 3
  // Robots 0 and 1 share one map; robot 2 has its own.
  EXPECT_EQ(data["maps"].size(), 2u);
  EXPECT_EQ(data["starts"], json::parse("[[0, 0, 0], [0, 1, 0], [2, 2, 1]]"));
  // The partition event names its partition, not a robot.
  EXPECT_EQ(data["events"][1], json::parse("[0, 10, -1, -1, 0, 0, 40000, 0]"));
  // Robot 0's x in mm, 1000, 1100, 1200, as deltas.
  EXPECT_EQ(data["frames"][0]["x"], json::array({1000, 100, 100}));
}

TEST(ViewData, DecimatesFramesButNeverEvents) {
  Page page;
  PageOptions options;
  options.max_robot_frames = 4;  // 3 robots x 3 rounds = 9 frames: keep every 3rd round
  const json data = DataOf(replay::testing::WriteSample().bytes, page, options);

  EXPECT_EQ(page.frame_stride, 3u);
  EXPECT_EQ(data["stride"], 3);
  EXPECT_EQ(data["frames"][0]["s"].size(), 1u);
  EXPECT_EQ(data["events"].size(), 6u);
}

// Frames are decimated as they are read, not after: robots x rounds of
// them held whole was gigabytes for a long run, or for a 1 MB hostile file
// (65,535 robots, 20,000 empty rounds: syrof view died of std::bad_alloc).
TEST(ViewData, HoldsOnlyTheFramesItKeeps) {
  replay::Header header = replay::testing::SampleHeader();
  header.robots.clear();
  for (uint16_t id = 0; id < 1000; ++id) header.robots.push_back({id, 0, 0.1f, {}});
  std::vector<replay::Round> rounds(3000);
  for (size_t index = 0; index < rounds.size(); ++index) {
    rounds[index].index = static_cast<uint32_t>(index + 1);
    rounds[index].time_ns = int64_t{50'000'000} * static_cast<int64_t>(index + 1);
  }
  const std::string bytes = replay::testing::Write(header, rounds).bytes;  // 75 KB
  PageOptions options;
  options.max_robot_frames = 1000;  // one round of the 3,000 is kept
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
  Page page;

  const json data = DataOf(bytes, page, options);

  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  EXPECT_TRUE(page.complete);
  EXPECT_EQ(page.frame_stride, 3000u);
  EXPECT_EQ(data["frames"][999]["s"].size(), 1u);
  // All 3,000,000 frames held would be 192 MB of columns (8 fields of 8 bytes).
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 64 * 1024) << "KiB of peak memory grown";
}

TEST(ViewData, SaysWhatIsWrongWithABadReplay) {
  const std::string good = replay::testing::WriteSample().bytes;
  std::string newer = good;
  replay::testing::PutU16At(newer, 8, replay::kFormatVersion + 1);
  Page page;

  EXPECT_EQ(DataOf("", page)["status"], "empty");
  EXPECT_FALSE(page.complete);
  const json truncated = DataOf(good.substr(0, good.size() - 25), page);
  EXPECT_EQ(truncated["status"], "truncated");
  EXPECT_EQ(page.rounds, 3u);
  EXPECT_NE(truncated["message"].get<std::string>().find("cut short after 3 rounds"), std::string::npos);
  const json newer_data = DataOf(newer, page);
  EXPECT_EQ(newer_data["status"], "newer");
  EXPECT_NE(newer_data["message"].get<std::string>().find("format version " + std::to_string(replay::kFormatVersion + 1) + " is newer"), std::string::npos);
  EXPECT_EQ(DataOf("not a replay", page)["status"], "invalid");
}

TEST(ViewPage, FillsEveryMarkerAndEscapesTheData) {
  replay::Header header = replay::testing::SampleHeader();
  header.scenario_name = "</script><b>x";
  const std::vector<replay::Round> rounds = replay::testing::SampleRounds();
  std::istringstream in(replay::testing::Write(header, rounds).bytes);

  const Page page = BuildPage(in, "a<b>.replay");

  for (const char* marker : {"@TITLE@", "/*@CSS@*/", "@DATA@", "/*@JS@*/"}) {
    EXPECT_EQ(page.html.find(marker), std::string::npos) << marker;
  }
  EXPECT_EQ(page.html.find("</script><b>x"), std::string::npos);
  EXPECT_NE(page.html.find("<\\/script><b>x"), std::string::npos);
  EXPECT_NE(page.html.find("<title>SyROF viewer: a&lt;b&gt;.replay</title>"), std::string::npos);
  EXPECT_NE(page.html.find("'use strict'"), std::string::npos);  // the script is inside
}

TEST(ViewPage, RefersToNothingOutsideItself) {
  std::istringstream in(replay::testing::WriteSample().bytes);

  const Page page = BuildPage(in, "sample.replay");

  // No external script, style sheet, image, font or fetch.
  EXPECT_FALSE(std::regex_search(page.html, std::regex(R"((src|href)\s*=\s*["']?[a-z]+:)", std::regex::icase)));
  EXPECT_FALSE(std::regex_search(page.html, std::regex(R"(https?://)", std::regex::icase)));
  EXPECT_EQ(page.html.find("fetch("), std::string::npos);
  EXPECT_EQ(page.html.find("XMLHttpRequest"), std::string::npos);
  EXPECT_EQ(page.html.find("@import"), std::string::npos);
  EXPECT_NE(page.html.find("default-src 'none'"), std::string::npos);  // and the browser enforces it
}

}  // namespace
}  // namespace syrof::lab::view
