// `syrof run` and `syrof validate` of a student's library: each robot's app
// in its own sandboxed syrof-app-host, libraries refused before a run with
// the file named, the CPU budget from the scenario and the command line,
// robot logs, faults in the summary and metrics.json, byte-identical reruns.
// Label app_host: these start real host processes, which the sanitizer
// builds' runtimes do not mix with.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "apps_command.h"
#include "run_command.h"
#include "validate_command.h"
#include "cli_test_support.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::Outcome;
using testing::ReadFile;

const std::string kLibs = SYROF_TEST_LIBS_DIR;
const std::string kScenarios = SYROF_SCENARIOS_DIR;

std::string Lib(const std::string& name) { return kLibs + "/lib" + name + ".so"; }

fs::path TempDir(const std::string& name) {
  const fs::path dir = FreshDir("syrof_cli_library_test_", name);
  fs::create_directories(dir);
  return dir;
}

Outcome RunSyrof(const RunOptions& options) {
  std::ostringstream out, err;
  const int status = RunRunCommand(options, out, err, false);
  return Outcome{status, out.str(), err.str()};
}

// A scenario in `dir` running `app_text` (the value of `app:`) on 4 robots for 4 s.
std::string WriteScenario(const fs::path& dir, const std::string& app_text) {
  const fs::path path = dir / "scenario.yaml";
  std::ofstream(path) << "name: lib_run\nrobots: { count: 4, placement: grid, spacing_m: 0.6 }\n"
                      << "timing: { duration_s: 4 }\napp: " << app_text << "\n";
  return path.string();
}

nlohmann::json Metrics(const RunOptions& options) {
  return nlohmann::json::parse(ReadFile(fs::path(options.out_dir) / "metrics.json"));
}

TEST(LibraryRunTest, TheStarterAppRunsInTheHostWithALogPerRobot) {
  const fs::path dir = TempDir("starter");
  RunOptions options;
  options.scenario_path = WriteScenario(dir, "{ library: " + Lib("starter_c") + " }");
  options.out_dir = (dir / "out").string();

  const Outcome outcome = RunSyrof(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("each robot's app in its own sandboxed process: CPU budget 100 ms"), std::string::npos)
      << outcome.out;
  EXPECT_NE(outcome.out.find("goal              none: declare checks under goal:"), std::string::npos) << outcome.out;
  const nlohmann::json metrics = Metrics(options);
  EXPECT_EQ(metrics["app"]["name"], "{{NAME}}");  // the template's placeholder, unfilled
  EXPECT_EQ(metrics["app"]["source"], Lib("starter_c"));
  EXPECT_TRUE(metrics["app"]["sandbox"].is_array());
  EXPECT_EQ(metrics["app"]["faults"], nlohmann::json::array());
  for (int id = 0; id < 4; ++id) {
    EXPECT_EQ(ReadFile(dir / "out" / "robots" / (std::to_string(id) + ".log")),
              "robot " + std::to_string(id) + " of 4: spreading on a circle of radius 1.00 m\n");
  }
}

// A library run is judged by the scenario's goal checks, and the summary
// says so (it said "none" whatever the scenario declared).
TEST(LibraryRunTest, TheSummaryGivesTheScenariosGoalChecks) {
  const fs::path dir = TempDir("goal");
  RunOptions options;
  options.scenario_path = WriteScenario(dir, "{ library: " + Lib("starter_c") + " }\n" +
                                                 "goal:\n  - { check: gathered, radius_m: 5 }\n" +
                                                 "  - { check: gathered, radius_m: 0.01 }");
  options.out_dir = (dir / "out").string();

  const Outcome outcome = RunSyrof(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("goal              NOT reached (1 of 2 checks passed"), std::string::npos)
      << outcome.out;
  EXPECT_EQ(Metrics(options)["goal"]["source"], "scenario");
}

// app.params in the scenario reach each robot's host (syrofAppParameter),
// and the app acts on them: the starters' circle is wider.
TEST(LibraryRunTest, TheScenariosParamsReachTheLibrary) {
  for (const std::string starter : {"starter_c", "starter_cpp"}) {
    const fs::path dir = TempDir("params_" + starter);
    RunOptions options;
    options.scenario_path = WriteScenario(dir, "{ library: " + Lib(starter) + ", params: { radius_m: 1.3 } }");
    options.out_dir = (dir / "out").string();
    RunOptions defaults = options;
    const fs::path dir_defaults = TempDir("params_defaults_" + starter);
    defaults.scenario_path = WriteScenario(dir_defaults, "{ library: " + Lib(starter) + " }");
    defaults.out_dir = (dir_defaults / "out").string();

    const Outcome outcome = RunSyrof(options);
    const Outcome outcome_defaults = RunSyrof(defaults);

    ASSERT_EQ(outcome.status, 0) << outcome.err;
    ASSERT_EQ(outcome_defaults.status, 0) << outcome_defaults.err;
    for (int id = 0; id < 4; ++id) {
      EXPECT_EQ(ReadFile(dir / "out" / "robots" / (std::to_string(id) + ".log")),
                "robot " + std::to_string(id) + " of 4: spreading on a circle of radius 1.30 m\n")
          << starter;
    }
    EXPECT_NE(ReadFile(dir / "out" / "replay"), ReadFile(dir_defaults / "out" / "replay")) << starter;
  }
}

// A packed group that must move: nine robots 0.3 m apart centre to centre
// (closer than the starters' clearance), the middle one's way out crossing
// the others' paths. The starters take turns by id, so the group spreads
// onto its circle in time, without a collision. (When every robot cut its
// path against every other robot's whole path, no robot ever moved.)
TEST(LibraryRunTest, TheStartersSpreadAPackedGroupWithoutDeadlock) {
  for (const std::string starter : {"starter_c", "starter_cpp"}) {
    const fs::path dir = TempDir("packed_" + starter);
    const fs::path scenario = dir / "packed.yaml";
    std::ofstream(scenario) << "name: packed\nseed: 1\narena: { width_m: 4, height_m: 4 }\n"
                            << "robots: { count: 9, placement: grid, spacing_m: 0.3 }\n"
                            << "timing: { duration_s: 30 }\n"
                            << "app: { library: " << Lib(starter) << " }\n"
                            << "goal:\n  - { check: circle, radius_min_m: 0.9, radius_max_m: 1.1, "
                               "angle_tolerance_rad: 0.15, deadline_s: 25 }\n";
    RunOptions options;
    options.scenario_path = scenario.string();
    options.out_dir = (dir / "out").string();

    const Outcome outcome = RunSyrof(options);

    ASSERT_EQ(outcome.status, 0) << outcome.err;
    const nlohmann::json metrics = Metrics(options);
    EXPECT_EQ(metrics["goal"]["reached"], true) << starter << ": " << metrics["goal"].dump();
    EXPECT_EQ(metrics["collisions"]["count"], 0) << starter << ": " << metrics["collisions"].dump();
    EXPECT_EQ(metrics["app"]["faults"], nlohmann::json::array()) << starter;
  }
}

TEST(LibraryRunTest, SandboxNotesArePrintedAndRecorded) {
  const fs::path dir = TempDir("notes");
  RunOptions options;
  options.scenario_path = WriteScenario(dir, Lib("starter_c"));
  options.out_dir = (dir / "out").string();

  const Outcome outcome = RunSyrof(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  const nlohmann::json notes = Metrics(options)["app"]["sandbox"];
  ASSERT_TRUE(notes.is_array());
  for (const auto& note : notes) {
    EXPECT_NE(outcome.out.find("  sandbox: " + note.get<std::string>()), std::string::npos) << outcome.out;
  }
}

// One's own library on a kernel without Landlock (pretended): the run goes
// on, and says which layer is missing.
TEST(LibraryRunTest, WithoutLandlockALibraryRunGoesOnWithASandboxNote) {
  const fs::path dir = TempDir("no_landlock");
  RunOptions options;
  options.scenario_path = WriteScenario(dir, Lib("starter_c"));
  options.out_dir = (dir / "out").string();
  setenv("SYROF_PRETEND_NO_LANDLOCK", "1", 1);
  const Outcome outcome = RunSyrof(options);
  unsetenv("SYROF_PRETEND_NO_LANDLOCK");
  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("  sandbox: Landlock unavailable"), std::string::npos) << outcome.out;
}

TEST(LibraryRunTest, ALibraryOnTheCommandLineReplacesTheScenariosApp) {
  const fs::path dir = TempDir("override");
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.app = Lib("starter_cpp");
  options.duration_s = 3;
  options.quiet = true;
  options.out_dir = (dir / "out").string();

  const Outcome outcome = RunSyrof(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_EQ(Metrics(options)["app"]["source"], Lib("starter_cpp"));
  EXPECT_TRUE(fs::exists(dir / "out" / "robots" / "0.log"));
}

TEST(LibraryRunTest, ALibraryRunIsByteIdenticalOnRerun) {
  const fs::path dir = TempDir("rerun");
  RunOptions first;
  first.scenario_path = WriteScenario(dir, "{ library: " + Lib("starter_c") + " }");
  first.reproducible = true;
  first.quiet = true;
  first.out_dir = (dir / "a").string();
  RunOptions second = first;
  second.out_dir = (dir / "b").string();

  ASSERT_EQ(RunSyrof(first).status, 0);
  ASSERT_EQ(RunSyrof(second).status, 0);

  EXPECT_EQ(ReadFile(dir / "a" / "metrics.json"), ReadFile(dir / "b" / "metrics.json"));
  EXPECT_EQ(ReadFile(dir / "a" / "replay"), ReadFile(dir / "b" / "replay"));
}

// ---- Refused before the run -----------------------------------------------------

Outcome RunLibrary(const std::string& library, const std::string& name) {
  const fs::path dir = TempDir(name);
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.app = library;
  options.out_dir = (dir / "out").string();
  Outcome outcome = RunSyrof(options);
  // Nothing is written for a library that cannot run.
  EXPECT_FALSE(fs::exists(dir / "out")) << name;
  return outcome;
}

TEST(LibraryRunTest, AMissingLibraryIsBadInputNamingTheFile) {
  const Outcome outcome = RunLibrary(kLibs + "/libnothere.so", "missing");

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("no such library file '" + kLibs + "/libnothere.so'"), std::string::npos) << outcome.err;
}

TEST(LibraryRunTest, ALibraryWithoutTheEntrySymbolIsBadInputNamingTheFile) {
  const Outcome outcome = RunLibrary(Lib("no_entry"), "no_entry");

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find(Lib("no_entry")), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find("syrof_app_entry"), std::string::npos) << outcome.err;
}

TEST(LibraryRunTest, AWrongAbiVersionIsBadInputNamingBothVersions) {
  const Outcome outcome = RunLibrary(Lib("wrong_abi"), "wrong_abi");

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find(Lib("wrong_abi")), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find("99"), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find(std::to_string(SYROF_APP_ABI_VERSION)), std::string::npos) << outcome.err;
}

TEST(LibraryRunTest, AFileThatIsNoLibraryIsBadInputNamingTheFile) {
  const fs::path dir = TempDir("not_elf");
  std::ofstream(dir / "libtext.so") << "just text\n";

  const Outcome outcome = RunLibrary((dir / "libtext.so").string(), "not_elf_run");

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find((dir / "libtext.so").string()), std::string::npos) << outcome.err;
}

TEST(LibraryRunTest, BudgetsForABuiltinAppAreRefused) {
  RunOptions options;
  options.scenario_path = kScenarios + "/idle.yaml";
  options.cpu_budget_ms = 50;

  const Outcome outcome = RunSyrof(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("--cpu-budget-ms is for a library app; builtin:idle runs inside the simulator"),
            std::string::npos)
      << outcome.err;
}

// ---- Faults and budgets -------------------------------------------------------------

TEST(LibraryRunTest, ACrashStaysInItsRobotAndStrictExitsWithThree) {
  const fs::path dir = TempDir("crash");
  RunOptions options;
  options.scenario_path = WriteScenario(dir, "{ library: " + Lib("robot1_crashes") + " }");
  options.out_dir = (dir / "out").string();

  const Outcome outcome = RunSyrof(options);
  options.strict = true;
  options.quiet = true;
  const Outcome strict = RunSyrof(options);

  EXPECT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("WARNING: the app misbehaved"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("first robot 1, new_round of epoch"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("crashed"), std::string::npos) << outcome.out;
  EXPECT_EQ(strict.status, 3);
  const nlohmann::json faults = Metrics(options)["app"]["faults"];
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0]["robot"], 1);
  EXPECT_EQ(faults[0]["verdict"], "crashed");
}

// The budget reaches the host: the verdict's detail names it.
std::string LoopVerdictDetail(const std::string& name, const std::string& app_text, RunOptions options) {
  const fs::path dir = TempDir(name);
  options.scenario_path = WriteScenario(dir, app_text);
  options.quiet = true;
  options.out_dir = (dir / "out").string();
  const Outcome outcome = RunSyrof(options);
  EXPECT_EQ(outcome.status, 0) << outcome.err;
  const nlohmann::json faults = Metrics(options)["app"]["faults"];
  if (faults.size() != 1u) return "faults: " + faults.dump();
  EXPECT_EQ(faults[0]["robot"], 0);
  EXPECT_EQ(faults[0]["verdict"], "timeout");
  return faults[0]["detail"].get<std::string>();
}

TEST(LibraryRunTest, TheScenariosCpuBudgetReachesTheHost) {
  const std::string detail =
      LoopVerdictDetail("budget_file", "{ library: " + Lib("robot0_loops") + ", cpu_budget_ms: 30 }", RunOptions{});

  EXPECT_NE(detail.find("CPU time over 30 ms"), std::string::npos) << detail;
}

TEST(LibraryRunTest, TheCommandLinesCpuBudgetWinsOverTheScenarios) {
  RunOptions options;
  options.cpu_budget_ms = 20;

  const std::string detail =
      LoopVerdictDetail("budget_cli", "{ library: " + Lib("robot0_loops") + ", cpu_budget_ms: 30 }", options);

  EXPECT_NE(detail.find("CPU time over 20 ms"), std::string::npos) << detail;
}

TEST(LibraryRunTest, AWallCapBelowTheBudgetIsRefused) {
  const fs::path dir = TempDir("wall_below");
  RunOptions options;
  options.scenario_path = WriteScenario(dir, "{ library: " + Lib("starter_c") + ", cpu_budget_ms: 300 }");
  options.wall_cap_ms = 200;

  const Outcome outcome = RunSyrof(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("the wall cap (200 ms) must be at least the CPU budget (300 ms)"), std::string::npos)
      << outcome.err;
}

// ---- validate and apps ------------------------------------------------------------------

TEST(LibraryValidateTest, ALibraryIsLoadedOnceAndNamed) {
  const fs::path dir = TempDir("validate");
  ValidateOptions options;
  options.scenario_path = WriteScenario(dir, "{ library: " + Lib("starter_c") + " }");
  std::ostringstream out, err;

  ASSERT_EQ(RunValidateCommand(options, out, err), 0) << err.str();

  EXPECT_NE(out.str().find("library " + Lib("starter_c") + " (app '{{NAME}}')"), std::string::npos) << out.str();
}

TEST(LibraryValidateTest, ALibraryRunWouldRefuseIsRefused) {
  const fs::path dir = TempDir("validate_bad");
  ValidateOptions options;
  options.scenario_path = WriteScenario(dir, "{ library: " + Lib("wrong_abi") + " }");
  std::ostringstream out, err;

  EXPECT_EQ(RunValidateCommand(options, out, err), 2);

  EXPECT_NE(err.str().find(Lib("wrong_abi")), std::string::npos) << err.str();
}

TEST(LibraryValidateTest, AMissingLibraryIsNamedAtItsPlace) {
  const fs::path dir = TempDir("validate_missing");
  ValidateOptions options;
  options.scenario_path = WriteScenario(dir, "{ library: build/libnope.so }");
  std::ostringstream out, err;

  EXPECT_EQ(RunValidateCommand(options, out, err), 2);

  EXPECT_NE(err.str().find("scenario.yaml:4:17: app.library: no such library file 'build/libnope.so'"),
            std::string::npos)
      << err.str();
}

TEST(AppsCommandTest, SaysHowToRunALibrary) {
  std::ostringstream out;

  ASSERT_EQ(RunAppsCommand(AppsOptions{}, out), 0);

  EXPECT_NE(out.str().find("syrof run SCENARIO --app build/libmyapp.so"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("syrof new myapp"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace syrof::cli
