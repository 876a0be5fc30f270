// `syrof run`, `validate` and `apps` as a user meets them: exit codes, messages,
// the files written, and identical bytes for identical runs.
#include "run_command.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <memory>
#include <fstream>
#include <sstream>
#include <string>

#include "apps_command.h"
#include "validate_command.h"
#include "cli_test_support.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::Outcome;
using testing::ReadFile;

const std::string kScenarios = SYROF_SCENARIOS_DIR;

fs::path RunTempDir(const std::string& name) {
  const fs::path dir = FreshDir("syrof_cli_test_", name);
  return dir;
}

Outcome RunWith(RunOptions options) {
  std::ostringstream out, err;
  const int status = RunRunCommand(options, out, err, false);
  return Outcome{status, out.str(), err.str()};
}

TEST(RunCommandTest, WritesMetricsAndReplayAndPrintsTheSummary) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.duration_s = 5;
  options.out_dir = RunTempDir("summary").string();

  const Outcome outcome = RunWith(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("common knowledge"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("collisions"), std::string::npos);
  const nlohmann::json metrics = nlohmann::json::parse(ReadFile(fs::path(options.out_dir) / "metrics.json"));
  // The safety layer and app-level agreement are summarised from metrics.json.
  EXPECT_NE(outcome.out.find(fmt::format("safety            {} interventions on {} robots, {} precautions, {} join waits",
                                         metrics["safety"]["interventions"].get<int64_t>(),
                                         metrics["safety"]["robots_involved"].get<int64_t>(),
                                         metrics["safety"]["precautions"].get<int64_t>(),
                                         metrics["safety"]["join_waits"].get<int64_t>())),
            std::string::npos)
      << outcome.out;
  EXPECT_NE(outcome.out.find(fmt::format("agreement         the app's global state agreed in {} of {} COOPERATIVE epochs",
                                         metrics["agreement"]["agreed_epochs"].get<int64_t>(),
                                         metrics["agreement"]["cooperative_epochs"].get<int64_t>())),
            std::string::npos)
      << outcome.out;
  EXPECT_DOUBLE_EQ(metrics["sim_seconds"].get<double>(), 5.0);
  EXPECT_GT(metrics["wall_seconds"].get<double>(), 0.0);
  EXPECT_GT(fs::file_size(fs::path(options.out_dir) / "replay"), 100u);
}

// Real clocks: the summary gives the start skew in milliseconds too, and a
// round-phase line (only when the scenario has a clocks section).
TEST(RunCommandTest, WithClocksTheSummaryGivesTheRoundPhase) {
  RunOptions options;
  options.scenario_path = kScenarios + "/clocks_circle.yaml";
  options.duration_s = 10;
  options.out_dir = RunTempDir("clocks").string();
  const Outcome clocked = RunWith(options);
  ASSERT_EQ(clocked.status, 0) << clocked.err;
  const nlohmann::json metrics = nlohmann::json::parse(ReadFile(fs::path(options.out_dir) / "metrics.json"));
  EXPECT_NE(clocked.out.find(fmt::format("start skew max {} rounds ({:.1f} ms)",
                                         metrics["synchrony"]["max_start_skew_rounds"].get<int64_t>(),
                                         metrics["synchrony"]["max_start_skew_ms"].get<double>())),
            std::string::npos)
      << clocked.out;
  EXPECT_NE(clocked.out.find(fmt::format("round phase       aligned within 1.0 ms after {:.2f} s",
                                         metrics["round_phase"]["converged_s"].get<double>())),
            std::string::npos)
      << clocked.out;

  options.scenario_path = kScenarios + "/demo_circle.yaml";
  options.out_dir = RunTempDir("no_clocks").string();
  const Outcome shared = RunWith(options);
  ASSERT_EQ(shared.status, 0) << shared.err;
  EXPECT_EQ(shared.out.find("round phase"), std::string::npos) << shared.out;
}

// Before, a replay writer failure went unnoticed: the run printed the path
// of a cut-short file and exited 0. /dev/full fails every write (ENOSPC).
TEST(RunCommandTest, AReplayWriterFailureExitsOneWithTheReason) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this host";
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.duration_s = 2;
  options.out_dir = RunTempDir("full_disk").string();
  fs::create_directories(options.out_dir);
  fs::create_symlink("/dev/full", fs::path(options.out_dir) / "replay");

  const Outcome outcome = RunWith(options);

  EXPECT_EQ(outcome.status, 1);
  EXPECT_NE(outcome.err.find("the replay " + (fs::path(options.out_dir) / "replay").string() + " is incomplete"),
            std::string::npos)
      << outcome.err;
  EXPECT_NE(outcome.err.find("the output stream failed"), std::string::npos) << outcome.err;
  EXPECT_EQ(outcome.out.find("outputs"), std::string::npos) << outcome.out;  // no summary naming the file
}

TEST(RunCommandTest, HtmlWritesTheReplaysPageNextToIt) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.duration_s = 2;
  options.out_dir = RunTempDir("html").string();
  options.html = true;

  const Outcome outcome = RunWith(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  const std::string page = ReadFile(fs::path(options.out_dir) / "replay.html");
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("\"status\":\"complete\""), std::string::npos);
  EXPECT_NE(outcome.out.find((fs::path(options.out_dir) / "replay.html").string()), std::string::npos);
}

TEST(RunCommandTest, ReproducibleRunsWriteIdenticalBytes) {
  RunOptions first;
  first.scenario_path = kScenarios + "/demo_circle.yaml";
  first.duration_s = 6;
  first.reproducible = true;
  first.quiet = true;
  first.out_dir = RunTempDir("repro_a").string();
  RunOptions second = first;
  second.out_dir = RunTempDir("repro_b").string();

  ASSERT_EQ(RunWith(first).status, 0);
  ASSERT_EQ(RunWith(second).status, 0);

  EXPECT_EQ(ReadFile(fs::path(first.out_dir) / "metrics.json"), ReadFile(fs::path(second.out_dir) / "metrics.json"));
  EXPECT_EQ(ReadFile(fs::path(first.out_dir) / "replay"), ReadFile(fs::path(second.out_dir) / "replay"));
}

// --realtime paces the run to the wall clock, and --live (which implies it)
// feeds the live page too: neither changes a byte of the outputs.
TEST(RunCommandTest, RealtimeAndLiveRunsWriteTheSameBytesAsAnUnpacedRun) {
  RunOptions fast;
  fast.scenario_path = kScenarios + "/demo_circle.yaml";
  fast.duration_s = 2;
  fast.reproducible = true;
  fast.quiet = true;
  fast.out_dir = RunTempDir("realtime_fast").string();
  RunOptions paced = fast;
  paced.realtime = true;
  paced.out_dir = RunTempDir("realtime_paced").string();
  RunOptions live = fast;
  live.live.address = "127.0.0.1:0";
  live.live.linger_s = 0;
  live.out_dir = RunTempDir("realtime_live").string();

  ASSERT_EQ(RunWith(fast).status, 0);
  const auto started = std::chrono::steady_clock::now();
  ASSERT_EQ(RunWith(paced).status, 0);
  const double paced_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const Outcome live_outcome = RunWith(live);
  ASSERT_EQ(live_outcome.status, 0) << live_outcome.err;

  EXPECT_GE(paced_s, 1.95);  // 2 s of world time took 2 s
  EXPECT_NE(live_outcome.out.find("live page: http://127.0.0.1:"), std::string::npos) << live_outcome.out;
  for (const RunOptions* run : {&paced, &live}) {
    EXPECT_TRUE(ReadFile(fs::path(fast.out_dir) / "metrics.json") == ReadFile(fs::path(run->out_dir) / "metrics.json"));
    EXPECT_TRUE(ReadFile(fs::path(fast.out_dir) / "replay") == ReadFile(fs::path(run->out_dir) / "replay"));
  }
}

TEST(RunCommandTest, ALiveAddressThatIsNotOneIsBadInput) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.quiet = true;
  options.out_dir = RunTempDir("live_bad").string();
  for (const std::string address : {"localhost:http", "127.0.0.1:70000", "203.0.113.9:0"}) {
    options.live.address = address;
    const Outcome outcome = RunWith(options);
    EXPECT_EQ(outcome.status, 2) << address;
    EXPECT_NE(outcome.err.find("--live"), std::string::npos) << outcome.err;
  }
}

// --threads: the same standard output and files as one thread (30 robots,
// so robots do run side by side); only the output folder's name differs.
TEST(RunCommandTest, ThreadsWriteAndPrintTheSameBytes) {
  RunOptions one;
  one.scenario_path = kScenarios + "/demo_circle.yaml";
  one.robots = 30;
  one.duration_s = 4;
  one.reproducible = true;
  one.out_dir = RunTempDir("threads_1").string();
  RunOptions two = one;
  two.threads = 2;
  two.out_dir = RunTempDir("threads_2").string();

  const Outcome first = RunWith(one);
  const Outcome second = RunWith(two);

  ASSERT_EQ(first.status, 0) << first.err;
  ASSERT_EQ(second.status, 0) << second.err;
  std::string second_out = second.out;
  for (size_t at = second_out.find(two.out_dir); at != std::string::npos; at = second_out.find(two.out_dir)) {
    second_out.replace(at, two.out_dir.size(), one.out_dir);
  }
  EXPECT_EQ(second_out, first.out);
  EXPECT_EQ(second.err, first.err);
  EXPECT_TRUE(ReadFile(fs::path(one.out_dir) / "metrics.json") == ReadFile(fs::path(two.out_dir) / "metrics.json"));
  EXPECT_TRUE(ReadFile(fs::path(one.out_dir) / "replay") == ReadFile(fs::path(two.out_dir) / "replay"));
}

TEST(RunCommandTest, OverridesReachTheRun) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.seed = 99;
  options.robots = 3;
  options.duration_s = 2;
  options.app = "builtin:circle";
  options.quiet = true;
  options.no_replay = true;
  options.out_dir = RunTempDir("overrides").string();

  ASSERT_EQ(RunWith(options).status, 0);

  const nlohmann::json metrics = nlohmann::json::parse(ReadFile(fs::path(options.out_dir) / "metrics.json"));
  EXPECT_EQ(metrics["seed"], 99);
  EXPECT_EQ(metrics["robots"], 3);
  EXPECT_EQ(metrics["app"]["source"], "builtin:circle");
  EXPECT_EQ(metrics["app"]["name"], "circle");
  EXPECT_FALSE(fs::exists(fs::path(options.out_dir) / "replay"));
}

TEST(RunCommandTest, MissingScenarioIsBadInputWithItsName) {
  RunOptions options;
  options.scenario_path = "/nonexistent/scenario.yaml";

  const Outcome outcome = RunWith(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("/nonexistent/scenario.yaml"), std::string::npos) << outcome.err;
}

// `syrof grade` prints a failed public test's replay as
// `syrof run gather/scenarios/gather_6.yaml --app build/lib...` (no absolute
// path: the student reads it on their own machine). From a student's
// project folder, where no gather/ is, that names the assignment's own file.
TEST(RunCommandTest, TheGradersReplayPathNamesTheAssignmentsFileFromAnyFolder) {
  RunOptions options;
  options.scenario_path = "gather/scenarios/gather_6.yaml";
  ASSERT_FALSE(fs::exists(options.scenario_path)) << "the test's working folder must not hold gather/";
  options.out_dir = RunTempDir("assignment_file").string();

  const Outcome outcome = RunWith(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  const std::string own = (fs::path(SYROF_ASSIGNMENTS_DIR) / "gather/scenarios/gather_6.yaml").string();
  EXPECT_EQ(outcome.err, "syrof run: gather/scenarios/gather_6.yaml is the assignment's file " + own + "\n");
  const nlohmann::json metrics = nlohmann::json::parse(ReadFile(fs::path(options.out_dir) / "metrics.json"));
  EXPECT_EQ(metrics["scenario"], "gather_6");

  // Only a file inside the assignment's folder, and only when the path
  // itself names nothing: these stay the loader's "cannot open".
  for (const char* path : {"gather/../../etc/passwd", "gather/scenarios/none.yaml", "gather", "nosuch/scenarios/x.yaml"}) {
    options.scenario_path = path;
    const Outcome missing = RunWith(options);
    EXPECT_EQ(missing.status, 2) << path;
    EXPECT_NE(missing.err.find(std::string(path) + ": cannot open"), std::string::npos) << missing.err;
  }
}

TEST(RunCommandTest, InvalidScenarioNamesFileLineAndColumn) {
  const fs::path dir = RunTempDir("invalid");
  fs::create_directories(dir);
  const fs::path path = dir / "bad.yaml";
  std::ofstream(path) << "robots: {count: 3}\napp: builtin:idle\nchanel: {loss: 0.1}\n";
  RunOptions options;
  options.scenario_path = path.string();

  const Outcome outcome = RunWith(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("bad.yaml:3:1"), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find("channel"), std::string::npos) << outcome.err;  // the suggestion
}

TEST(RunCommandTest, UnknownAppOverrideIsBadInput) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.app = "builtin:dance";

  const Outcome outcome = RunWith(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("dance"), std::string::npos) << outcome.err;
}

// ---- An app that misbehaves ---------------------------------------------------

// Holds still; robot 1's newRound crashes at epoch 2, and robot 0's first
// newRound returns an unknown command kind.
class MisbehavingApp final : public app::App {
 public:
  explicit MisbehavingApp(uint16_t id) : id_(id) {}
  const char* name() const override { return "misbehaving"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform&, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t&, uint32_t) override {
    if (id_ == 1 && ldmap.epoch == 2) return app::CallStatus::Fault(app::Verdict::kTimeout, "cpu budget");
    if (id_ == 0 && ldmap.epoch == 1) command.kind = 42;
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }

 private:
  uint16_t id_;
};

RunOptions MisbehavingRun(const std::string& name) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.robots = 4;
  options.duration_s = 5;
  options.out_dir = RunTempDir(name).string();
  options.apps.factory = [](uint16_t id) { return std::make_unique<MisbehavingApp>(id); };
  options.apps.source = "test:misbehaving";
  return options;
}

TEST(RunCommandTest, StrictExitsWithThreeAfterWritingTheOutputsWhenTheAppMisbehaved) {
  RunOptions options = MisbehavingRun("strict_fault");
  options.strict = true;

  const Outcome outcome = RunWith(options);

  EXPECT_EQ(outcome.status, 3) << outcome.err;
  const nlohmann::json metrics = nlohmann::json::parse(ReadFile(fs::path(options.out_dir) / "metrics.json"));
  EXPECT_EQ(metrics["app"]["source"], "test:misbehaving");
  ASSERT_EQ(metrics["app"]["faults"].size(), 1u);
  EXPECT_EQ(metrics["app"]["faults"][0]["robot"], 1);
  EXPECT_EQ(metrics["app"]["invalid_commands"]["count"], 1);
  EXPECT_GT(fs::file_size(fs::path(options.out_dir) / "replay"), 100u);
}

TEST(RunCommandTest, TheSummaryWarnsAndNamesTheFirstOfEachMisbehaviour) {
  const Outcome outcome = RunWith(MisbehavingRun("summary_fault"));

  EXPECT_EQ(outcome.status, 0) << outcome.err;  // not --strict
  EXPECT_NE(outcome.out.find("misbehaving: WARNING: the app misbehaved"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("1 in all; first robot 1, new_round of epoch 2 at "), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("timeout (cpu budget)"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("1 in all, each replaced by STOP; first robot 0, epoch 1: kind 42 is unknown"),
            std::string::npos)
      << outcome.out;
  EXPECT_EQ(outcome.out.find("refused payloads"), std::string::npos) << outcome.out;  // none happened
}

TEST(RunCommandTest, AQuietRunStillWarnsOnStandardError) {
  RunOptions options = MisbehavingRun("quiet_fault");
  options.quiet = true;

  const Outcome outcome = RunWith(options);

  EXPECT_EQ(outcome.status, 0);
  EXPECT_EQ(outcome.out, "");
  EXPECT_NE(outcome.err.find("warning: the app misbehaved"), std::string::npos) << outcome.err;
}

TEST(RunCommandTest, StrictExitsWithZeroWhenTheAppBehaved) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.duration_s = 3;
  options.strict = true;
  options.out_dir = RunTempDir("strict_clean").string();

  const Outcome outcome = RunWith(options);

  EXPECT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("idle: no faults, no invalid commands, no refused payloads"), std::string::npos)
      << outcome.out;
}

TEST(RunCommandTest, StrictIsACommandLineFlag) {
  CLI::App app;
  RunOptions options;
  SetupRunCommand(app, options);

  app.parse("run some.yaml --strict", false);

  EXPECT_TRUE(options.strict);
  EXPECT_FALSE(options.apps.factory);  // only code sets a factory
}

TEST(ValidateCommandTest, PrintsTheResolvedScenario) {
  ValidateOptions options;
  options.scenario_path = kScenarios + "/rovers.yaml";
  std::ostringstream out, err;

  ASSERT_EQ(RunValidateCommand(options, out, err), 0) << err.str();

  EXPECT_NE(out.str().find("rover"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find(": ok"), std::string::npos);
}

TEST(AppsCommandTest, ListsEveryBuiltinApp) {
  std::ostringstream out;

  ASSERT_EQ(RunAppsCommand(AppsOptions{}, out), 0);

  for (const char* name : {"builtin:idle", "builtin:gather", "builtin:circle", "builtin:leader_follow"}) {
    EXPECT_NE(out.str().find(name), std::string::npos) << name;
  }
}

// Each says which activation models it was searched under
// (docs/activation.md, "Which apps survive which model").
TEST(AppsCommandTest, SaysWhichModelsEachBuiltinSurvives) {
  std::ostringstream out;
  ASSERT_EQ(RunAppsCommand(AppsOptions{}, out), 0);
  EXPECT_NE(out.str().find("builtin:gather         pack around the centre of the first smallest enclosing circle\n"
                           "    models: FSYNC\n"
                           "            SSYNC: survived every schedule of 3 robots over 6 epochs (117,649)\n"
                           "            ASYNC: survived every schedule of 3 robots with delays up to 1 epoch over 3 "
                           "epochs (4,096), and with moves cut at 5 cm over 2 epochs (10,648)\n"),
            std::string::npos)
      << out.str();
  for (const char* model : {"    models: FSYNC\n", "            SSYNC: survived", "            ASYNC: survived"}) {
    size_t lines = 0;
    for (size_t at = out.str().find(model); at != std::string::npos; at = out.str().find(model, at + 1)) ++lines;
    EXPECT_EQ(lines, 4u) << model;
  }
}

// The installed command itself: exit status 2 for a usage error.
TEST(SyrofExecutableTest, UsageErrorsExitWithTwo) {
  const std::string syrof = SYROF_EXECUTABLE;
  EXPECT_EQ(WEXITSTATUS(std::system((syrof + " run > /dev/null 2>&1").c_str())), 2);
  EXPECT_EQ(WEXITSTATUS(std::system((syrof + " frobnicate > /dev/null 2>&1").c_str())), 2);
  EXPECT_EQ(WEXITSTATUS(std::system((syrof + " --help > /dev/null 2>&1").c_str())), 0);
}

// `--live ADDR:PORT` with a space works as `--live=ADDR:PORT` does, before
// or after the scenario, for `syrof run` and `syrof swarm` (the swarm's
// scenario is missing, so it stops at loading it: what matters is that the
// address was not read as a positional).
TEST(SyrofExecutableTest, LiveTakesItsAddressAfterASpaceToo) {
  const std::string syrof = SYROF_EXECUTABLE;
  const fs::path out = RunTempDir("live_space");
  const auto run = [&](const std::string& arguments) {
    std::string text;
    FILE* pipe = popen((syrof + " " + arguments + " 2>&1").c_str(), "r");
    char buffer[4096];
    for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) text.append(buffer, n);
    const int status = pclose(pipe);
    return std::make_pair(WEXITSTATUS(status), text);
  };
  const std::string idle = kScenarios + "/idle.yaml";
  for (const std::string& arguments :
       {"run " + idle + " --live 127.0.0.1:0", "run --live 127.0.0.1:0 " + idle}) {
    const auto [status, text] = run(arguments + " --live-linger 0 --duration 0.5 --quiet --out " + out.string());
    EXPECT_EQ(status, 0) << arguments << "\n" << text;
    EXPECT_NE(text.find("live page: http://127.0.0.1:"), std::string::npos) << arguments << "\n" << text;
    EXPECT_EQ(text.find("not expected"), std::string::npos) << arguments << "\n" << text;
  }
  const auto [status, text] = run("swarm " + (out / "missing.yaml").string() + " --live 127.0.0.1:0");
  EXPECT_EQ(status, 2) << text;
  EXPECT_NE(text.find("missing.yaml"), std::string::npos) << text;
  EXPECT_EQ(text.find("not expected"), std::string::npos) << text;
}

}  // namespace
}  // namespace syrof::cli
