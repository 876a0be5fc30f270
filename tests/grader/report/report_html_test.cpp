// report.html without a browser (report_browser_test.cpp loads it in one):
// what the page says, where its viewers point, that it has no script and
// escapes what it shows; and WriteSubmissionReports: the files it writes,
// each failing run's viewer page, replays missing or cut short, and the
// same bytes for the same result.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "replay_test_support.h"
#include "report_test_support.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/report/reports.h"

namespace syrof::grader::report {
namespace {

namespace fs = std::filesystem;
using testing::ExampleResult;

size_t Count(const std::string& text, const std::string& what) {
  size_t count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

std::string ReadHtml(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A fresh folder per test and process.
fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("syrof_report_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void WriteReplay(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST(ReportHtmlTest, ShowsTheScoreAndEveryTestWithItsCriteria) {
  const std::string html = ReportHtml(ExampleResult(), {}, ReportForm::kFull);

  EXPECT_NE(html.find("<p id=\"score\" class=\"partial\">Points <b>68.75/100</b> &middot; Tests passed <b>2/4</b>"),
            std::string::npos);
  EXPECT_NE(html.find("<h1>Gather the swarm</h1>"), std::string::npos);
  EXPECT_EQ(Count(html, "<tr id=\"test-"), 4u);
  EXPECT_NE(html.find("<li class=\"lost\">goal 25/50: 1 of 2 checks passed; gathered: robot 3 is 0.900 m"),
            std::string::npos);
  EXPECT_NE(html.find("<li class=\"lost\">the run has no score: time limit of 120 s reached</li>"), std::string::npos);
  EXPECT_NE(html.find("<li>collisions 20/20: no collision and no wall contact</li>"), std::string::npos);
}

TEST(ReportHtmlTest, EmbedsTheViewerOfEachFailingRunWithAReplayByRelativePath) {
  const std::string html = ReportHtml(ExampleResult());

  // One failing run has a replay; the timed-out one has none.
  EXPECT_EQ(Count(html, "<iframe"), 1u);
  EXPECT_NE(html.find("<iframe class=\"viewer\" src=\"runs/gather_6/seed-2/replay.html\""), std::string::npos);
  EXPECT_NE(html.find("<a href=\"#run-2\">failed: see its run</a>"), std::string::npos);
  EXPECT_NE(html.find("<details id=\"run-2\" class=\"run\" open>"), std::string::npos);
  // Nothing but those frames may load: no script, no address elsewhere.
  EXPECT_EQ(Count(html, "<script"), 0u);
  EXPECT_EQ(Count(html, "http://") + Count(html, "https://"), 0u);
  EXPECT_NE(html.find("content=\"default-src 'none'; style-src 'unsafe-inline'; frame-src 'self' file:\""),
            std::string::npos);
}

TEST(ReportHtmlTest, OnlyPublicTestsShowTheirReplayCommand) {
  const std::string html = ReportHtml(ExampleResult());

  EXPECT_NE(html.find("gather/scenarios/gather_6.yaml --app build/libgather.so --seed 1"), std::string::npos);
  EXPECT_EQ(html.find("hidden/gather_10_crash.yaml"), std::string::npos);
}

TEST(ReportHtmlTest, LaterViewersLoadLazilyAndStartClosed) {
  assignment::SubmissionResult result = ExampleResult();
  result.tests[2].replay_path = "runs/crash10/seed-101/replay";

  const std::string html = ReportHtml(result, {}, ReportForm::kFull);

  EXPECT_EQ(Count(html, "<iframe"), 2u);
  EXPECT_NE(html.find("<details id=\"run-3\" class=\"run\">"), std::string::npos);
  EXPECT_NE(html.find("src=\"runs/crash10/seed-101/replay.html\" title=\"The viewer of crash10/seed-101\" "
                      "loading=\"lazy\""),
            std::string::npos);
}

// The student's form (the default): a hidden test is its name, set, points
// and verdict; its reasons, its command and its viewer stay out, and the
// full form shows them.
TEST(ReportHtmlTest, TheStudentFormShowsAHiddenTestOnlyAsItsNamePointsAndVerdict) {
  assignment::SubmissionResult result = ExampleResult();
  result.tests[2].run_error.clear();
  result.tests[2].score.criteria = {{"goal", 0, 50, "gathered: robot 4 is 2.480 m from (1.500, 3.500)"}};
  result.tests[2].message_format = "3 payloads broke the message format (robots 4)";
  result.tests[2].replay_path = "runs/crash10/seed-101/replay";

  const std::string student = ReportHtml(result);
  const std::string full = ReportHtml(result, {}, ReportForm::kFull);

  for (const std::string& hidden_detail :
       {std::string("robot 4 is 2.480 m"), std::string("payloads broke"), std::string("hidden/gather_10_crash.yaml"),
        std::string("runs/crash10/seed-101/replay.html"), std::string("run-3")}) {
    EXPECT_EQ(student.find(hidden_detail), std::string::npos) << hidden_detail;
    if (hidden_detail != "hidden/gather_10_crash.yaml") {
      EXPECT_NE(full.find(hidden_detail), std::string::npos) << hidden_detail;
    }
  }
  EXPECT_EQ(Count(student, "<iframe"), 1u);  // the public failing run's alone
  EXPECT_EQ(Count(full, "<iframe"), 2u);
  // Its row is still there: name, set, points, verdict.
  EXPECT_NE(student.find("<tr id=\"test-3\" class=\"failed\"><td><code>crash10/seed-101</code></td><td>hidden</td>"
                         "<td class=\"points\">0/25</td><td class=\"result\">failed</td>"),
            std::string::npos)
      << student;
  EXPECT_NE(student.find("<tr id=\"test-4\" class=\"passed\"><td><code>crash10/seed-102</code></td><td>hidden</td>"
                         "<td class=\"points\">25/25</td><td class=\"result\">passed</td>"),
            std::string::npos);
  // The public tests are whole in both.
  EXPECT_NE(student.find("goal 25/50: 1 of 2 checks passed; gathered: robot 3 is 0.900 m"), std::string::npos);
  EXPECT_EQ(student.find("instructor's full report"), std::string::npos);
  EXPECT_NE(full.find("instructor's full report"), std::string::npos);
}

TEST(ReportHtmlTest, ReportFormsByName) {
  EXPECT_EQ(ParseReportForm("student"), ReportForm::kStudent);
  EXPECT_EQ(ParseReportForm("full"), ReportForm::kFull);
  EXPECT_EQ(ParseReportForm("Full"), std::nullopt);
  EXPECT_EQ(ToString(ReportForm::kFull), "full");
  EXPECT_EQ(ToString(ReportForm::kStudent), "student");
}

TEST(ReportHtmlTest, EscapesWhatItShowsAndEncodesPaths) {
  assignment::SubmissionResult result = ExampleResult();
  result.title = "<script>alert(1)</script>";
  result.tests[1].score.criteria[0].reason = "x < y && \"z\" 'w'";
  result.tests[1].replay_path = "runs/my run/<seed>/replay";

  const std::string html = ReportHtml(result);

  EXPECT_EQ(Count(html, "<script"), 0u);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("x &lt; y &amp;&amp; &quot;z&quot; &#39;w&#39;"), std::string::npos);
  EXPECT_NE(html.find("src=\"runs/my%20run/%3Cseed%3E/replay.html\""), std::string::npos);
}

TEST(ReportHtmlTest, NoTimingsAndNoAbsolutePaths) {
  assignment::SubmissionResult slower = ExampleResult();
  for (assignment::TestResult& test : slower.tests) test.wall_seconds *= 7;

  const std::string html = ReportHtml(ExampleResult());

  EXPECT_EQ(html, ReportHtml(slower));
  EXPECT_EQ(html.find("/tmp/"), std::string::npos);
}

TEST(ReportHtmlTest, ABuildFailureSaysWhyAndLinksTheLog) {
  assignment::SubmissionResult result = ExampleResult();
  result.build.verdict = assignment::BuildVerdict::kBuildFailed;
  result.build.detail = "app.c:3:1: error: expected ';'";
  result.points = 0;
  result.tests_passed = 0;
  for (assignment::TestResult& test : result.tests) {
    test.passed = false;
    test.points = 0;
    test.replay_path.clear();
  }

  const std::string html = ReportHtml(result);

  EXPECT_NE(html.find("class=\"none\">Points <b>0/100</b>"), std::string::npos);
  EXPECT_NE(html.find("the submission did not build (build_failed): app.c:3:1: error: expected &#39;;&#39;"),
            std::string::npos);
  EXPECT_NE(html.find("<a href=\"build.log\">build.log</a>"), std::string::npos);
  EXPECT_EQ(Count(html, "<iframe"), 0u);
}

TEST(ReportHtmlTest, ReplayPagePathIsBesideTheReplayAndInsideTheFolder) {
  assignment::TestResult test;
  const auto page = [&test](const std::string& replay) {
    test.replay_path = replay;
    return ReplayPagePath(test);
  };
  EXPECT_EQ(page("runs/gather_6/seed-2/replay"), "runs/gather_6/seed-2/replay.html");
  EXPECT_EQ(page("replay"), "replay.html");
  EXPECT_EQ(page("runs/a/replay.html"), "runs/a/replay.html.html");
  EXPECT_EQ(page(""), "");
  EXPECT_EQ(page("/tmp/runs/a/replay"), "");
  EXPECT_EQ(page("runs/../../a/replay"), "");
}

// ---- WriteSubmissionReports ------------------------------------------------

TEST(WriteSubmissionReportsTest, WritesTheThreeReportsAndEachFailingRunsViewer) {
  const fs::path dir = FreshDir("writes");
  WriteReplay(dir / "runs/gather_6/seed-2/replay", lab::replay::testing::WriteSample().bytes);

  EXPECT_EQ(WriteSubmissionReports(ExampleResult(), dir.string()), std::nullopt);

  EXPECT_EQ(ReadHtml(dir / "results.json"), GradescopeResultsJson(ExampleResult()));
  EXPECT_EQ(ReadHtml(dir / "junit.xml"), JunitXml(ExampleResult()));
  EXPECT_EQ(ReadHtml(dir / "report.html"), ReportHtml(ExampleResult()));
  const std::string page = ReadHtml(dir / "runs/gather_6/seed-2/replay.html");
  EXPECT_TRUE(page.starts_with("<!DOCTYPE html>")) << page.substr(0, 200);
  EXPECT_NE(page.find("gather_6/seed-2"), std::string::npos);  // named by the test, not a path
  EXPECT_EQ(page.find(dir.string()), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "runs/gather_6/seed-1/replay.html"));  // passed: no viewer
  fs::remove_all(dir);
}

// A failing run's viewer page says its verdict from the run's metrics.json
// beside its replay, as `syrof view` does, not "not judged here".
TEST(WriteSubmissionReportsTest, AFailingRunsViewerSaysItsVerdictFromItsMetrics) {
  const fs::path dir = FreshDir("verdict");
  WriteReplay(dir / "runs/gather_6/seed-2/replay", lab::replay::testing::WriteSample().bytes);
  lab::metrics::Metrics metrics;
  metrics.seed = 42;  // the sample replay's
  metrics.goal.app = "builtin:gather";
  metrics.goal.reached = false;
  metrics.goal.detail = "the robots fit in a circle of 1.942 m; the limit is 0.900 m";
  std::ofstream(dir / "runs/gather_6/seed-2/metrics.json") << lab::metrics::ToJson(metrics);

  EXPECT_EQ(WriteSubmissionReports(ExampleResult(), dir.string()), std::nullopt);

  const std::string page = ReadHtml(dir / "runs/gather_6/seed-2/replay.html");
  EXPECT_NE(page.find("\"state\":\"missed\""), std::string::npos);
  EXPECT_NE(page.find("Goal missed: "), std::string::npos);
  EXPECT_EQ(page.find("not judged"), std::string::npos);
  fs::remove_all(dir);
}

// A hidden failing run's viewer page is written for the full form only; the
// student's form removes one an earlier full report left.
TEST(WriteSubmissionReportsTest, AHiddenRunsViewerPageIsWrittenOnlyForTheFullForm) {
  const fs::path dir = FreshDir("forms");
  assignment::SubmissionResult result = ExampleResult();
  result.tests[2].replay_path = "runs/crash10/seed-101/replay";
  for (const char* replay : {"runs/gather_6/seed-2/replay", "runs/crash10/seed-101/replay"}) {
    WriteReplay(dir / replay, lab::replay::testing::WriteSample().bytes);
  }
  const fs::path hidden_page = dir / "runs/crash10/seed-101/replay.html";
  ReportOptions full;
  full.form = ReportForm::kFull;

  ASSERT_EQ(WriteSubmissionReports(result, dir.string(), full), std::nullopt);
  EXPECT_TRUE(fs::exists(hidden_page));
  EXPECT_EQ(ReadHtml(dir / "report.html"), ReportHtml(result, {}, ReportForm::kFull));

  ASSERT_EQ(WriteSubmissionReports(result, dir.string()), std::nullopt);
  EXPECT_FALSE(fs::exists(hidden_page));
  EXPECT_TRUE(fs::exists(dir / "runs/gather_6/seed-2/replay.html"));
  EXPECT_EQ(ReadHtml(dir / "report.html"), ReportHtml(result));
  fs::remove_all(dir);
}

TEST(WriteSubmissionReportsTest, TheSameResultGivesTheSameBytesWhereverItIsWritten) {
  const fs::path a = FreshDir("same_a");
  const fs::path b = FreshDir("same_b");
  for (const fs::path& dir : {a, b}) {
    WriteReplay(dir / "runs/gather_6/seed-2/replay", lab::replay::testing::WriteSample().bytes);
  }
  assignment::SubmissionResult slower = ExampleResult();
  for (assignment::TestResult& test : slower.tests) test.wall_seconds += 10;
  ReportOptions zero;
  zero.zero_timings = true;

  ASSERT_EQ(WriteSubmissionReports(ExampleResult(), a.string(), zero), std::nullopt);
  ASSERT_EQ(WriteSubmissionReports(slower, b.string(), zero), std::nullopt);

  for (const std::string file : {"results.json", "junit.xml", "report.html", "runs/gather_6/seed-2/replay.html"}) {
    EXPECT_EQ(ReadHtml(a / file), ReadHtml(b / file)) << file;
    EXPECT_FALSE(ReadHtml(a / file).empty()) << file;
  }
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(WriteSubmissionReportsTest, AMissingReplayIsSaidWhereItsViewerWouldBe) {
  const fs::path dir = FreshDir("missing");

  EXPECT_EQ(WriteSubmissionReports(ExampleResult(), dir.string()), std::nullopt);

  const std::string html = ReadHtml(dir / "report.html");
  EXPECT_NE(html.find("No viewer: the run left no replay at runs/gather_6/seed-2/replay."), std::string::npos);
  EXPECT_EQ(Count(html, "<iframe"), 0u);
  fs::remove_all(dir);
}

TEST(WriteSubmissionReportsTest, AReplayCutShortStillGetsItsViewerAndANote) {
  const fs::path dir = FreshDir("cut");
  const std::string bytes = lab::replay::testing::WriteSample().bytes;
  WriteReplay(dir / "runs/gather_6/seed-2/replay", bytes.substr(0, bytes.size() - 7));

  EXPECT_EQ(WriteSubmissionReports(ExampleResult(), dir.string()), std::nullopt);

  EXPECT_TRUE(fs::exists(dir / "runs/gather_6/seed-2/replay.html"));
  const std::string html = ReadHtml(dir / "report.html");
  EXPECT_NE(html.find("The replay is not whole ("), std::string::npos);
  EXPECT_EQ(Count(html, "<iframe"), 1u);
  fs::remove_all(dir);
}

TEST(WriteSubmissionReportsTest, AReplayPathOutsideTheFolderWritesNothingThere) {
  const fs::path root = FreshDir("outside");
  const fs::path dir = root / "reports";
  fs::create_directories(dir);
  assignment::SubmissionResult result = ExampleResult();
  result.tests[1].replay_path = "../replay";
  WriteReplay(root / "replay", lab::replay::testing::WriteSample().bytes);

  EXPECT_EQ(WriteSubmissionReports(result, dir.string()), std::nullopt);

  EXPECT_FALSE(fs::exists(root / "replay.html"));
  EXPECT_NE(ReadHtml(dir / "report.html").find("is not inside the report&#39;s folder"), std::string::npos);
  fs::remove_all(root);
}

TEST(WriteSubmissionReportsTest, AFolderThatCannotBeWrittenIsReported) {
  const std::optional<lab::Error> problem = WriteSubmissionReports(ExampleResult(), "/nonexistent/syrof/reports");

  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->ToString(),
            "cannot write /nonexistent/syrof/reports/results.json\n"
            "cannot write /nonexistent/syrof/reports/junit.xml\n"
            "cannot write /nonexistent/syrof/reports/report.html");
}

}  // namespace
}  // namespace syrof::grader::report
