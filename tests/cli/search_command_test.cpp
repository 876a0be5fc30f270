// `syrof search` with a student's library: a library that crashes in an
// AUTONOMOUS epoch is broken by the smallest loss pattern that leaves a
// robot out, and the counterexample it writes reruns bit for bit with
// `syrof run`; the starter app survives; bad input exits 2. Label app_host:
// every run starts sandboxed host processes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_test_support.h"
#include "run_command.h"
#include "search_command.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::Outcome;
using testing::ReadFile;

std::string TestLib(const std::string& name) { return std::string(SYROF_TEST_LIBS_DIR) + "/lib" + name + ".so"; }

// Three robots voting for one round (K = 1), so that one lost beacon can
// leave a robot out; the channel's own loss is what the search replaces.
std::string WriteSearchScenario(const fs::path& dir, const std::string& app) {
  fs::create_directories(dir);
  const fs::path path = dir / "scenario.yaml";
  std::ofstream(path) << "name: search_me\nseed: 3\nrobots: { count: 3, spacing_m: 1.0 }\n"
                      << "timing: { duration_s: 4, vote_rounds: 1, silence_rounds: 2 }\n"
                      << "channel: { model: iid, loss: 0.2 }\napp: " << app << "\n";
  return path.string();
}

Outcome RunSearch(const std::vector<std::string>& arguments) {
  return testing::ParseAndRun<SearchOptions>(
      "search", arguments, [](CLI::App& app, SearchOptions& options) { SetupSearchCommand(app, options); },
      [](const SearchOptions& options, std::ostream& out, std::ostream& err) {
        return RunSearchCommand(options, out, err, false);
      });
}

// `syrof run` of OUT/counterexample.yaml into DIR/rerun, from another
// folder as a student would after moving it, gives the search's replay and
// metrics.json byte for byte.
void ExpectRerunsBitForBit(const fs::path& dir, const fs::path& out) {
  RunOptions rerun;
  rerun.scenario_path = (out / "counterexample.yaml").string();
  rerun.out_dir = (dir / "rerun").string();
  rerun.quiet = true;
  rerun.reproducible = true;
  std::ostringstream run_out, run_err;
  ASSERT_EQ(RunRunCommand(rerun, run_out, run_err, false), 0) << run_err.str();
  EXPECT_EQ(ReadFile(dir / "rerun" / "replay"), ReadFile(out / "replay"));
  EXPECT_EQ(ReadFile(dir / "rerun" / "metrics.json"), ReadFile(out / "metrics.json"));
}

TEST(SearchCommandTest, FindsThePatternThatBreaksALibraryAndItRerunsBitForBit) {
  const fs::path dir = FreshDir("syrof_search_test_", "broken");
  const std::string scenario = WriteSearchScenario(dir, TestLib("assumes_cooperative"));
  const fs::path out = dir / "out";
  const Outcome outcome = RunSearch({scenario, "--max-losses", "2", "--epochs", "2", "--jobs", "2", "--out", out});
  ASSERT_EQ(outcome.status, 1) << outcome.out << outcome.err;
  EXPECT_NE(outcome.out.find("BROKEN by 1 lost beacon"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("broken: app fault: robot"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("syrof run " + (out / "counterexample.yaml").string()), std::string::npos);
  for (const char* name : {"counterexample.yaml", "replay", "metrics.json", "replay.html"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
  }
  const std::string yaml = ReadFile(out / "counterexample.yaml");
  EXPECT_NE(yaml.find("model: scripted"), std::string::npos) << yaml;
  EXPECT_EQ(yaml.find("loss:"), std::string::npos) << yaml;

  ExpectRerunsBitForBit(dir, out);
}

// A library named by a relative path: the counterexample's file names it
// absolute (to run from any folder), and its rerun once reported another
// app.source than the search's run, so the search called its own
// counterexample an internal error.
TEST(SearchCommandTest, ALibraryNamedByARelativePathGivesACounterexampleThatReruns) {
  const fs::path dir = FreshDir("syrof_search_test_", "relative");
  const std::string relative = fs::relative(TestLib("assumes_cooperative")).string();
  ASSERT_FALSE(fs::path(relative).is_absolute());
  const std::string scenario = WriteSearchScenario(dir, "builtin:idle");
  const fs::path out = dir / "out";
  const Outcome outcome =
      RunSearch({scenario, "--app", relative, "--max-losses", "2", "--epochs", "2", "--out", out.string()});
  ASSERT_EQ(outcome.status, 1) << outcome.out << outcome.err;
  EXPECT_EQ(outcome.err.find("internal error"), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.out.find("BROKEN by 1 lost beacon"), std::string::npos) << outcome.out;
  const std::string absolute = fs::absolute(relative).lexically_normal().string();
  EXPECT_NE(ReadFile(out / "metrics.json").find(absolute), std::string::npos);
}

TEST(SearchCommandTest, AScenarioWithoutANameKeepsItsNameInTheCounterexample) {
  // The counterexample's file is named counterexample.yaml: without the
  // name written in, its rerun was named "counterexample" and differed.
  const fs::path dir = FreshDir("syrof_search_test_", "unnamed");
  fs::create_directories(dir);
  const fs::path scenario = dir / "three.yaml";
  std::ofstream(scenario) << "robots: { count: 3, spacing_m: 1.0 }\ntiming: { duration_s: 3 }\napp: builtin:idle\n";
  const Outcome outcome = RunSearch({scenario.string(), "--max-losses", "1", "--app", TestLib("robot0_loops"),
                                     "--out", (dir / "out").string()});
  ASSERT_EQ(outcome.status, 1) << outcome.out << outcome.err;
  EXPECT_NE(outcome.out.find("BROKEN without any lost beacon"), std::string::npos) << outcome.out;
  // The loss-free run is the first: one run, counted in the singular.
  EXPECT_NE(outcome.out.find("after 1 run (1 distinct outcome) in"), std::string::npos) << outcome.out;
  EXPECT_NE(ReadFile(dir / "out" / "metrics.json").find("\"scenario\": \"three\""), std::string::npos);
}

TEST(SearchCommandTest, TheStarterAppSurvivesAndTheSearchSaysHowFarItGot) {
  const fs::path dir = FreshDir("syrof_search_test_", "starter");
  const std::string scenario = WriteSearchScenario(dir, TestLib("starter_c"));
  const Outcome outcome = RunSearch({scenario, "--max-losses", "1", "--epochs", "1", "--out", dir / "out"});
  ASSERT_EQ(outcome.status, 0) << outcome.out << outcome.err;
  EXPECT_NE(outcome.out.find("no pattern broke it: all"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("distinct outcome"), std::string::npos) << outcome.out;
  EXPECT_FALSE(fs::exists(dir / "out" / "counterexample.yaml"));
}

TEST(SearchCommandTest, ATimeLimitStopsTheSearchAndSaysSo) {
  const fs::path dir = FreshDir("syrof_search_test_", "limit");
  const std::string scenario = WriteSearchScenario(dir, "builtin:idle");
  const Outcome outcome =
      RunSearch({scenario, "--max-losses", "3", "--epochs", "3", "--time-limit", "0.5", "--out", dir / "out"});
  ASSERT_EQ(outcome.status, 0) << outcome.out << outcome.err;
  EXPECT_NE(outcome.out.find("before the time limit"), std::string::npos) << outcome.out;
}

TEST(SearchCommandTest, BadInputExitsTwoAndSaysWhatIsWrong) {
  const fs::path dir = FreshDir("syrof_search_test_", "bad");
  const Outcome missing = RunSearch({(dir / "nothing.yaml").string(), "--max-losses", "1"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("nothing.yaml"), std::string::npos) << missing.err;

  const Outcome no_entry = RunSearch({WriteSearchScenario(dir, TestLib("no_entry")), "--max-losses", "1", "--out", dir / "o"});
  EXPECT_EQ(no_entry.status, 2);
  EXPECT_NE(no_entry.err.find("syrof_app_entry"), std::string::npos) << no_entry.err;

  // 200 robots over 3 epochs: about 2.4 M slots.
  const fs::path crowd = dir / "crowd.yaml";
  std::ofstream(crowd) << "robots: { count: 200, spacing_m: 0.5 }\narena: { width_m: 20, height_m: 20 }\n"
                       << "timing: { duration_s: 4 }\napp: builtin:idle\n";
  const Outcome crowded = RunSearch({crowd.string(), "--max-losses", "1", "--out", dir / "crowd"});
  EXPECT_EQ(crowded.status, 2);
  EXPECT_NE(crowded.err.find("more than a search can try"), std::string::npos) << crowded.err;

  const Outcome negative = RunSearch({WriteSearchScenario(dir, "builtin:idle"), "--max-losses", "-1"});
  EXPECT_EQ(negative.status, 2);
  const Outcome absent = RunSearch({WriteSearchScenario(dir, "builtin:idle")});
  EXPECT_EQ(absent.status, 2);
  EXPECT_NE(absent.err.find("--max-losses"), std::string::npos) << absent.err;
}

// The schedule search (docs/activation.md): a library that counts its own
// turns passes the FSYNC run (the search's first), and the first SSYNC
// schedule that leaves one robot out of one epoch breaks its agreement;
// the counterexample is a scripted schedule that `syrof run` reruns.
TEST(SearchCommandTest, TheScheduleSearchBreaksALibraryCountingItsTurnsAndItReruns) {
  const fs::path dir = FreshDir("syrof_search_test_", "activations");
  const fs::path path = dir / "scenario.yaml";
  fs::create_directories(dir);
  std::ofstream(path) << "name: turns\nseed: 3\nrobots: { count: 3, spacing_m: 1.0 }\ntiming: { duration_s: 4 }\n"
                      << "app: " << TestLib("counts_turns") << "\n";
  const fs::path out = dir / "out";
  const Outcome outcome = RunSearch({path.string(), "--activations", "ssync", "--epochs", "3", "--out", out});
  ASSERT_EQ(outcome.status, 1) << outcome.out << outcome.err;
  EXPECT_NE(outcome.out.find("SSYNC schedules of the first 3 epochs"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("BROKEN by a schedule leaving 1 robot-epoch out ([epoch: robot]): ["), std::string::npos)
      << outcome.out;
  EXPECT_NE(outcome.out.find("broken: agreement"), std::string::npos) << outcome.out;
  const std::string yaml = ReadFile(out / "counterexample.yaml");
  EXPECT_NE(yaml.find("schedule: scripted"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("active:"), std::string::npos) << yaml;
  ExpectRerunsBitForBit(dir, out);

  // The built-in idle app survives every schedule, and the search says so
  // in the words of schedules.
  const Outcome survived = RunSearch(
      {path.string(), "--app", "builtin:idle", "--activations", "ssync", "--epochs", "2", "--out", dir / "idle"});
  EXPECT_EQ(survived.status, 0) << survived.out << survived.err;
  EXPECT_NE(survived.out.find("no schedule broke it: all 49 runs"), std::string::npos) << survived.out;
}

TEST(SearchCommandTest, TheScheduleSearchRefusesFlagsThatDoNotGoWithIt) {
  const fs::path dir = FreshDir("syrof_search_test_", "activation_flags");
  const std::string scenario = WriteSearchScenario(dir, "builtin:idle");
  const auto refused = [&](const std::vector<std::string>& arguments, const std::string& words) {
    std::vector<std::string> all{scenario};
    all.insert(all.end(), arguments.begin(), arguments.end());
    const Outcome outcome = RunSearch(all);
    EXPECT_EQ(outcome.status, 2) << outcome.out;
    EXPECT_NE(outcome.err.find(words), std::string::npos) << outcome.err;
    EXPECT_FALSE(fs::exists(dir / "o")) << "nothing written";
  };
  refused({"--activations", "sometimes", "--out", (dir / "o").string()}, "must be ssync or async, not 'sometimes'");
  refused({"--activations", "ssync", "--max-losses", "1", "--out", (dir / "o").string()}, "do not combine");
  refused({"--max-losses", "1", "--fair-within", "2", "--out", (dir / "o").string()}, "--fair-within applies to --activations only");
  refused({"--activations", "ssync", "--fair-within", "5", "--epochs", "3", "--out", (dir / "o").string()},
          "--fair-within 5 is more than the 3 epochs searched");
}

// The ASYNC schedule search (docs/activation.md): the library counting its
// turns passes the FSYNC run, and the first schedule with one deviating
// cycle (robot 0's first move over two epochs, so it skips the second
// look) breaks its agreement; the counterexample is a scripted ASYNC
// schedule that `syrof run` reruns bit for bit, with its page.
TEST(SearchCommandTest, TheAsyncScheduleSearchBreaksALibraryCountingItsTurnsAndItReruns) {
  const fs::path dir = FreshDir("syrof_search_test_", "async");
  const fs::path path = dir / "scenario.yaml";
  fs::create_directories(dir);
  std::ofstream(path) << "name: turns\nseed: 3\nrobots: { count: 3, spacing_m: 1.0 }\ntiming: { duration_s: 4 }\n"
                      << "app: " << TestLib("counts_turns") << "\n";
  const fs::path out = dir / "out";
  const Outcome outcome =
      RunSearch({path.string(), "--activations", "async", "--max-delay", "1", "--epochs", "3", "--out", out});
  ASSERT_EQ(outcome.status, 1) << outcome.out << outcome.err;
  EXPECT_NE(outcome.out.find("ASYNC schedules of the first 3 epochs: start delays up to 1 epoch, moves up to 2 "
                             "epochs, rigid"),
            std::string::npos)
      << outcome.out;
  // (1 + 3x + 3x (from the second look) ...) per robot over 3 epochs: 16^3.
  EXPECT_NE(outcome.out.find("9 robot-epochs; 4096 schedules"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("BROKEN by a schedule with 1 deviating cycle ([look epoch, robot, start_delay, "
                             "move_epochs(, cut)]): [1, 0, 0, 2]\n"),
            std::string::npos)
      << outcome.out;
  EXPECT_NE(outcome.out.find("broken: agreement"), std::string::npos) << outcome.out;
  const std::string yaml = ReadFile(out / "counterexample.yaml");
  EXPECT_NE(yaml.find("model: async"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("max_delay_epochs: 1"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("[1, 0, 0, 2]"), std::string::npos) << yaml;
  EXPECT_TRUE(fs::exists(out / "replay.html"));
  ExpectRerunsBitForBit(dir, out);
}

// builtin:gather on lab/scenarios/gather_async.yaml (4 robots, delays up to
// 2 epochs, cuts at 5 cm): every schedule of at most one deviating cycle
// in its first 2 epochs, 1 + 8 looks x 17 choices = 137, none breaks it.
TEST(SearchCommandTest, GatherSurvivesTheAsyncSchedulesOfItsOwnScenario) {
  const fs::path dir = FreshDir("syrof_search_test_", "async_gather");
  const Outcome outcome =
      RunSearch({std::string(SYROF_SCENARIOS_DIR) + "/gather_async.yaml", "--activations", "async", "--epochs", "2",
                 "--max-deviations", "1", "--jobs", "2", "--out", (dir / "out").string()});
  EXPECT_EQ(outcome.status, 0) << outcome.out << outcome.err;
  EXPECT_NE(outcome.out.find("start delays up to 2 epochs, moves up to 3 epochs, cut once they covered 0.05 m"),
            std::string::npos)
      << outcome.out;
  EXPECT_NE(outcome.out.find("137 schedules of at most 1 deviating cycle\n"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("no schedule broke it: all 137 runs"), std::string::npos) << outcome.out;
  EXPECT_FALSE(fs::exists(dir / "out" / "counterexample.yaml"));
}

TEST(SearchCommandTest, TheAsyncScheduleSearchRefusesBadInputAndWritesNothing) {
  const fs::path dir = FreshDir("syrof_search_test_", "async_flags");
  const std::string scenario = WriteSearchScenario(dir, "builtin:idle");
  const auto refused = [&](const std::vector<std::string>& arguments, const std::string& words) {
    std::vector<std::string> all{scenario};
    all.insert(all.end(), arguments.begin(), arguments.end());
    all.push_back("--out");
    all.push_back((dir / "o").string());
    const Outcome outcome = RunSearch(all);
    EXPECT_EQ(outcome.status, 2) << outcome.out;
    EXPECT_NE(outcome.err.find(words), std::string::npos) << outcome.err;
    EXPECT_FALSE(fs::exists(dir / "o")) << "nothing written";
  };
  refused({"--activations", "async", "--max-delay", "1", "--max-losses", "1"}, "do not combine");
  refused({"--activations", "async", "--max-delay", "1", "--fair-within", "2"},
          "--fair-within applies to --activations ssync only");
  refused({"--activations", "async", "--max-delay", "1", "--max-inactive", "2"}, "async: --max-deviations");
  refused({"--activations", "ssync", "--max-delay", "1"}, "apply to --activations async only");
  refused({"--max-losses", "1", "--min-move", "0.1"}, "apply to --activations async only");
  // An FSYNC scenario has no delay bound of its own.
  refused({"--activations", "async"}, "give --max-delay D");
  refused({"--activations", "async", "--max-delay", "9"}, "--max-delay");
  refused({"--activations", "async", "--max-delay", "1", "--max-deviations", "0"}, "--max-deviations");
  refused({"--activations", "async", "--max-delay", "1", "--min-move", "-1"}, "--min-move");
  // 3 robots over 1000 epochs: up to 3,000 looks, within the bound; 200
  // robots over 21 epochs: 4,200, beyond it (refused before any run).
  const fs::path crowd = dir / "crowd.yaml";
  std::ofstream(crowd) << "robots: { count: 200, spacing_m: 0.5 }\narena: { width_m: 20, height_m: 20 }\n"
                       << "timing: { duration_s: 4 }\napp: builtin:idle\n";
  const Outcome crowded = RunSearch({crowd.string(), "--activations", "async", "--max-delay", "1", "--epochs", "21",
                                     "--out", (dir / "o").string()});
  EXPECT_EQ(crowded.status, 2) << crowded.out;
  EXPECT_NE(crowded.err.find("up to 4200 robot-epochs"), std::string::npos) << crowded.err;
  EXPECT_NE(crowded.err.find("--epochs"), std::string::npos) << crowded.err;
  EXPECT_FALSE(fs::exists(dir / "o")) << "nothing written";
}

}  // namespace
}  // namespace syrof::cli
