// The grade command's pure parts: adding runs up (result.h's rule),
// grade.json written and read back, the table, the class CSV and summary,
// shards. No app host, no build.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "syrof/grader/class_grading.h"
#include "syrof/grader/grade.h"
#include "syrof/grader/grade_json.h"
#include "syrof/grader/table.h"

namespace syrof::grader {
namespace {

using assignment::CriterionScore;
using assignment::SubmissionResult;
using assignment::TestResult;

TestResult MakeTest(const std::string& scenario, uint64_t seed, double run_points, double run_max) {
  TestResult test;
  test.name = scenario + "/seed-" + std::to_string(seed);
  test.scenario = scenario;
  test.seed = seed;
  test.score.points = run_points;
  test.score.max_points = run_max;
  test.score.criteria = {CriterionScore{"goal", run_points, run_max, run_points < run_max ? "goal missed: far" : "ok"}};
  test.output_dir = "runs/" + scenario + "/seed-" + std::to_string(seed);
  return test;
}

// An assignment worth `points`, with no search test.
assignment::Assignment WorthPoints(double points) {
  assignment::Assignment worth;
  worth.points = points;
  return worth;
}

SubmissionResult Sample() {
  SubmissionResult result;
  result.submission = "alice";
  result.assignment = "gather";
  result.title = "Gather the swarm";
  result.build.detail = "built libgather.so";
  result.build.log_path = "build.log";
  result.tests = {MakeTest("a", 1, 100, 100), MakeTest("a", 2, 50, 100), MakeTest("b", 7, 0, 100)};
  result.tests[1].replay_command = "syrof run a.yaml --app lib.so --seed 2 --out rerun/a-seed-2";
  result.tests[2].visibility = assignment::Visibility::kHidden;
  result.tests[2].run_error = "the run took longer than its time limit of 60 s (wall clock) and was stopped";
  result.tests[2].wall_seconds = 61.5;
  AddUp(result, WorthPoints(90));
  return result;
}

TEST(AddUpTest, EachTestIsAnEqualShareEarnedByItsRunsFraction) {
  const SubmissionResult result = Sample();
  EXPECT_EQ(result.tests[0].max_points, 30);
  EXPECT_EQ(result.tests[0].points, 30);
  EXPECT_TRUE(result.tests[0].passed);
  EXPECT_EQ(result.tests[1].points, 15);
  EXPECT_FALSE(result.tests[1].passed);
  EXPECT_EQ(result.tests[2].points, 0) << "a run error earns nothing";
  EXPECT_EQ(result.points, 45);
  EXPECT_EQ(result.max_points, 90);
  EXPECT_EQ(result.tests_passed, 1);
}

TEST(AddUpTest, ASubmissionThatDidNotBuildGetsNothing) {
  SubmissionResult result = Sample();
  result.build.verdict = assignment::BuildVerdict::kBuildFailed;
  AddUp(result, WorthPoints(90));
  EXPECT_EQ(result.points, 0);
  EXPECT_EQ(result.tests_passed, 0);
}

TEST(AddUpTest, SharesAreRoundedToTheHundredth) {
  SubmissionResult result;
  result.tests = {MakeTest("a", 1, 1, 3), MakeTest("a", 2, 1, 3), MakeTest("a", 3, 1, 3)};
  AddUp(result, WorthPoints(100));
  EXPECT_EQ(result.tests[0].points, 11.11);
  EXPECT_EQ(result.points, 33.33);
}

TEST(AddUpTest, FullMarksOnEveryTestIsExactlyTheAssignmentsPoints) {
  // 100 / 7 = 14.2857...: seven shares rounded first would add up to 100.03.
  SubmissionResult result;
  for (uint64_t seed = 1; seed <= 7; ++seed) result.tests.push_back(MakeTest("a", seed, 100, 100));
  AddUp(result, WorthPoints(100));
  EXPECT_EQ(result.tests[0].points, 14.29);
  EXPECT_EQ(result.points, 100);
  EXPECT_EQ(result.tests_passed, 7);
}

TEST(AddUpTest, ASearchTestIsWorthItsOwnPointsAndTheRunsShareTheRest) {
  assignment::Assignment worth = WorthPoints(100);
  assignment::SearchTestSpec lossy;
  lossy.name = "lossy";
  lossy.points = 20;
  worth.search_tests.push_back(lossy);
  SubmissionResult result;
  result.tests = {MakeTest("a", 1, 100, 100), MakeTest("a", 2, 50, 100)};
  TestResult search;
  search.name = "search/lossy";
  search.scenario = "lossy";
  search.search = true;
  search.score.criteria = {CriterionScore{"search", 0, 20, "broken by 1 lost beacon"}};
  search.score.max_points = 20;
  result.tests.push_back(search);
  AddUp(result, worth);
  EXPECT_EQ(result.tests[0].max_points, 40);  // (100 - 20) / 2 runs
  EXPECT_EQ(result.tests[1].points, 20);
  EXPECT_EQ(result.tests[2].max_points, 20);
  EXPECT_EQ(result.tests[2].points, 0);
  EXPECT_FALSE(result.tests[2].passed);
  EXPECT_EQ(result.points, 60);
  EXPECT_EQ(result.max_points, 100);
  result.tests[2].score.criteria[0].points = 20;
  result.tests[2].score.points = 20;
  AddUp(result, worth);
  EXPECT_EQ(result.points, 80);
  EXPECT_EQ(result.tests_passed, 2);
}

TEST(GradeJsonTest, ReadsBackWhatItWroteAndKeepsTimingsApart) {
  GradeFile file;
  file.result = Sample();
  file.inputs_hash = "0123456789abcdef";
  file.syrof_version = SyrofVersion();
  file.notes = {"build: network not isolated"};
  const std::string text = GradeJson(file);
  EXPECT_TRUE(text.starts_with("{\n  \"format\": \"syrof-grade\",\n  \"version\": 1,\n")) << text;
  const size_t timings = text.find("\"timings\"");
  ASSERT_NE(timings, std::string::npos);
  EXPECT_EQ(text.find("61.5"), text.find("61.5", timings)) << "wall times only under timings";

  const std::string path = ::testing::TempDir() + "grade_json_" + std::to_string(getpid()) + ".json";
  std::ofstream(path) << text;
  const GradeFileOrError read_json = ReadGradeJson(path);
  ASSERT_TRUE(read_json.ok()) << read_json.error->ToString();
  const std::optional<GradeFile>& read = read_json.file;
  EXPECT_EQ(GradeJson(*read), text);
  EXPECT_EQ(read->result.tests[2].wall_seconds, 61.5);

  std::ofstream(path) << "{\"format\": \"something else\"}";
  GradeFileOrError wrong = ReadGradeJson(path);
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error->where, path);
  EXPECT_EQ(wrong.error->ToString(), path + ": not a grade.json of format syrof-grade version 1");
  std::ofstream(path) << "{\"format\": ";
  wrong = ReadGradeJson(path);
  ASSERT_FALSE(wrong.ok());
  EXPECT_TRUE(wrong.error->ToString().starts_with(path + ": not JSON: [json.exception.parse_error"))
      << wrong.error->ToString();
  std::ofstream(path) << R"({"format": "syrof-grade", "version": 1, "build": {"verdict": "fine"}, "tests": []})";
  wrong = ReadGradeJson(path);
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error->ToString(),
            path + ": build.verdict \"fine\" is not a build verdict (ok, build_failed, ...)");
  std::ofstream(path) << R"({"format": "syrof-grade", "version": 1, "build": {"verdict": "ok"}})";
  wrong = ReadGradeJson(path);
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error->ToString(), path + ": no tests array");
  wrong = ReadGradeJson(path + ".missing");
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(wrong.error->ToString(), path + ".missing: cannot be read");
}

TEST(TableTest, HeaderThenOneLinePerTestWithWhyAndTheReplay) {
  std::ostringstream out;
  PrintSubmissionTable(Sample(), "grade-out/alice", out);
  EXPECT_EQ(out.str(),
            "Gather the swarm (gather), submission alice\n"
            "Build: ok, built libgather.so\n"
            "Tests passed 1/3, Points 45.00/90.00\n"
            "\n"
            "  test                    points  result  why\n"
            "  a/seed-1           30.00/30.00  PASS\n"
            "  a/seed-2           15.00/30.00  FAIL    goal: goal missed: far\n"
            "                     replay: syrof run a.yaml --app lib.so --seed 2 --out rerun/a-seed-2\n"
            "  b/seed-7 (hidden)   0.00/30.00  FAIL    the run took longer than its time limit of 60 s (wall clock) "
            "and was stopped\n");
}

TEST(ClassFilesTest, CsvHasAColumnPerScenarioAndTheSummaryDeciles) {
  SubmissionResult alice = Sample();
  SubmissionResult bob = Sample();
  bob.submission = "bob, jr";
  bob.build.verdict = assignment::BuildVerdict::kTimeout;
  bob.build.detail = "the build took longer than its limit of 120 s";
  AddUp(bob, WorthPoints(90));
  EXPECT_EQ(ClassCsv({alice, bob}),
            "student,points,max_points,tests_passed,tests,build,a,b\n"
            "alice,45.00,90.00,1,3,ok,45.00,0.00\n"
            "\"bob, jr\",0.00,90.00,0,3,timeout,0.00,0.00\n");
  const std::string summary = ClassSummary({alice, bob});
  EXPECT_NE(summary.find("Points: mean 22.50, median 22.50, min 0.00, max 45.00 (out of 90.00)\n"), std::string::npos)
      << summary;
  EXPECT_NE(summary.find("    0- 10%)    1  #\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("   50- 60%)    1  #\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("Builds failed: 1\n  bob, jr: timeout: the build took longer than its limit of 120 s\n"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("  a/seed-2: failed by 1\n"), std::string::npos) << summary;
}

TEST(ShardTest, SlicesCoverTheSortedListOnce) {
  const std::vector<std::string> students = {"a", "b", "c", "d", "e"};
  std::vector<std::string> all;
  for (int i = 1; i <= 3; ++i) {
    for (const std::string& student : ShardOf(students, {i, 3})) all.push_back(student);
  }
  EXPECT_EQ(all, students);
  ShardOrError parsed = ParseShard("3/2");
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error->ToString(), "--shard I/N needs 1 <= I <= N <= 10000, not '3/2'");
  parsed = ParseShard("two");
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error->ToString(), "--shard must be I/N (for example 2/4), not 'two'");
  parsed = ParseShard("2/4");
  ASSERT_TRUE(parsed.ok()) << parsed.error->ToString();
  EXPECT_FALSE(parsed.error);
  EXPECT_EQ(parsed.shard->index, 2);
  EXPECT_EQ(parsed.shard->count, 4);
}

}  // namespace
}  // namespace syrof::grader
