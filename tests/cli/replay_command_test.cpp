// `syrof replay` (cli/replay_command.cpp) on small files.
#include "replay_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "replay_test_support.h"
#include "syrof/lab/metrics/metrics.h"
#include "view_command.h"

namespace syrof::cli {
namespace {

namespace replay = lab::replay;

// Writes `bytes` to a file of its own under the test temp dir, so parallel
// test processes never share one.
std::string WriteFile(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + "syrof_replay_command_" + name + ".replay";
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
  return path;
}

struct Output {
  int status = -1;
  std::string out;
  std::string err;
};

Output RunCommand(const ReplayOptions& options) {
  std::ostringstream out;
  std::ostringstream err;
  Output result;
  result.status = RunReplayCommand(options, out, err);
  result.out = out.str();
  result.err = err.str();
  return result;
}

const char* const kHeaderText =
    "SyROF replay, format version 5\n"
    "scenario: three_robots\n"
    "app: builtin:idle\n"
    "seed: 42\n"
    "radio round: 50000000 ns\n"
    "arena: 4 x 3 m\n"
    "robots: 3\n"
    "  robot 0: omni, body radius 0.1 m\n"
    "  robot 1: omni, body radius 0.1 m\n"
    "  robot 2: rover, body radius 0.12 m\n";

const char* const kLegend =
    "frames: time robot ID PRESENCE member|joining PHASE MODE epoch E "
    "true (x m, y m, heading rad) est (x m, y m, heading rad)\n";

std::string SampleFile(const std::string& name) {
  return WriteFile(name, replay::testing::WriteSample().bytes);
}

TEST(ReplayCommand, PrintsHeaderFramesAndEvents) {
  const ReplayOptions options{.file = SampleFile("everything")};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 0) << output.err;
  EXPECT_EQ(output.err, "");
  EXPECT_EQ(output.out,
            std::string(kHeaderText) + kLegend +
                "round 0 t=0.050000000s\n"
                "  0.050000000s robot 0 RUNNING member PROGRESS COOPERATIVE epoch 1 true (1.000, 1.000, 0.250) est (1.010, 0.980, 0.260)\n"
                "  0.050000000s robot 1 RUNNING member PROGRESS COOPERATIVE epoch 1 true (2.000, 1.000, 0.250) est (2.010, 0.980, 0.260)\n"
                "  0.050000000s robot 2 ABSENT member PROGRESS COOPERATIVE epoch 0 true (0.000, 0.000, 0.000) est (0.000, 0.000, 0.000)\n"
                "  0.050000000s event EPOCH_START robot 0 epoch 1 mode COOPERATIVE\n"
                "  0.040000000s event PARTITION_START partition 0\n"
                "  0.050000000s map robot 0 epoch 1 COOPERATIVE members 0 1\n"
                "  0.050000000s map robot 1 epoch 1 COOPERATIVE members 0 1\n"
                "round 1 t=0.100000000s\n"
                "  0.100000000s robot 0 RUNNING member WAIT COOPERATIVE epoch 1 true (1.100, 1.000, 0.250) est (1.110, 0.980, 0.260)\n"
                "  0.100000000s robot 1 CRASHED member PROGRESS COOPERATIVE epoch 1 true (2.000, 1.000, 0.250) est (2.010, 0.980, 0.260)\n"
                "  0.100000000s robot 2 RUNNING joining PROGRESS AUTONOMOUS epoch 0 true (3.000, 2.000, 0.250) est (3.010, 1.980, 0.260)\n"
                "  0.090000000s event COLLISION robot 0 other 1 epoch 1 mode COOPERATIVE\n"
                "  0.095000000s event CRASH robot 1 epoch 1 mode COOPERATIVE\n"
                "  0.100000000s event JOIN robot 2 epoch 0 mode AUTONOMOUS\n"
                "round 3 t=0.200000000s\n"
                "  0.200000000s robot 0 RUNNING member VOTE COOPERATIVE epoch 2 true (1.200, 1.000, 0.250) est (1.210, 0.980, 0.260)\n"
                "  0.200000000s robot 2 RUNNING member PROGRESS AUTONOMOUS epoch 2 true (3.000, 2.100, 0.250) est (3.010, 2.080, 0.260)\n"
                "  0.200000000s event MEMBER_REMOVED robot 0 other 1 epoch 2 mode COOPERATIVE\n"
                "  0.200000000s map robot 2 epoch 2 AUTONOMOUS members 0 2\n");
}

// A message assignment's run: each robot's private inputs on its line, the
// message format under them (text), and both in the jsonl header.
TEST(ReplayCommand, ShowsEachRobotsInputsAndTheMessageFormat) {
  replay::Header header = replay::testing::SampleHeader();
  header.robots[0].inputs = {{"charge", 866}, {"colour", 2}};
  header.robots[1].inputs = {{"charge", 38.5}};
  lab::message::MessageFormat format;
  format.none = false;
  format.fields = {{"charge", lab::message::FieldType::kU16Be, 0}};
  format.length = 2;
  header.message = format;
  const std::string path =
      WriteFile("inputs", replay::testing::Write(header, replay::testing::SampleRounds()).bytes);

  const Output text = RunCommand({.file = path, .summary = true});
  EXPECT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("  robot 0: omni, body radius 0.1 m, inputs: charge=866, colour=2\n"
                          "  robot 1: omni, body radius 0.1 m, inputs: charge=38.5\n"
                          "  robot 2: rover, body radius 0.12 m\n"
                          "message format: 2 bytes: charge u16be\n"),
            std::string::npos)
      << text.out;

  const Output json = RunCommand({.file = path, .format = "jsonl"});
  EXPECT_EQ(json.status, 0) << json.err;
  const nlohmann::json first = nlohmann::json::parse(json.out.substr(0, json.out.find('\n')));
  EXPECT_EQ(first["message"], "2 bytes: charge u16be");
  EXPECT_EQ(first["robots"][0]["inputs"]["colour"], 2.0);
  EXPECT_EQ(first["robots"][1]["inputs"]["charge"], 38.5);
  EXPECT_TRUE(first["robots"][2]["inputs"].empty());
}

TEST(ReplayCommand, FiltersByRoundAndRobot) {
  const ReplayOptions options{.file = SampleFile("filters"), .round = 1, .robot = 1};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 0) << output.err;
  EXPECT_EQ(output.out,
            std::string(kHeaderText) + kLegend +
                "round 1 t=0.100000000s\n"
                "  0.100000000s robot 1 CRASHED member PROGRESS COOPERATIVE epoch 1 true (2.000, 1.000, 0.250) est (2.010, 0.980, 0.260)\n"
                "  0.090000000s event COLLISION robot 0 other 1 epoch 1 mode COOPERATIVE\n"
                "  0.095000000s event CRASH robot 1 epoch 1 mode COOPERATIVE\n");
}

TEST(ReplayCommand, EventsOnlySkipsFramesAndQuietRounds) {
  const ReplayOptions options{.file = SampleFile("events_only"), .robot = 2, .events_only = true};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 0) << output.err;
  EXPECT_EQ(output.out, std::string(kHeaderText) +
                            "round 1 t=0.100000000s\n"
                            "  0.100000000s event JOIN robot 2 epoch 0 mode AUTONOMOUS\n");
}

TEST(ReplayCommand, SummaryCountsEventsByKind) {
  const ReplayOptions options{.file = SampleFile("summary"), .summary = true};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 0) << output.err;
  EXPECT_EQ(output.out, std::string(kHeaderText) +
                            "rounds: 3 (index 0 .. 3, t=0.050000000s .. 0.200000000s)\n"
                            "frames: 8\n"
                            "events: 6\n"
                            "  EPOCH_START: 1\n"
                            "  MEMBER_REMOVED: 1\n"
                            "  MEMBER_JOINED: 0\n"
                            "  BECAME_JOINER: 0\n"
                            "  COLLISION: 1\n"
                            "  WALL_CONTACT: 0\n"
                            "  CRASH: 1\n"
                            "  PAUSE: 0\n"
                            "  RESUME: 0\n"
                            "  JOIN: 1\n"
                            "  PARTITION_START: 1\n"
                            "  PARTITION_END: 0\n"
      "  APP_FAULT: 0\n"
      "  INVALID_COMMAND: 0\n"
      "  PAYLOAD_REFUSED: 0\n"
      "  SAFETY_INTERVENTION: 0\n"
      "  JOIN_WAIT: 0\n"
                            "  BEACON_LOST: 0\n"
                            "file: complete\n");
}

TEST(ReplayCommand, SummaryOfTruncatedFileSaysSoAndFails) {
  const replay::testing::Written written = replay::testing::WriteSample();
  const ReplayOptions options{.file = WriteFile("truncated", written.bytes.substr(0, written.round_ends[1] + 5)),
                              .summary = true};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 2);
  EXPECT_NE(output.out.find("rounds: 2 (index 0 .. 1,"), std::string::npos) << output.out;
  EXPECT_NE(output.out.find("file: truncated (offset "), std::string::npos) << output.out;
  EXPECT_NE(output.err.find("truncated"), std::string::npos) << output.err;
}

TEST(ReplayCommand, DumpOfDamagedFilePrintsWhatItCanThenFails) {
  const replay::testing::Written written = replay::testing::WriteSample();
  std::string bytes = written.bytes;
  bytes[written.round_ends[0] + 30] ^= 0x04;
  const ReplayOptions options{.file = WriteFile("damaged", bytes), .events_only = true};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 2);
  EXPECT_NE(output.out.find("EPOCH_START"), std::string::npos) << output.out;
  EXPECT_EQ(output.out.find("round 1"), std::string::npos) << output.out;
  EXPECT_NE(output.err.find("checksum"), std::string::npos) << output.err;
}

TEST(ReplayCommand, BadInputReturnsTwoWithAMessage) {
  const std::string sample = SampleFile("bad_input");
  const std::vector<std::pair<ReplayOptions, std::string>> cases = {
      {{.file = ::testing::TempDir() + "syrof_replay_command_missing.replay"}, "cannot open"},
      {{.file = ::testing::TempDir() + "syrof_replay_command_missing.replay"}, "No such file or directory"},
      {{.file = ::testing::TempDir()}, "is a folder, not a replay file"},
      {{.file = WriteFile("not_replay", "hello, world")}, "not a SyROF replay file"},
      {{.file = sample, .robot = 7}, "no robot 7 in this replay"},
      {{.file = sample, .round = 2}, "no round 2 in this replay"},
  };
  for (const auto& [options, message] : cases) {
    const Output output = RunCommand(options);

    EXPECT_EQ(output.status, 2) << message;
    EXPECT_NE(output.err.find(message), std::string::npos) << output.err;
    EXPECT_EQ(output.err.rfind("syrof replay: ", 0), 0u) << output.err;
  }
}

TEST(ReplayCommand, SetupParsesTheCommandLine) {
  CLI::App app("syrof");
  ReplayOptions options;
  CLI::App* command = SetupReplayCommand(app, options);

  app.parse("replay run.replay --round 12 --robot 3 --events-only", false);

  EXPECT_TRUE(command->parsed());
  EXPECT_EQ(options.file, "run.replay");
  EXPECT_EQ(options.round, 12u);
  EXPECT_EQ(options.robot, 3);
  EXPECT_TRUE(options.events_only);
  EXPECT_FALSE(options.summary);
}

TEST(ReplayCommand, SetupRefusesSummaryWithFilters) {
  CLI::App app("syrof");
  ReplayOptions options;
  SetupReplayCommand(app, options);

  EXPECT_THROW(app.parse("replay run.replay --summary --robot 3", false), CLI::ExcludesError);
  EXPECT_THROW(app.parse("replay run.replay --robot 70000", false), CLI::ConversionError);
}

TEST(ReplayExport, CsvFramesHaveOneRowPerFrameWithTheDocumentedColumns) {
  const ReplayOptions options{.file = SampleFile("csv_frames"), .format = "csv"};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 0) << output.err;
  std::istringstream lines(output.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line,
            "round,time_s,robot,presence,status,phase,mode,epoch,true_x_m,true_y_m,true_heading_rad,est_x_m,est_y_m,"
            "est_heading_rad");
  std::getline(lines, line);
  EXPECT_EQ(line, "0,0.050000000,0,RUNNING,member,PROGRESS,COOPERATIVE,1,1,1,0.25,1.01,0.98,0.26");
  size_t rows = 1;
  while (std::getline(lines, line)) ++rows;
  EXPECT_EQ(rows, 8u);  // the sample's frames
}

TEST(ReplayExport, CsvEventsAndMaps) {
  const std::string file = SampleFile("csv_events");

  const Output events = RunCommand(ReplayOptions{.file = file, .format = "csv", .table = "events"});
  const Output maps = RunCommand(ReplayOptions{.file = file, .robot = 2, .format = "csv", .table = "maps"});

  EXPECT_EQ(events.status, 0) << events.err;
  EXPECT_EQ(events.out,
            "round,time_s,kind,robot,other,partition,epoch,mode\n"
            "0,0.050000000,EPOCH_START,0,,,1,COOPERATIVE\n"
            "0,0.040000000,PARTITION_START,,,0,0,COOPERATIVE\n"
            "1,0.090000000,COLLISION,0,1,,1,COOPERATIVE\n"
            "1,0.095000000,CRASH,1,,,1,COOPERATIVE\n"
            "1,0.100000000,JOIN,2,,,0,AUTONOMOUS\n"
            "3,0.200000000,MEMBER_REMOVED,0,1,,2,COOPERATIVE\n");
  EXPECT_EQ(maps.status, 0) << maps.err;
  EXPECT_EQ(maps.out,
            "round,time_s,robot,epoch,mode,member,member_phase,x_m,y_m,heading_rad,vx_m_s,vy_m_s,payload_hex\n"
            "3,0.200000000,2,2,AUTONOMOUS,0,PROGRESS,1.000,0.000,0.250,0.000,0.000,\n"
            "3,0.200000000,2,2,AUTONOMOUS,2,PROGRESS,1.200,-0.010,0.252,0.002,0.000,a2a2\n");
}

TEST(ReplayExport, JsonLinesHoldEveryRecordAsOneObjectPerLine) {
  const ReplayOptions options{.file = SampleFile("jsonl"), .format = "jsonl"};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 0) << output.err;
  std::istringstream lines(output.out);
  std::string line;
  std::map<std::string, int> types;
  while (std::getline(lines, line)) {
    const nlohmann::json record = nlohmann::json::parse(line);
    ++types[record["type"].get<std::string>()];
  }
  EXPECT_EQ(types, (std::map<std::string, int>{{"header", 1}, {"frame", 8}, {"event", 6}, {"map", 3}}));
  EXPECT_NE(output.out.find(R"({"type":"map","round":0,"time_ns":50000000,"robot":1,"epoch":1,"mode":"COOPERATIVE")"),
            std::string::npos);
  EXPECT_NE(output.out.find(R"("kind":"PARTITION_START","robot":null,"other":null,"partition":0)"), std::string::npos);
}

TEST(ReplayExport, TruncatedFileExportsWhatItHoldsThenFails) {
  const std::string bytes = replay::testing::WriteSample().bytes;
  const ReplayOptions options{.file = WriteFile("cut.replay", bytes.substr(0, bytes.size() - 25)), .format = "jsonl"};

  const Output output = RunCommand(options);

  EXPECT_EQ(output.status, 2);
  EXPECT_NE(output.err.find("file ends after 3 rounds without the end marker"), std::string::npos) << output.err;
  EXPECT_NE(output.out.find(R"("kind":"MEMBER_REMOVED")"), std::string::npos);
}

std::string ReadBack(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

TEST(ViewCommand, WritesTheSelfContainedPage) {
  const ViewOptions options{.file = SampleFile("view"), .output = WriteFile("view_out.html", "")};
  std::ostringstream out, err;

  const int status = RunViewCommand(options, out, err);

  EXPECT_EQ(status, 0) << err.str();
  EXPECT_NE(out.str().find("wrote " + options.output + " (3 rounds, 6 events"), std::string::npos) << out.str();
  const std::string page = ReadBack(options.output);
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("\"scenario\":\"three_robots\""), std::string::npos);
}

TEST(ViewCommand, ABadReplayStillGetsAPageThatSaysWhyAndExitsTwo) {
  const std::string bytes = replay::testing::WriteSample().bytes;
  const ViewOptions options{.file = WriteFile("view_cut.replay", bytes.substr(0, bytes.size() - 25))};
  std::ostringstream out, err;

  const int status = RunViewCommand(options, out, err);

  EXPECT_EQ(status, 2);
  EXPECT_NE(err.str().find("file ends after 3 rounds without the end marker"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("wrote " + options.file + ".html"), std::string::npos) << err.str();
  EXPECT_NE(ReadBack(options.file + ".html").find("\"status\":\"truncated\""), std::string::npos);
  EXPECT_EQ(RunViewCommand(ViewOptions{.file = "/nonexistent/replay"}, out, err), 2);
}

TEST(ViewCommand, TheVerdictComesFromTheRunsMetricsBesideTheReplay) {
  // A run folder: its replay (the sample, seed 42) and its metrics.json.
  const std::filesystem::path run = std::filesystem::path(::testing::TempDir()) / "syrof_view_verdict_run";
  std::filesystem::create_directories(run);
  std::ofstream(run / "replay", std::ios::binary) << replay::testing::WriteSample().bytes;
  lab::metrics::Metrics metrics;
  metrics.seed = 42;
  metrics.goal.app = "builtin:idle";
  metrics.goal.reached = true;
  metrics.collisions.count = 1;
  metrics.collisions.pairs = {{.time_ns = 2'500'000'000, .a = 0, .b = 2}};
  std::ofstream(run / "metrics.json", std::ios::binary) << lab::metrics::ToJson(metrics);
  std::ostringstream out, err;

  const int status = RunViewCommand(ViewOptions{.file = (run / "replay").string()}, out, err);

  EXPECT_EQ(status, 0) << err.str();
  EXPECT_NE(ReadBack((run / "replay.html").string()).find("BROKEN: 1 collision, the first robots 0 and 2 at 2.50 s"),
            std::string::npos);
}

TEST(ViewCommand, AMalformedMetricsFileIsNamedWithItsField) {
  const std::string metrics = WriteFile("bad_metrics", R"({"seed": 42, "goal": {"app": "x", "reached": 1}})");
  std::ostringstream out, err;

  const int status = RunViewCommand(ViewOptions{.file = SampleFile("view_bad_metrics"), .metrics = metrics}, out, err);

  EXPECT_EQ(status, 2);
  EXPECT_NE(err.str().find(metrics + ": goal.reached: expected true or false"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace syrof::cli
