// A graded submission's reports (docs/grading.md, "Reports"): Gradescope's
// results.json, JUnit XML for CI systems, and report.html, which embeds the
// viewer (lab/view) of failing runs. report.html has two forms: the
// student's (the default), where a hidden test is only its name, set,
// points and verdict, and the instructor's full form.
//
// What students see (results.json, report.html's student form, the viewer
// pages it frames) names no absolute path: commands name the scenario from
// the folder holding the assignment's folder and the library relative to
// the submission's output folder (grade.cpp), and every path a report
// writes is relative to that folder.
//
// Each report is a pure function of the SubmissionResult the runner filled
// (syrof/assignment/result.h): the same result gives the same bytes. Timings
// (BuildResult::wall_seconds, TestResult::wall_seconds) appear only in
// results.json's execution_time and JUnit's time attributes, and
// ReportOptions::zero_timings writes 0 there, for tests that compare bytes.
//
// Text from outside (a compiler's first error, a run's reasons) may hold
// any bytes: invalid UTF-8 becomes U+FFFD in every report, and each report
// escapes what its format needs (JSON strings, XML text and attributes,
// HTML).
//
// Usage, from the runner once a submission is graded:
//
//   if (std::optional<lab::Error> problem = report::WriteSubmissionReports(result, out_dir)) {
//     ...  // problem->ToString(); the reports that could be written are there
//   }
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "syrof/assignment/result.h"
#include "syrof/lab/base/error.h"

namespace syrof::grader::report {

using assignment::SubmissionResult;
using assignment::TestResult;

/// Which report.html to write.
enum class ReportForm {
  /// For students (the default): a hidden test shows only its name, set,
  /// points and passed/failed; no reasons, no replay command, no viewer
  /// (its viewer page is not written, and an old one is removed).
  kStudent,
  /// For the instructor: every test whole, hidden ones with their reasons
  /// and viewers (`syrof grade --report full`).
  kFull,
};

/// "student" or "full"; the parse of the same (nullopt for anything else).
std::string_view ToString(ReportForm form);
std::optional<ReportForm> ParseReportForm(std::string_view text);

struct ReportOptions {
  /// Writes 0 for every timing (execution_time, JUnit time="0.000"), so two
  /// gradings of the same submission give identical files.
  bool zero_timings = false;
  ReportForm form = ReportForm::kStudent;  ///< report.html's form
  /// Set when this submission is past the assignment's
  /// hidden_feedback_submissions: results.json shows a hidden test that
  /// would be `visible` only after the due date, and its summary says why.
  struct FeedbackCap {
    int submission = 0;  ///< this submission's number, from 1
    int cap = 0;         ///< the submissions that get the hidden tests' feedback
  };
  std::optional<FeedbackCap> feedback_withheld;
};

/// A test's visibility in results.json: its `gradescope:` when
/// assignment.yaml gives one, else `visible` for a public test and
/// `after_due_date` for a hidden one; with `withheld`, a hidden test that
/// would be `visible` is `after_due_date`.
const char* GradescopeVisibilityOf(const TestResult& test, bool withheld = false);

/// Gradescope's results.json (Gradescope's autograder format): the score,
/// a summary for the student, and one test per run. Public tests are
/// "visible" and their output ends with the command that replays the run;
/// hidden tests are "after_due_date" and name no scenario file.
std::string GradescopeResultsJson(const SubmissionResult& result, const ReportOptions& options = {});

/// JUnit XML: one testsuite named after the assignment, one testcase per
/// run (classname = assignment, name = test name); a failed run has a
/// <failure> whose message is its first lost criterion; every testcase's
/// <system-out> holds all its criteria. A submission that did not build is
/// one failing testcase named "build".
std::string JunitXml(const SubmissionResult& result, const ReportOptions& options = {});

/// Where a failing run's viewer page goes, relative to the submission's out
/// dir: "replay.html" beside the run's replay (TestResult::replay_path).
/// Empty when the test has no replay or its replay_path is not a relative
/// path inside the out dir (absolute, or with a ".." part).
std::string ReplayPagePath(const TestResult& test);

/// What became of a failing run's viewer page, for report.html.
struct ReplayPageNote {
  bool page_written = true;  ///< false: the report shows `note` and no viewer
  std::string note;          ///< empty, or why the page is missing or partial
};

/// report.html: the score, the build, a table of every test with each
/// criterion and its reason, and for each failing run with a replay its
/// viewer page (ReplayPagePath) in an <iframe> by relative path, so the
/// folder works from file:// with no network and no server. `notes` (by
/// test name) says which pages could not be written, or are partial. In
/// the student form (`form`), a hidden test is a row of its name, set,
/// points and verdict, and has no viewer.
std::string ReportHtml(const SubmissionResult& result, const std::map<std::string, ReplayPageNote>& notes = {},
                       ReportForm form = ReportForm::kStudent);

/// Whether `form` shows `test` whole (its reasons, command and viewer).
bool ShowsWhole(const TestResult& test, ReportForm form);

/// Writes, into `out_dir` (which exists, and where the result's relative
/// paths point): the viewer page (BuildPage of its replay) of every failing
/// run that options.form shows whole (ShowsWhole), then results.json,
/// junit.xml and report.html in options.form. Returns what went wrong, if
/// anything (each problem on its own line of the message); every file that
/// can be written is, whatever else failed. A replay that is missing or
/// cannot be read is not a failure: report.html says so where its viewer
/// would be.
std::optional<lab::Error> WriteSubmissionReports(const SubmissionResult& result, const std::string& out_dir,
                                                 const ReportOptions& options = {});

}  // namespace syrof::grader::report
