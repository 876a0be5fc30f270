// Gradescope's results.json: the documented format, byte for byte (the
// golden below is also docs/grading.md's example, and a test keeps the two
// the same), hidden tests after the due date, a submission that did not
// build, timings only in execution_time.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "report_test_support.h"
#include "syrof/report/reports.h"

namespace syrof::grader::report {
namespace {

using nlohmann::json;
using testing::ExampleResult;

constexpr const char* kGolden = R"({
  "score": 68.75,
  "execution_time": 128,
  "output": "Gather the swarm (gather)\nThe submission built.\nPublic tests: passed 1/2, points 43.75/50.\nHidden tests: 2; their results are shown after the due date.\n",
  "visibility": "visible",
  "stdout_visibility": "hidden",
  "tests": [
    {
      "name": "gather_6/seed-1",
      "score": 25.0,
      "max_score": 25.0,
      "status": "passed",
      "output": "goal 50/50: 2 of 2 checks passed\ncollisions 20/20: no collision and no wall contact\nagreement 30/30: the robots' global states agreed in 40 of 40 COOPERATIVE epochs\nrun total 100/100\nreplay: syrof run gather/scenarios/gather_6.yaml --app build/libgather.so --seed 1 --out rerun/gather_6-seed-1\n",
      "visibility": "visible"
    },
    {
      "name": "gather_6/seed-2",
      "score": 18.75,
      "max_score": 25.0,
      "status": "failed",
      "output": "goal 25/50: 1 of 2 checks passed; gathered: robot 3 is 0.900 m from (1.000, 1.000); the limit is 0.500 m\ncollisions 20/20: no collision and no wall contact\nagreement 30/30: the robots' global states agreed in 40 of 40 COOPERATIVE epochs\nrun total 75/100\nreplay: syrof run gather/scenarios/gather_6.yaml --app build/libgather.so --seed 2 --out rerun/gather_6-seed-2\n",
      "visibility": "visible"
    },
    {
      "name": "crash10/seed-101",
      "score": 0.0,
      "max_score": 25.0,
      "status": "failed",
      "output": "the run has no score: time limit of 120 s reached\n",
      "visibility": "after_due_date"
    },
    {
      "name": "crash10/seed-102",
      "score": 25.0,
      "max_score": 25.0,
      "status": "passed",
      "output": "goal 50/50: 2 of 2 checks passed\ncollisions 20/20: no collision and no wall contact\nagreement 30/30: the robots' global states agreed in 40 of 40 COOPERATIVE epochs\nrun total 100/100\n",
      "visibility": "after_due_date"
    }
  ]
}
)";

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

TEST(GradescopeJsonTest, MatchesTheDocumentedFormatByteForByte) {
  EXPECT_EQ(GradescopeResultsJson(ExampleResult()), kGolden);
}

TEST(GradescopeJsonTest, TheDocsShowTheSameExample) {
  const std::string docs = ReadText(SYROF_GRADING_DOC);
  ASSERT_FALSE(docs.empty()) << SYROF_GRADING_DOC;
  EXPECT_NE(docs.find(std::string("```json\n") + kGolden + "```\n"), std::string::npos)
      << "docs/grading.md's results.json example differs from this test's golden";
}

TEST(GradescopeJsonTest, HiddenTestsWaitForTheDueDateAndNameNoScenarioFile) {
  const json results = json::parse(GradescopeResultsJson(ExampleResult()));

  for (const json& test : results["tests"]) {
    const bool hidden = test["name"].get<std::string>().starts_with("crash10/");
    EXPECT_EQ(test["visibility"], hidden ? "after_due_date" : "visible") << test["name"];
    if (hidden) {
      EXPECT_EQ(test["output"].get<std::string>().find("replay:"), std::string::npos) << test["output"];
    }
  }
  // The summary every student sees counts the hidden tests and no more.
  EXPECT_EQ(results["output"].get<std::string>().find("crash10"), std::string::npos);
}

// assignment.yaml's `gradescope:` per test, and past the feedback cap a
// hidden test that would be visible waits for the due date.
TEST(GradescopeJsonTest, EachTestsVisibilityIsItsOwnAndTheFeedbackCapHoldsHiddenOnesBack) {
  SubmissionResult result = ExampleResult();
  for (TestResult& test : result.tests) {
    if (test.visibility == assignment::Visibility::kHidden) test.gradescope = assignment::GradescopeVisibility::kVisible;
  }
  result.tests[0].gradescope = assignment::GradescopeVisibility::kAfterPublished;

  const json open = json::parse(GradescopeResultsJson(result));
  ReportOptions capped;
  capped.feedback_withheld = ReportOptions::FeedbackCap{4, 3};
  const json held = json::parse(GradescopeResultsJson(result, capped));

  for (size_t i = 0; i < result.tests.size(); ++i) {
    const bool hidden = result.tests[i].visibility == assignment::Visibility::kHidden;
    const std::string expected = i == 0 ? "after_published" : "visible";
    EXPECT_EQ(open["tests"][i]["visibility"], expected) << result.tests[i].name;
    EXPECT_EQ(held["tests"][i]["visibility"], hidden ? "after_due_date" : expected) << result.tests[i].name;
  }
  EXPECT_NE(held["output"].get<std::string>().find(
                "feedback on them is given for your first 3 submissions, and this is submission 4"),
            std::string::npos)
      << held["output"];
}

TEST(GradescopeJsonTest, StatusAndScoresFollowTheTests) {
  const json results = json::parse(GradescopeResultsJson(ExampleResult()));

  double total = 0;
  for (const json& test : results["tests"]) {
    total += test["score"].get<double>();
    EXPECT_EQ(test["status"], test["score"] == test["max_score"] ? "passed" : "failed") << test["name"];
  }
  EXPECT_DOUBLE_EQ(total, results["score"].get<double>());
}

TEST(GradescopeJsonTest, ASubmissionThatDidNotBuildScoresZeroAndSaysWhy) {
  assignment::SubmissionResult result = ExampleResult();
  result.build.verdict = assignment::BuildVerdict::kBuildFailed;
  result.build.detail = "app.c:3:1: error: expected ';' before '}' token";
  for (assignment::TestResult& test : result.tests) {
    test.points = 0;
    test.passed = false;
    test.score = {};
  }
  result.points = 0;
  result.tests_passed = 0;

  const json results = json::parse(GradescopeResultsJson(result));

  EXPECT_EQ(results["score"], 0.0);
  EXPECT_NE(results["output"].get<std::string>().find(
                "Not graded: the submission did not build (build_failed): app.c:3:1: error: expected ';' before '}' "
                "token. Every test scores 0."),
            std::string::npos)
      << results["output"];
  for (const json& test : results["tests"]) {
    EXPECT_EQ(test["status"], "failed");
    EXPECT_TRUE(test["output"].get<std::string>().starts_with("not run: the submission did not build"));
  }
}

TEST(GradescopeJsonTest, TimingsAppearOnlyInExecutionTimeAndCanBeZeroed) {
  assignment::SubmissionResult slower = ExampleResult();
  slower.build.wall_seconds = 99;
  for (assignment::TestResult& test : slower.tests) test.wall_seconds *= 3;

  json a = json::parse(GradescopeResultsJson(ExampleResult()));
  json b = json::parse(GradescopeResultsJson(slower));
  EXPECT_NE(a["execution_time"], b["execution_time"]);
  a.erase("execution_time");
  b.erase("execution_time");
  EXPECT_EQ(a, b);

  ReportOptions zero;
  zero.zero_timings = true;
  EXPECT_EQ(GradescopeResultsJson(ExampleResult(), zero), GradescopeResultsJson(slower, zero));
  EXPECT_EQ(json::parse(GradescopeResultsJson(slower, zero))["execution_time"], 0);
}

TEST(GradescopeJsonTest, BytesThatAreNotUtf8BecomeReplacementCharacters) {
  assignment::SubmissionResult result = ExampleResult();
  result.tests[1].score.criteria[0].reason = "robot \xff\xfe went \"away\"\n\\";

  const std::string text = GradescopeResultsJson(result);
  const json results = json::parse(text);  // throws on invalid UTF-8

  EXPECT_NE(results["tests"][1]["output"].get<std::string>().find("robot \xEF\xBF\xBD\xEF\xBF\xBD went \"away\"\n\\"),
            std::string::npos);
}

}  // namespace
}  // namespace syrof::grader::report
