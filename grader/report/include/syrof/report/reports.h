// A graded submission's reports (docs/grading.md, "Reports"): Gradescope's
// results.json, JUnit XML for CI systems, and report.html for the student,
// which embeds the viewer (lab/view) of every failing run.
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
//   const std::string problem = report::WriteSubmissionReports(result, out_dir);
//   if (!problem.empty()) ... // the reports that could be written are there
#pragma once

#include <map>
#include <string>

#include "syrof/assignment/result.h"

namespace syrof::grader::report {

using assignment::SubmissionResult;
using assignment::TestResult;

struct ReportOptions {
  /// Writes 0 for every timing (execution_time, JUnit time="0.000"), so two
  /// gradings of the same submission give identical files.
  bool zero_timings = false;
};

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
/// test name) says which pages could not be written, or are partial.
std::string ReportHtml(const SubmissionResult& result, const std::map<std::string, ReplayPageNote>& notes = {});

/// Writes, into `out_dir` (which exists, and where the result's relative
/// paths point): every failing run's viewer page (BuildPage of its replay),
/// then results.json, junit.xml and report.html. Returns "" or what went
/// wrong (each problem on its own line); every file that can be written is,
/// whatever else failed. A replay that is missing or cannot be read is not
/// a failure: report.html says so where its viewer would be.
std::string WriteSubmissionReports(const SubmissionResult& result, const std::string& out_dir,
                                   const ReportOptions& options = {});

}  // namespace syrof::grader::report
