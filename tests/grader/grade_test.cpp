// The grade command's runner (grader/): building submissions in the
// sandbox, grading through the app host, a class of hostile submissions
// (each with its verdict, the others unaffected), determinism, resume,
// shards and merge, mixed swarms. Runs are short (tests/grader/tiny).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/expected.h"
#include "syrof/grader/assignment_check.h"
#include "syrof/grader/build.h"
#include "syrof/grader/class_grading.h"
#include "syrof/grader/grade.h"
#include "syrof/grader/grade_json.h"
#include "syrof/grader/mix.h"
#include "syrof/grader/outputs.h"
#include "syrof/grader/student_seeds.h"
#include "syrof/grader/table.h"

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::Assignment;
using assignment::SubmissionResult;

const fs::path kTiny = fs::path(SYROF_TEST_DATA_DIR) / "tiny";
const fs::path kReference = fs::path(SYROF_ASSIGNMENTS_DIR) / "gather" / "reference";
const fs::path kHostileLibs = fs::path(SYROF_HOSTILE_LIBS_DIR);

fs::path Fresh(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("grade_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void Write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

std::string Read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

Assignment LoadTiny(const std::string& file = "assignment.yaml") {
  const assignment::LoadResult loaded = assignment::LoadAssignmentFile((kTiny / file).string());
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return loaded.ok() ? *loaded.assignment : Assignment{};
}

// A sources-only submission: one of the app host's hostile libraries.
void HostileSubmission(const fs::path& folder, const std::string& library) {
  fs::create_directories(folder);
  fs::copy_file(kHostileLibs / (library + ".c"), folder / (library + ".c"));
  fs::copy_file(kHostileLibs / "hostile.h", folder / "hostile.h");
}

// Every file under `dir` by relative path, grade.json without its timings.
std::map<std::string, std::string> Snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir)) {
    const std::string relative = entry.path().lexically_relative(dir).generic_string();
    // The build's own folders and log are CMake's and the compiler's output.
    // A flooding app's log is cut where the host was stopped, which
    // depends on timing: robots' logs are not compared.
    if (relative.find("/build/") != std::string::npos || relative.find("/source/") != std::string::npos ||
        relative.find("/robots/") != std::string::npos || relative.ends_with("build.log") ||
        !entry.is_regular_file()) {
      continue;
    }
    std::string bytes = Read(entry.path());
    // Timings are the one thing allowed to differ: grade.json keeps them
    // under "timings", results.json in execution_time, JUnit in time="...".
    if (relative.ends_with("grade.json")) bytes = bytes.substr(0, bytes.find("\"timings\""));
    if (relative.ends_with("results.json")) {
      bytes = std::regex_replace(bytes, std::regex("\"execution_time\": [0-9.e+-]+"), "\"execution_time\": T");
    }
    if (relative.ends_with("junit.xml")) bytes = std::regex_replace(bytes, std::regex(" time=\"[0-9.]+\""), " time=\"T\"");
    files[relative] = bytes;
  }
  return files;
}

// The faults criterion's reason of a submission's first test.
std::string FaultReason(const SubmissionResult& student) {
  if (student.tests.empty()) return {};
  for (const assignment::CriterionScore& criterion : student.tests[0].score.criteria) {
    if (criterion.criterion == "faults") return criterion.reason;
  }
  return {};
}

TEST(BuildSubmissionTest, BuildsACMakeSubmission) {
  const fs::path out = Fresh("cmake");
  std::vector<std::string> notes;
  const assignment::BuildResult build = BuildSubmission(kReference.string(), out.string(), {}, notes);
  EXPECT_EQ(build.verdict, assignment::BuildVerdict::kOk) << build.detail << "\n" << Read(out / "build.log");
  EXPECT_EQ(build.detail, "built libgather.so");
  EXPECT_TRUE(fs::exists(build.library_path));
  EXPECT_TRUE(fs::exists(out / "source" / "gather.c"));
}

TEST(BuildSubmissionTest, BuildsASubmissionOfSourcesOnly) {
  const fs::path submission = Fresh("sources_in");
  fs::copy_file(kReference / "gather.c", submission / "gather.c");
  const fs::path out = Fresh("sources");
  std::vector<std::string> notes;
  const assignment::BuildResult build = BuildSubmission(submission.string(), out.string(), {}, notes);
  EXPECT_EQ(build.verdict, assignment::BuildVerdict::kOk) << build.detail << "\n" << Read(out / "build.log");
  EXPECT_EQ(build.detail, "built libsubmission.so");
  EXPECT_NE(Read(out / "source" / "CMakeLists.txt").find("add_library(submission MODULE"), std::string::npos);
  EXPECT_FALSE(fs::exists(submission / "CMakeLists.txt")) << "the student's folder is never written";
}

TEST(BuildSubmissionTest, ACompileErrorGivesTheFirstErrorLine) {
  const fs::path submission = Fresh("broken_in");
  Write(submission / "app.c", "#include \"syrof/app.h\"\nint broken(void) { return undeclared_thing; }\n");
  const fs::path out = Fresh("broken");
  std::vector<std::string> notes;
  const assignment::BuildResult build = BuildSubmission(submission.string(), out.string(), {}, notes);
  EXPECT_EQ(build.verdict, assignment::BuildVerdict::kBuildFailed);
  EXPECT_TRUE(build.detail.starts_with("app.c:2:")) << build.detail;
  EXPECT_NE(build.detail.find("error:"), std::string::npos) << build.detail;
  EXPECT_NE(build.detail.find("undeclared_thing"), std::string::npos) << build.detail;
}

TEST(BuildSubmissionTest, ABuildThatLoopsIsStoppedAtItsTimeLimit) {
  const fs::path submission = Fresh("loop_in");
  Write(submission / "CMakeLists.txt",
        "cmake_minimum_required(VERSION 3.16)\nproject(loop LANGUAGES NONE)\n"
        "execute_process(COMMAND sleep 600)\n");
  const fs::path out = Fresh("loop");
  BuildOptions options;
  options.timeout_s = 2;
  std::vector<std::string> notes;
  const assignment::BuildResult build = BuildSubmission(submission.string(), out.string(), options, notes);
  EXPECT_EQ(build.verdict, assignment::BuildVerdict::kTimeout);
  EXPECT_EQ(build.detail, "the build took longer than its limit of 2 s");
  EXPECT_LT(build.wall_seconds, 30.0) << "the sleeping child was killed with its group";
}

TEST(BuildSubmissionTest, AFolderWithoutSourcesHasNothingToBuild) {
  const fs::path submission = Fresh("empty_in");
  Write(submission / "notes.txt", "nothing here\n");
  const fs::path out = Fresh("empty");
  std::vector<std::string> notes;
  EXPECT_EQ(BuildSubmission(submission.string(), out.string(), {}, notes).verdict, assignment::BuildVerdict::kNoSources);
}

// What fails before the build starts is said whole, in the detail and the log.
TEST(BuildSubmissionTest, ASubmissionAboveItsSizeAndAPackageWithoutItsConfigAreSaidWhole) {
  const fs::path submission = Fresh("big_in");
  Write(submission / "app.c", std::string(1536u << 10, ' '));
  const fs::path out = Fresh("big");
  BuildOptions options;
  options.max_submission_bytes = 1u << 20;
  std::vector<std::string> notes;
  const assignment::BuildResult big = BuildSubmission(submission.string(), out.string(), options, notes);
  EXPECT_EQ(big.verdict, assignment::BuildVerdict::kBuildFailed);
  EXPECT_EQ(big.detail, "the submission holds more than 1 MB of files");
  EXPECT_NE(Read(out / "build.log").find("syrof grade: the submission holds more than 1 MB of files\n"),
            std::string::npos)
      << Read(out / "build.log");

  const fs::path no_package = Fresh("no_package");
  BuildOptions elsewhere;
  elsewhere.syrof_dir = no_package.string();
  const assignment::BuildResult unstaged =
      BuildSubmission(kReference.string(), Fresh("unstaged").string(), elsewhere, notes);
  EXPECT_EQ(unstaged.verdict, assignment::BuildVerdict::kBuildFailed);
  EXPECT_EQ(unstaged.detail, (no_package / "SyROFConfig.cmake").string() +
                                 " is missing or names no IMPORTED_LOCATION or INTERFACE_INCLUDE_DIRECTORIES");
}

TEST(GradeSubmissionTest, TheReferenceGetsFullMarksAndTheTableSaysSo) {
  const Assignment tiny = LoadTiny();
  const fs::path out = Fresh("reference");
  std::vector<std::string> notes;
  GradeOptions options;
  options.jobs = 2;
  const SubmissionResult result = GradeSubmission(tiny, kReference.string(), out.string(), options, notes);
  ASSERT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 3u);
  EXPECT_EQ(result.tests[0].name, "tiny/seed-1");
  EXPECT_EQ(result.tests[2].name, "secret/seed-3");
  EXPECT_EQ(result.tests[2].visibility, assignment::Visibility::kHidden);
  EXPECT_EQ(result.points, 60) << FirstLoss(result.tests[0]);
  EXPECT_EQ(result.tests_passed, 3);
  EXPECT_TRUE(fs::exists(out / "runs" / "tiny" / "seed-1" / "metrics.json"));
  EXPECT_TRUE(fs::exists(out / "runs" / "tiny" / "seed-1" / "robots" / "0.log"));
  EXPECT_FALSE(fs::exists(out / "runs" / "tiny" / "seed-1" / "replay.bin")) << "a passed run keeps no replay";
  std::ostringstream table;
  PrintSubmissionTable(result, out.string(), table);
  EXPECT_NE(table.str().find("Tests passed 3/3, Points 60.00/60.00\n"), std::string::npos) << table.str();
}

TEST(GradeSubmissionTest, ARunOverItsTimeLimitIsStoppedWithARunError) {
  const Assignment slow = LoadTiny("time_limit.yaml");
  const fs::path out = Fresh("time_limit");
  std::vector<std::string> notes;
  const SubmissionResult result = GradeSubmission(slow, kReference.string(), out.string(), {}, notes);
  ASSERT_EQ(result.tests.size(), 1u);
  EXPECT_EQ(result.tests[0].run_error,
            "the run took longer than its time limit of 1e-06 s (wall clock) and was stopped");
  EXPECT_EQ(result.points, 0);
}

// run_autograder's deadline: a test not started by then is not run, with
// the reason, and the tests graded before keep their points.
TEST(GradeSubmissionTest, TestsNotStartedByTheDeadlineAreNotRunAndTheOthersKeepTheirPoints) {
  const Assignment tiny = LoadTiny();
  const fs::path out = Fresh("deadline");
  std::vector<std::string> notes;
  GradeOptions options;
  // The first test ends the grading's time: every later one finds the deadline passed.
  options.deadline = std::chrono::steady_clock::time_point::max();
  options.on_test = [&options](const assignment::TestResult&) { options.deadline = std::chrono::steady_clock::now(); };

  const SubmissionResult result = GradeSubmission(tiny, kReference.string(), out.string(), options, notes);

  ASSERT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 3u);
  EXPECT_TRUE(result.tests[0].passed);
  EXPECT_EQ(result.tests[0].run_error, "");
  for (size_t index : {1u, 2u}) {
    EXPECT_EQ(result.tests[index].run_error, kNotRunDeadline) << result.tests[index].name;
    EXPECT_EQ(result.tests[index].points, 0);
  }
  EXPECT_EQ(result.points, 20) << "the first test's share, 60 / 3";
}

// results.json while grading runs: valid JSON at every write, the tests
// graded so far with their points, the others said not graded; at the end
// the reports' bytes.
TEST(LiveResultsFileTest, HoldsTheTestsGradedSoFarAndAtTheEndTheReportsBytes) {
  const Assignment tiny = LoadTiny();
  const fs::path out = Fresh("live_results");
  std::vector<std::string> notes;
  GradeOptions options;
  const SubmissionResult graded = GradeSubmission(tiny, kReference.string(), out.string(), options, notes);
  ASSERT_EQ(graded.points, 60);
  SubmissionResult planned;
  planned.assignment = tiny.name;
  planned.title = tiny.title;
  planned.tests = PlanTests(tiny, false);
  const fs::path path = out / "live.json";
  LiveResultsFile live(path.string(), tiny, planned);

  ASSERT_EQ(live.Begin(), std::nullopt);
  const std::string begun = Read(path);
  EXPECT_NE(begun.find("\"score\": 0"), std::string::npos) << begun;
  EXPECT_NE(begun.find(LiveResultsFile::kNotGraded), std::string::npos) << begun;

  ASSERT_EQ(live.Record(graded.tests[0]), std::nullopt);
  const std::string one = Read(path);
  EXPECT_NE(one.find("\"score\": 20"), std::string::npos) << one;
  EXPECT_NE(one.find("\"status\": \"passed\""), std::string::npos) << one;
  EXPECT_NE(one.find(LiveResultsFile::kNotGraded), std::string::npos) << "two tests not graded yet: " << one;
  EXPECT_FALSE(fs::exists(path.string() + ".partial")) << "each write is renamed into place";

  ASSERT_EQ(live.Finish(graded), std::nullopt);
  ASSERT_EQ(WriteSubmissionOutputs(graded, "hash", notes, out.string()), std::nullopt);
  EXPECT_EQ(Read(path), Read(out / "results.json"));
}

TEST(GradeSubmissionTest, WithoutTheHiddenFilesOnlyPublicTestsAreGraded) {
  const fs::path copy = Fresh("student_copy");
  fs::copy(kTiny, copy, fs::copy_options::recursive);
  fs::remove_all(copy / "hidden");
  assignment::LoadOptions load;
  load.allow_missing_hidden = true;
  const assignment::LoadResult loaded = assignment::LoadAssignmentFile(copy.string(), load);
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();
  EXPECT_TRUE(loaded.assignment->hidden_missing);
  EXPECT_TRUE(loaded.assignment->hidden_runs.empty());
  EXPECT_EQ(PlanTests(*loaded.assignment, false).size(), 2u);
  EXPECT_FALSE(assignment::LoadAssignmentFile(copy.string()).ok()) << "without the option a missing file is an error";
}

// An app that assumes every epoch is COOPERATIVE and dereferences NULL in
// an AUTONOMOUS one: only a loss pattern that leaves a robot out shows it.
constexpr const char* kAssumesCooperative = R"(#include <stddef.h>
#include "syrof/app.h"
static uint8_t Init(const syrof_app_info* info) { (void)info; return 0; }
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command, (void)clock_ms, (void)state;
  if (map->mode == SYROF_MODE_AUTONOMOUS) { volatile int* volatile nowhere = NULL; *nowhere = 1; }
  return (uint8_t)map->epoch;
}
static uint8_t EndOfRound(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map, (void)clock_ms;
  return state;
}
SYROF_APP_DEFINE("assumes_cooperative", Init, NewRound, EndOfRound)
)";

// ---- What students are shown --------------------------------------------------

// Every robot returns its own id as the global state: the agreement is lost
// in every run, so every run (public and hidden) keeps a replay.
constexpr const char* kDisagrees = R"(#include "syrof/app.h"
static uint8_t self;
static uint8_t Init(const syrof_app_info* info) { self = (uint8_t)info->self_id; return self; }
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command, (void)map, (void)state, (void)clock_ms;
  return self;
}
static uint8_t EndOfRound(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map, (void)clock_ms;
  return state;
}
SYROF_APP_DEFINE("disagrees", Init, NewRound, EndOfRound)
)";

// report.html's table row of test `number` (from 1).
std::string Row(const std::string& report, int number) {
  const size_t begin = report.find("<tr id=\"test-" + std::to_string(number) + "\"");
  if (begin == std::string::npos) return {};
  return report.substr(begin, report.find("</tr>", begin) - begin);
}

// Graded in a temporary folder: what students see (results.json,
// report.html in the student's form, the viewer pages it frames) names no
// absolute path, neither the grader's folders nor the source tree's; the
// student's library, not the scenario's `app:`, is the run's app; and the
// hidden run shows nothing but its name, points and verdict until the
// instructor asks for the full form.
TEST(GradeOutputsTest, StudentOutputsNameNoAbsolutePathTheStudentsLibraryAndNoHiddenRun) {
  const Assignment tiny = LoadTiny();
  const fs::path root = Fresh("student_outputs");
  const fs::path submission = root / "bob";
  Write(submission / "app.c", kDisagrees);
  const fs::path out = root / "graded" / "bob";
  GradeOptions options;
  options.jobs = 2;
  std::vector<std::string> notes;

  const SubmissionResult result = GradeSubmission(tiny, submission.string(), out.string(), options, notes);
  ASSERT_EQ(WriteSubmissionOutputs(result, "hash", notes, out.string()), std::nullopt);

  ASSERT_TRUE(result.build.ok()) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 3u);
  for (const assignment::TestResult& test : result.tests) {
    ASSERT_FALSE(test.passed) << test.name;
    ASSERT_FALSE(test.replay_path.empty()) << test.name;
  }
  const std::string library = "build/" + fs::path(result.build.library_path).filename().string();
  EXPECT_EQ(result.tests[0].replay_command,
            "syrof run tiny/scenarios/tiny.yaml --app " + library + " --seed 1 --out rerun/tiny-seed-1");
  // The run's app is the student's library, in metrics.json and the replay
  // (the viewer's page shows the replay header's app).
  const std::string metrics = Read(out / "runs/tiny/seed-1/metrics.json");
  EXPECT_NE(metrics.find("\"source\": \"" + library + "\""), std::string::npos) << metrics.substr(0, 400);
  EXPECT_EQ(metrics.find("builtin:gather"), std::string::npos) << metrics;
  const std::string page = Read(out / "runs/tiny/seed-1/replay.html");
  EXPECT_NE(page.find(library), std::string::npos);
  EXPECT_EQ(page.find("builtin:gather"), std::string::npos);

  // No absolute path: not the temporary folder's, not the source tree's.
  const std::string clone = fs::path(SYROF_ASSIGNMENTS_DIR).parent_path().string();
  std::vector<fs::path> shown = {out / "results.json", out / "report.html"};
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(out / "runs")) {
    if (entry.path().filename() == "replay.html") shown.push_back(entry.path());
  }
  EXPECT_EQ(shown.size(), 4u) << "the two public failing runs' viewer pages";
  for (const fs::path& file : shown) {
    const std::string bytes = Read(file);
    ASSERT_FALSE(bytes.empty()) << file;
    EXPECT_EQ(bytes.find(root.string()), std::string::npos) << file;
    EXPECT_EQ(bytes.find(clone), std::string::npos) << file;
  }

  // The hidden run: its row, and nothing of its scenario, reasons or viewer.
  const std::string report = Read(out / "report.html");
  EXPECT_NE(report.find("<code>secret/seed-3</code></td><td>hidden</td>"), std::string::npos);
  EXPECT_EQ(report.find("tiny_hidden"), std::string::npos);
  EXPECT_EQ(report.find("runs/secret/seed-3/replay.html"), std::string::npos);
  EXPECT_FALSE(fs::exists(out / "runs/secret/seed-3/replay.html"));
  EXPECT_EQ(Row(report, 3).find("agreement"), std::string::npos) << "no reason of the hidden run: " << Row(report, 3);
  EXPECT_NE(Row(report, 1).find("agreement"), std::string::npos) << Row(report, 1);

  // The instructor's full form shows it whole, still with no absolute path.
  ASSERT_EQ(WriteSubmissionOutputs(result, "hash", notes, out.string(), true), std::nullopt);
  const std::string full = Read(out / "report.html");
  EXPECT_NE(full.find("runs/secret/seed-3/replay.html"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "runs/secret/seed-3/replay.html"));
  EXPECT_NE(Row(full, 3).find("agreement"), std::string::npos) << Row(full, 3);
  EXPECT_EQ(full.find(root.string()), std::string::npos);
  fs::remove_all(root);
}

TEST(SearchGradeTest, TheReferenceSurvivesTheSearchTestAndEarnsItsPoints) {
  const Assignment searched = LoadTiny("search.yaml");
  ASSERT_EQ(searched.search_tests.size(), 1u);
  const fs::path out = Fresh("search_reference");
  std::vector<std::string> notes;
  const SubmissionResult result = GradeSubmission(searched, kReference.string(), out.string(), {}, notes);
  ASSERT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 2u);
  const assignment::TestResult& search = result.tests[1];
  EXPECT_EQ(search.name, "search/tiny_vote1");
  EXPECT_TRUE(search.search);
  EXPECT_EQ(result.tests[0].max_points, 40);
  EXPECT_EQ(search.max_points, 20);
  EXPECT_TRUE(search.passed) << FirstLoss(search);
  EXPECT_NE(search.score.criteria.at(0).reason.find("no pattern of up to 1 lost beacon in the first 1 epoch broke it"),
            std::string::npos)
      << search.score.criteria.at(0).reason;
  EXPECT_NE(search.replay_command.find("syrof search "), std::string::npos) << search.replay_command;
  EXPECT_EQ(result.points, 60);
}

TEST(SearchGradeTest, AnAppThatFailsInAnAutonomousEpochLosesTheSearchTestWithACounterexample) {
  const Assignment searched = LoadTiny("search.yaml");
  const fs::path submission = Fresh("search_broken_in");
  Write(submission / "app.c", kAssumesCooperative);
  const fs::path out = Fresh("search_broken");
  std::vector<std::string> notes;
  const SubmissionResult result = GradeSubmission(searched, submission.string(), out.string(), {}, notes);
  ASSERT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 2u);
  const assignment::TestResult& search = result.tests[1];
  EXPECT_FALSE(search.passed);
  EXPECT_EQ(search.points, 0);
  const std::string& reason = search.score.criteria.at(0).reason;
  EXPECT_NE(reason.find("broken by 1 lost beacon"), std::string::npos) << reason;
  EXPECT_NE(reason.find("app fault"), std::string::npos) << reason;
  EXPECT_EQ(search.replay_path, "search/tiny_vote1/replay");
  EXPECT_TRUE(fs::exists(out / "search" / "tiny_vote1" / "counterexample.yaml"));
  EXPECT_TRUE(fs::exists(out / search.replay_path));
  EXPECT_EQ(assignment::LostCriteria(result).back(), "search");
}

// GradeOptions::fork_server = false (the benches' switch): the search test
// starts a fresh host per robot and pattern, and finds the same
// counterexample, scored and written byte for byte as with the fork server
// (the same library graded twice, so the files name the same path).
TEST(SearchGradeTest, WithoutTheForkServerTheSearchTestFindsTheSameCounterexample) {
  const Assignment searched = LoadTiny("search.yaml");
  const fs::path submission = Fresh("search_fresh_in");
  Write(submission / "app.c", kAssumesCooperative);
  const fs::path built = Fresh("search_fresh_built");
  std::vector<std::string> notes;
  const SubmissionResult first = GradeSubmission(searched, submission.string(), built.string(), {}, notes);
  ASSERT_EQ(first.build.verdict, assignment::BuildVerdict::kOk) << first.build.detail;
  const fs::path forked_out = Fresh("search_forked");
  const fs::path fresh_out = Fresh("search_fresh");
  const SubmissionResult forked = GradeLibrary(searched, first.build.library_path, forked_out.string(), {});
  GradeOptions fresh_hosts;
  fresh_hosts.fork_server = false;
  const SubmissionResult fresh = GradeLibrary(searched, first.build.library_path, fresh_out.string(), fresh_hosts);
  ASSERT_EQ(forked.tests.size(), 2u);
  ASSERT_EQ(fresh.tests.size(), 2u);
  const assignment::TestResult& search = fresh.tests[1];
  EXPECT_FALSE(search.passed);
  EXPECT_NE(search.score.criteria.at(0).reason.find("broken by 1 lost beacon"), std::string::npos)
      << search.score.criteria.at(0).reason;
  EXPECT_EQ(search.score.criteria.at(0).reason, forked.tests[1].score.criteria.at(0).reason);
  EXPECT_EQ(fresh.points, forked.points);
  ASSERT_TRUE(fs::exists(fresh_out / "search" / "tiny_vote1" / "counterexample.yaml"));
  const auto fresh_files = Snapshot(fresh_out);
  EXPECT_EQ(fresh_files, Snapshot(forked_out));
  EXPECT_EQ(fresh_files.count("search/tiny_vote1/replay"), 1u);
}

// Holds still; its global state counts its own newRound calls: under FSYNC
// every robot's count agrees, under SSYNC a robot left out falls behind.
constexpr const char* kCountsTurns = R"(#include "syrof/app.h"
static uint8_t Init(const syrof_app_info* info) { (void)info; return 0; }
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command, (void)map, (void)clock_ms;
  return (uint8_t)(state + 1);
}
static uint8_t EndOfRound(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map, (void)clock_ms;
  return state;
}
SYROF_APP_DEFINE("counts_turns", Init, NewRound, EndOfRound)
)";

// A schedule search test (`activations: ssync`): the grader runs the same
// activation search as `syrof search --activations ssync`.
TEST(SearchGradeTest, TheReferenceSurvivesEveryScheduleOfAScheduleSearchTest) {
  const Assignment scheduled = LoadTiny("schedules.yaml");
  ASSERT_EQ(scheduled.search_tests.size(), 2u);
  ASSERT_TRUE(scheduled.search_tests[0].activations);
  const fs::path out = Fresh("schedules_reference");
  std::vector<std::string> notes;
  const SubmissionResult result = GradeSubmission(scheduled, kReference.string(), out.string(), {}, notes);
  ASSERT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 4u);
  EXPECT_TRUE(result.tests[1].passed) << "under the scripted schedule too: " << FirstLoss(result.tests[1]);
  const assignment::TestResult& search = result.tests[2];
  EXPECT_EQ(search.name, "search/tiny_ssync");
  EXPECT_TRUE(search.passed) << FirstLoss(search);
  EXPECT_NE(search.score.criteria.at(0).reason.find("no SSYNC schedule in the first 2 epochs broke it (49 runs)"),
            std::string::npos)
      << search.score.criteria.at(0).reason;
  EXPECT_NE(search.replay_command.find(" --activations ssync --epochs 2 "), std::string::npos) << search.replay_command;
  EXPECT_EQ(search.replay_command.find("--max-losses"), std::string::npos) << search.replay_command;
  // The budget reaches the search: of the 22 schedules leaving at most 2
  // robot-epochs out, the 3 leaving one robot out of both epochs are not run.
  const assignment::TestResult& fair = result.tests[3];
  EXPECT_TRUE(fair.passed) << FirstLoss(fair);
  EXPECT_NE(fair.score.criteria.at(0).reason.find("no SSYNC schedule of up to 2 robot-epochs out in the first 2 "
                                                  "epochs that leaves no robot out of 2 epochs in a row broke it "
                                                  "(19 runs)"),
            std::string::npos)
      << fair.score.criteria.at(0).reason;
  EXPECT_NE(fair.replay_command.find(" --activations ssync --max-inactive 2 --fair-within 2 --epochs 2 "),
            std::string::npos)
      << fair.replay_command;
  EXPECT_EQ(result.points, 60);
}

TEST(SearchGradeTest, AnAppThatCountsItsTurnsLosesTheScheduleSearchTestWithACounterexample) {
  const Assignment scheduled = LoadTiny("schedules.yaml");
  const fs::path submission = Fresh("schedules_counts_turns_in");
  Write(submission / "app.c", kCountsTurns);
  const fs::path out = Fresh("schedules_counts_turns");
  std::vector<std::string> notes;
  const SubmissionResult result = GradeSubmission(scheduled, submission.string(), out.string(), {}, notes);
  ASSERT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 4u);
  // A set runs its scenario file's own activation model: the FSYNC run's
  // counts agree, the scripted run's do not (robot 3 falls one behind).
  const auto agreement = [](const assignment::TestResult& test) {
    for (const assignment::CriterionScore& criterion : test.score.criteria) {
      if (criterion.criterion == "agreement") return criterion;
    }
    return assignment::CriterionScore{};
  };
  EXPECT_EQ(agreement(result.tests[0]).points, agreement(result.tests[0]).max_points) << agreement(result.tests[0]).reason;
  EXPECT_GT(agreement(result.tests[0]).max_points, 0);
  EXPECT_LT(agreement(result.tests[1]).points, agreement(result.tests[1]).max_points) << agreement(result.tests[1]).reason;
  const assignment::TestResult& search = result.tests[2];
  EXPECT_FALSE(search.passed);
  EXPECT_EQ(search.points, 0);
  const std::string& reason = search.score.criteria.at(0).reason;
  EXPECT_NE(reason.find("broken by a schedule leaving 1 robot-epoch out [epoch: robot]: [1: 0]"), std::string::npos)
      << reason;
  EXPECT_NE(reason.find("agreement"), std::string::npos) << reason;
  const std::string counterexample = Read(out / "search" / "tiny_ssync" / "counterexample.yaml");
  EXPECT_NE(counterexample.find("schedule: scripted"), std::string::npos) << counterexample;
  EXPECT_TRUE(fs::exists(out / search.replay_path));
}

// An ASYNC search test (tiny/async.yaml): the reference survives the 10
// schedules; an app counting its turns is broken by the first cycle that
// moves over two epochs, with a counterexample of scripted cycles.
TEST(SearchGradeTest, AnAsyncSearchTestKeepsTheReferenceAndBreaksAnAppCountingItsTurns) {
  const Assignment asynchronous = LoadTiny("async.yaml");
  ASSERT_EQ(asynchronous.search_tests.size(), 1u);
  ASSERT_TRUE(asynchronous.search_tests[0].async);
  std::vector<std::string> notes;
  const fs::path reference_out = Fresh("async_reference");
  const SubmissionResult reference =
      GradeSubmission(asynchronous, kReference.string(), reference_out.string(), {}, notes);
  ASSERT_EQ(reference.build.verdict, assignment::BuildVerdict::kOk) << reference.build.detail;
  ASSERT_EQ(reference.tests.size(), 2u);
  const assignment::TestResult& survived = reference.tests[1];
  EXPECT_TRUE(survived.passed) << FirstLoss(survived);
  EXPECT_NE(survived.score.criteria.at(0).reason.find("no ASYNC schedule of up to 1 deviating cycle in the first 1 "
                                                      "epoch with delays up to 1 epoch broke it (10 runs)"),
            std::string::npos)
      << survived.score.criteria.at(0).reason;
  EXPECT_NE(survived.replay_command.find(" --activations async --max-delay 1 --max-deviations 1 --epochs 1 "),
            std::string::npos)
      << survived.replay_command;
  EXPECT_EQ(reference.points, 60);

  const fs::path submission = Fresh("async_counts_turns_in");
  Write(submission / "app.c", kCountsTurns);
  const fs::path out = Fresh("async_counts_turns");
  const SubmissionResult result = GradeSubmission(asynchronous, submission.string(), out.string(), {}, notes);
  ASSERT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail;
  const assignment::TestResult& search = result.tests.at(1);
  EXPECT_FALSE(search.passed);
  const std::string& reason = search.score.criteria.at(0).reason;
  EXPECT_NE(reason.find("broken by a schedule with 1 deviating cycle [look epoch, robot, start_delay, "
                        "move_epochs(, cut)]: [1, 0, 0, 2]"),
            std::string::npos)
      << reason;
  const std::string counterexample = Read(out / "search" / "tiny_async" / "counterexample.yaml");
  EXPECT_NE(counterexample.find("model: async"), std::string::npos) << counterexample;
  EXPECT_NE(counterexample.find("schedule: scripted"), std::string::npos) << counterexample;
  EXPECT_TRUE(fs::exists(out / search.replay_path));
}

// The hostile libraries as a class, with a good submission (the gather
// reference, a CMake project) and one that does not compile.
class ClassTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    submissions_ = new fs::path(Fresh("class_in"));
    fs::copy(kReference, *submissions_ / "good", fs::copy_options::recursive);
    for (const char* library : {"segfault", "infinite_loop", "flood_output", "missing_entry", "fork"}) {
      HostileSubmission(*submissions_ / library, library);
    }
    Write(*submissions_ / "syntax" / "app.c", "this is not C\n");
  }
  static void TearDownTestSuite() { delete submissions_; }
  static ClassResult Grade(const fs::path& out, Shard shard = {}, bool resume = true) {
    ClassOptions options;
    options.jobs = 2;
    options.shard = shard;
    options.resume = resume;
    options.assignment_dir = kTiny.string();
    return GradeClass(LoadTiny(), submissions_->string(), out.string(), options);
  }
  static fs::path* submissions_;
};
fs::path* ClassTest::submissions_ = nullptr;

TEST_F(ClassTest, EachSubmissionGetsItsVerdictRerunsAreIdenticalAndShardsMerge) {
  const fs::path out = Fresh("class_out");
  const ClassResult first = Grade(out);
  ASSERT_EQ(first.students.size(), 7u);
  std::map<std::string, SubmissionResult> by_name;
  for (const SubmissionResult& student : first.students) by_name[student.submission] = student;

  EXPECT_EQ(by_name["good"].points, 60) << "the others' crashes, loops and floods cost it nothing";
  EXPECT_EQ(by_name["syntax"].build.verdict, assignment::BuildVerdict::kBuildFailed);
  EXPECT_EQ(by_name["missing_entry"].build.verdict, assignment::BuildVerdict::kBadLibrary);
  EXPECT_NE(by_name["missing_entry"].build.detail.find("syrof_app_entry"), std::string::npos)
      << by_name["missing_entry"].build.detail;
  for (const char* name : {"segfault", "infinite_loop", "flood_output", "fork"}) {
    const SubmissionResult& student = by_name[name];
    EXPECT_EQ(student.build.verdict, assignment::BuildVerdict::kOk) << name << ": " << student.build.detail;
    EXPECT_LT(student.points, 60) << name;
    ASSERT_FALSE(student.tests.empty());
    EXPECT_TRUE(student.tests[0].run_error.empty()) << name << ": " << student.tests[0].run_error;
    EXPECT_FALSE(FirstLoss(student.tests[0]).empty()) << name;
    EXPECT_FALSE(student.tests[0].replay_path.empty()) << name << ": a failed run keeps its replay";
    EXPECT_TRUE(fs::exists(out / name / student.tests[0].replay_path)) << name;
  }
  EXPECT_NE(FaultReason(by_name["segfault"]).find("crashed"), std::string::npos) << FaultReason(by_name["segfault"]);
  EXPECT_NE(FaultReason(by_name["infinite_loop"]).find("timeout"), std::string::npos) << FaultReason(by_name["infinite_loop"]);
  EXPECT_NE(FaultReason(by_name["flood_output"]).find("output_limit"), std::string::npos) << FaultReason(by_name["flood_output"]);
  EXPECT_NE(FaultReason(by_name["fork"]).find("forbidden_syscall"), std::string::npos) << FaultReason(by_name["fork"]);

  const std::string csv = Read(out / "class.csv");
  EXPECT_TRUE(csv.starts_with("student,points,max_points,tests_passed,tests,build,tiny,secret\n")) << csv;
  EXPECT_NE(csv.find("\ngood,60.00,60.00,3,3,ok,40.00,20.00\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nsyntax,0.00,60.00,0,3,build_failed,0.00,0.00\n"), std::string::npos) << csv;
  EXPECT_NE(Read(out / "summary.txt").find("Builds failed: 2\n"), std::string::npos) << Read(out / "summary.txt");

  // Determinism: the same class graded again into the same folder.
  const std::map<std::string, std::string> before = Snapshot(out);
  const fs::path kept = out.string() + "_first";
  fs::rename(out, kept);
  const ClassResult second = Grade(out, {}, /*resume=*/false);
  EXPECT_EQ(second.graded, 7);
  const std::map<std::string, std::string> after = Snapshot(out);
  ASSERT_EQ(before.size(), after.size());
  for (const auto& [name, bytes] : before) {
    EXPECT_TRUE(bytes == after.at(name)) << name << " differs between two gradings";
  }

  // Resume: nothing changed, nothing graded again.
  const ClassResult third = Grade(out);
  EXPECT_EQ(third.resumed, 7);
  EXPECT_EQ(third.graded, 0);
  EXPECT_EQ(Read(out / "class.csv"), before.at("class.csv"));

  // Shards, merged, give the unsharded class's CSV and summary.
  const fs::path shard1 = Fresh("class_shard1");
  const fs::path shard2 = Fresh("class_shard2");
  EXPECT_EQ(Grade(shard1, {1, 2}).students.size(), 3u);
  EXPECT_EQ(Grade(shard2, {2, 2}).students.size(), 4u);
  const fs::path merged = Fresh("class_merged");
  const MergedClass both = MergeClassOutputs({shard1.string(), shard2.string()}, merged.string());
  ASSERT_TRUE(both.ok()) << both.error->ToString();
  EXPECT_EQ(both.students->size(), 7u);
  EXPECT_FALSE(both.error);
  EXPECT_EQ(Read(merged / "class.csv"), before.at("class.csv"));
  EXPECT_EQ(Read(merged / "summary.txt"), before.at("summary.txt"));
  const MergedClass twice = MergeClassOutputs({shard1.string(), shard1.string()}, merged.string());
  ASSERT_FALSE(twice.ok());
  EXPECT_EQ(twice.error->ToString(), "student '" + ListStudents(shard1.string()).front() +
                                         "' is in two of the folders merged (" +
                                         (shard1 / ListStudents(shard1.string()).front() / "grade.json").string() + ")");
  const MergedClass not_a_folder = MergeClassOutputs({(shard1 / "class.csv").string()}, merged.string());
  ASSERT_FALSE(not_a_folder.ok());
  EXPECT_EQ(not_a_folder.error->ToString(), (shard1 / "class.csv").string() + ": not a folder");

  // A shard stopped on the way is refused by name, not merged short.
  const fs::path stopped = Fresh("class_shard2_stopped");
  fs::copy(shard2, stopped, fs::copy_options::recursive);
  fs::remove(stopped / "class.csv");
  const fs::path short_merge = Fresh("class_merged_short");
  const MergedClass unfinished = MergeClassOutputs({shard1.string(), stopped.string()}, short_merge.string());
  ASSERT_FALSE(unfinished.ok());
  EXPECT_EQ(unfinished.error->ToString(), stopped.string() + ": this shard did not finish (it has no class.csv): grade "
                                                               "it again, it resumes where it stopped");
  fs::copy_file(shard2 / "class.csv", stopped / "class.csv");
  const std::string student = ListStudents(stopped.string()).back();
  fs::remove(stopped / student / "grade.json");
  const MergedClass no_grade = MergeClassOutputs({shard1.string(), stopped.string()}, short_merge.string());
  ASSERT_FALSE(no_grade.ok());
  EXPECT_EQ(no_grade.error->ToString(), (stopped / student).string() +
                                            ": no grade.json: this shard did not finish grading the student: grade it "
                                            "again, it resumes");
  EXPECT_FALSE(fs::exists(short_merge / "class.csv"));
}

// A broken variant whose project cannot be made is not graded, and says why.
TEST(AssignmentCheckTest, AVariantWithoutTheScriptIsNotMadeAndSaysWhy) {
  CheckSubject variant;
  variant.name = "broken/off_by_one";
  variant.role = SubjectRole::kBrokenVariant;
  variant.variant = "off_by_one";
  CheckOptions options;
  options.broken_variant_script = "/nonexistent/broken-variant.sh";
  const std::vector<SubjectOutcome> outcomes =
      CheckAssignment(LoadTiny(), {variant}, Fresh("check_no_script").string(), options);
  ASSERT_EQ(outcomes.size(), 1u);
  EXPECT_EQ(outcomes[0].problems, std::vector<std::string>{"cannot make the variant: scripts/broken-variant.sh was not "
                                                           "found (looked for /nonexistent/broken-variant.sh)"});
  EXPECT_EQ(outcomes[0].result.build.verdict, assignment::BuildVerdict::kNotMade);
  EXPECT_TRUE(outcomes[0].result.tests.empty());
}

// Hidden seeds per student (student_seeds.h): the derived seeds reach the
// result, grade.json and a replay command, and that command's seed runs
// the same run again.
constexpr const char* kCourseSecret = "0123456789abcdef-course-secret";

TEST(StudentSeedsGradeTest, HiddenRunsUseTheStudentsSeedsAndTheReplayCommandReproducesThem) {
  const Assignment tiny = LoadTiny();
  const fs::path out = Fresh("student_seeds");
  GradeOptions options;
  options.student_seeds = StudentSeeds{kCourseSecret, "alice@example.edu"};
  std::vector<std::string> notes;
  const SubmissionResult result = GradeSubmission(tiny, kReference.string(), out.string(), options, notes);
  ASSERT_TRUE(result.build.ok()) << result.build.detail;
  ASSERT_EQ(result.tests.size(), 3u);
  const uint64_t derived = DeriveSeed(kCourseSecret, "Tiny gather", "secret", "alice@example.edu", 0);
  EXPECT_EQ(result.seed_student, "alice@example.edu");
  EXPECT_EQ(result.tests[0].seed, 1u) << "public seeds stay as listed";
  EXPECT_EQ(result.tests[1].seed, 2u);
  EXPECT_FALSE(result.tests[0].replay_command.empty());
  const assignment::TestResult& hidden = result.tests[2];
  EXPECT_EQ(hidden.seed, derived);
  EXPECT_EQ(hidden.name, "secret/seed-" + std::to_string(derived));
  EXPECT_EQ(hidden.output_dir, "runs/secret/seed-" + std::to_string(derived));
  EXPECT_NE(hidden.replay_command.find("hidden/tiny_hidden.yaml"), std::string::npos) << hidden.replay_command;
  EXPECT_NE(hidden.replay_command.find(" --seed " + std::to_string(derived) + " "), std::string::npos)
      << hidden.replay_command;

  // grade.json keeps the student and the seeds.
  ASSERT_EQ(WriteSubmissionOutputs(result, "hash", notes, out.string()), std::nullopt);
  const GradeFileOrError read_json = ReadGradeJson((out / "grade.json").string());
  ASSERT_TRUE(read_json.ok()) << read_json.error->ToString();
  const std::optional<GradeFile>& read = read_json.file;
  EXPECT_EQ(read->result.seed_student, "alice@example.edu");
  EXPECT_EQ(read->result.tests[2].seed, derived);
  EXPECT_EQ(read->result.tests[2].replay_command, hidden.replay_command);
  EXPECT_EQ(Read(out / "results.json").find("tiny_hidden.yaml"), std::string::npos)
      << "the student's results.json names no hidden scenario";

  // The command's seed, listed in the assignment, gives the same run.
  const size_t at = hidden.replay_command.find(" --seed ") + 8;
  const uint64_t command_seed = std::stoull(hidden.replay_command.substr(at));
  Assignment listed = tiny;
  listed.hidden_runs[0].seeds = {command_seed};
  const fs::path rerun = Fresh("student_seeds_rerun");
  // The library where the grader puts it, so metrics.json names it the same
  // (relative to the output folder).
  const fs::path library = rerun / "build" / fs::path(result.build.library_path).filename();
  fs::create_directories(library.parent_path());
  fs::copy_file(result.build.library_path, library);
  const SubmissionResult again = GradeLibrary(listed, library.string(), rerun.string(), {});
  ASSERT_EQ(again.tests.size(), 3u);
  EXPECT_EQ(again.tests[2].name, hidden.name);
  const std::string metrics = Read(out / hidden.output_dir / "metrics.json");
  EXPECT_FALSE(metrics.empty());
  EXPECT_EQ(Read(rerun / again.tests[2].output_dir / "metrics.json"), metrics);

  // Another student, other hidden seeds.
  options.student_seeds->student = "bob@example.edu";
  const std::vector<assignment::TestResult> bob = PlanTests(GradedAssignment(tiny, options), false);
  EXPECT_NE(bob[2].seed, derived);
  EXPECT_EQ(bob[0].seed, 1u);
}

TEST(StudentSeedsGradeTest, AClassDerivesEachStudentsSeedsFromItsFolderName) {
  const fs::path submissions = Fresh("seed_class_in");
  fs::copy(kReference, submissions / "alice", fs::copy_options::recursive);
  fs::copy(kReference, submissions / "bob", fs::copy_options::recursive);
  const fs::path out = Fresh("seed_class_out");
  ClassOptions options;
  options.jobs = 2;
  options.assignment_dir = kTiny.string();
  options.grade.student_seeds = StudentSeeds{kCourseSecret, "ignored"};
  const ClassResult first = GradeClass(LoadTiny(), submissions.string(), out.string(), options);
  ASSERT_EQ(first.students.size(), 2u);
  for (const SubmissionResult& student : first.students) {
    EXPECT_EQ(student.seed_student, student.submission);
    ASSERT_EQ(student.tests.size(), 3u);
    EXPECT_EQ(student.tests[2].seed, DeriveSeed(kCourseSecret, "Tiny gather", "secret", student.submission, 0));
    EXPECT_EQ(student.points, 60) << student.submission;
    const GradeFileOrError read_json = ReadGradeJson((out / student.submission / "grade.json").string());
    ASSERT_TRUE(read_json.ok()) << read_json.error->ToString();
    const std::optional<GradeFile>& read = read_json.file;
    EXPECT_EQ(read->result.tests[2].seed, student.tests[2].seed);
  }
  EXPECT_NE(first.students[0].tests[2].seed, first.students[1].tests[2].seed);

  // The same secret resumes; another secret derives other seeds: regraded.
  EXPECT_EQ(GradeClass(LoadTiny(), submissions.string(), out.string(), options).resumed, 2);
  options.grade.student_seeds->course_secret = "another-course-secret-0123";
  const ClassResult again = GradeClass(LoadTiny(), submissions.string(), out.string(), options);
  EXPECT_EQ(again.graded, 2);
  EXPECT_NE(again.students[0].tests[2].seed, first.students[0].tests[2].seed);
}

// A class's reports are the student's form unless the full one is asked;
// a resumed class switches forms without grading again.
TEST(ClassReportFormTest, EachStudentsReportIsTheStudentFormAndAResumedClassSwitchesForms) {
  const fs::path submissions = Fresh("form_class_in");
  Write(submissions / "bob" / "app.c", kDisagrees);
  const fs::path out = Fresh("form_class_out");
  const fs::path report = out / "bob" / "report.html";
  const fs::path hidden_page = out / "bob" / "runs/secret/seed-3/replay.html";
  ClassOptions options;
  options.assignment_dir = kTiny.string();

  ASSERT_EQ(GradeClass(LoadTiny(), submissions.string(), out.string(), options).graded, 1);
  EXPECT_EQ(Read(report).find("instructor's full report"), std::string::npos);
  EXPECT_EQ(Row(Read(report), 3).find("agreement"), std::string::npos) << Row(Read(report), 3);
  EXPECT_FALSE(fs::exists(hidden_page));

  options.full_report = true;
  ASSERT_EQ(GradeClass(LoadTiny(), submissions.string(), out.string(), options).resumed, 1);
  EXPECT_NE(Read(report).find("instructor's full report"), std::string::npos);
  EXPECT_NE(Row(Read(report), 3).find("agreement"), std::string::npos) << Row(Read(report), 3);
  EXPECT_TRUE(fs::exists(hidden_page));

  options.full_report = false;
  ASSERT_EQ(GradeClass(LoadTiny(), submissions.string(), out.string(), options).resumed, 1);
  EXPECT_EQ(Read(report).find("instructor's full report"), std::string::npos);
  EXPECT_FALSE(fs::exists(hidden_page));
  fs::remove_all(submissions);
  fs::remove_all(out);
}

TEST(MixTest, NamesTheSubmissionWhoseRobotsFaulted) {
  const Assignment tiny = LoadTiny();
  const fs::path segfault = Fresh("mix_segfault_in");
  HostileSubmission(segfault, "segfault");
  const fs::path out = Fresh("mix");
  std::vector<MixEntry> entries;
  for (const auto& [name, folder] : {std::pair{"good", kReference}, std::pair{"bad", segfault}}) {
    std::vector<std::string> notes;
    const assignment::BuildResult build = BuildSubmission(folder.string(), (out / "builds" / name).string(), {}, notes);
    ASSERT_TRUE(build.ok()) << build.detail;
    entries.push_back({name, build.library_path});
  }
  GradeOptions options;
  options.public_only = true;
  const std::vector<MixRun> runs = RunMix(tiny, entries, out.string(), options);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].shares[0].robots, (std::vector<uint16_t>{0, 2}));
  EXPECT_EQ(runs[0].shares[0].faults, 0);
  EXPECT_EQ(runs[0].shares[1].faults, 2);
  std::ostringstream report;
  PrintMixReport(runs, entries, report);
  EXPECT_NE(report.str().find("  good (robots 0,2): ok\n"), std::string::npos) << report.str();
  EXPECT_NE(report.str().find("  bad (robots 1,3): 2 faulted, first robot "), std::string::npos) << report.str();
}

// The strongest assignment's message format (2 bytes, charge u16be), on
// one public run: the reference with itself, then with broken/too_long
// (10-byte payloads, refused by sendMessageData).
class MixMessageTest : public ::testing::Test {
 protected:
  static Assignment LoadStrongest() {
    const assignment::LoadResult loaded =
        assignment::LoadAssignmentFile((fs::path(SYROF_ASSIGNMENTS_DIR) / "strongest").string());
    EXPECT_TRUE(loaded.ok()) << loaded.error->ToString();
    Assignment strongest = *loaded.assignment;
    strongest.public_runs.resize(1);
    strongest.public_runs[0].seeds = {1};
    strongest.search_tests.clear();  // the runs' payloads are what these tests read
    return strongest;
  }

  static std::vector<MixRun> Mix(const Assignment& strongest, const fs::path& out,
                                 const std::vector<std::pair<std::string, fs::path>>& folders,
                                 std::vector<MixEntry>& entries) {
    for (const auto& [name, folder] : folders) {
      std::vector<std::string> notes;
      const assignment::BuildResult build =
          BuildSubmission(folder.string(), (out / "builds" / name).string(), {}, notes);
      EXPECT_TRUE(build.ok()) << build.detail;
      entries.push_back({name, build.library_path});
    }
    GradeOptions options;
    options.public_only = true;
    options.jobs = 1;
    return RunMix(strongest, entries, out.string(), options);
  }
};

TEST_F(MixMessageTest, TheReferenceMixedWithItselfGetsFullMarks) {
  const Assignment strongest = LoadStrongest();
  ASSERT_TRUE(strongest.message.has_value());
  const fs::path reference = fs::path(SYROF_ASSIGNMENTS_DIR) / "strongest" / "reference";
  std::vector<MixEntry> entries;
  const std::vector<MixRun> runs = Mix(strongest, Fresh("mix_strongest_self"), {{"a", reference}, {"b", reference}}, entries);
  ASSERT_EQ(runs.size(), 1u);
  ASSERT_EQ(runs[0].run_error, "");
  EXPECT_EQ(runs[0].score.points, runs[0].score.max_points);
  for (const MixShare& share : runs[0].shares) EXPECT_EQ(share.format_violations, 0);
  std::ostringstream report;
  PrintMixReport(runs, entries, report);
  EXPECT_EQ(report.str().find("message format broken"), std::string::npos) << report.str();
}

TEST_F(MixMessageTest, NamesTooLongAsTheSideThatBrokeTheFormat) {
  const Assignment strongest = LoadStrongest();
  const fs::path reference = fs::path(SYROF_ASSIGNMENTS_DIR) / "strongest" / "reference";
  const fs::path too_long = fs::path(SYROF_BROKEN_VARIANTS_DIR) / "strongest" / "broken" / "too_long";
  std::vector<MixEntry> entries;
  const std::vector<MixRun> runs =
      Mix(strongest, Fresh("mix_strongest_too_long"), {{"reference", reference}, {"too_long", too_long}}, entries);
  ASSERT_EQ(runs.size(), 1u);
  ASSERT_EQ(runs[0].run_error, "");
  EXPECT_EQ(runs[0].shares[0].format_violations, 0);
  EXPECT_EQ(runs[0].shares[1].format_violations, 3);  // robots 1, 3, 5: one refused payload each, in init
  std::ostringstream report;
  PrintMixReport(runs, entries, report);
  EXPECT_NE(report.str().find("  message format broken by: too_long\n"), std::string::npos) << report.str();
  EXPECT_NE(report.str().find("too_long (robots 1,3,5): broke the message format 3 times, first robot 1 in init of "
                              "epoch 0: 10 bytes, but the format has 2"),
            std::string::npos)
      << report.str();
}

// Graded alone, a submission whose payloads break the format hears so in
// its test (not scored): before a mixed swarm misreads them.
TEST_F(MixMessageTest, GradedAloneTooLongIsToldItsPayloadsBreakTheFormat) {
  const Assignment strongest = LoadStrongest();
  GradeOptions options;
  options.public_only = true;
  options.jobs = 1;
  std::vector<std::string> notes;
  const fs::path too_long = fs::path(SYROF_BROKEN_VARIANTS_DIR) / "strongest" / "broken" / "too_long";
  const SubmissionResult broken =
      GradeSubmission(strongest, too_long.string(), Fresh("alone_too_long").string(), options, notes);
  ASSERT_EQ(broken.tests.size(), 1u);
  EXPECT_NE(broken.tests[0].message_format.find("payloads broke the message format (robots 0,1,2,3,4,5), first robot "
                                                "0 in init of epoch 0: 10 bytes, but the format has 2"),
            std::string::npos)
      << broken.tests[0].message_format;
  std::ostringstream table;
  PrintSubmissionTable(broken, "out", table);
  EXPECT_NE(table.str().find("  message format: "), std::string::npos) << table.str();
  const fs::path json = Fresh("alone_too_long_json") / "grade.json";
  GradeFile file;
  file.result = broken;
  std::ofstream(json) << GradeJson(file);
  const GradeFileOrError read_json = ReadGradeJson(json.string());
  ASSERT_TRUE(read_json.ok()) << read_json.error->ToString();
  const std::optional<GradeFile>& read_back = read_json.file;
  ASSERT_EQ(read_back->result.tests.size(), 1u);
  EXPECT_EQ(read_back->result.tests[0].message_format, broken.tests[0].message_format);

  const fs::path reference = fs::path(SYROF_ASSIGNMENTS_DIR) / "strongest" / "reference";
  const SubmissionResult good =
      GradeSubmission(strongest, reference.string(), Fresh("alone_reference").string(), options, notes);
  ASSERT_EQ(good.tests.size(), 1u);
  EXPECT_EQ(good.tests[0].message_format, "");
}

}  // namespace

}  // namespace syrof::grader
