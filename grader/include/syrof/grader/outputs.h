// What a graded submission leaves in its folder besides its runs: grade.json
// (grade_json.h) and the reports (grader/report: results.json, junit.xml,
// report.html with the viewer of each failing run).
#pragma once

#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/result.h"
#include "syrof/lab/base/error.h"
#include "syrof/report/reports.h"

namespace syrof::grader {

/// Writes `out_dir`/grade.json for `result` (with the inputs' hash and the
/// sandboxes' notes), then the reports: report.html in the student's form,
/// or with `full_report` the instructor's (report::ReportForm);
/// `feedback_withheld` as report::ReportOptions says. Returns what failed,
/// if anything.
std::optional<lab::Error> WriteSubmissionOutputs(
    const assignment::SubmissionResult& result, const std::string& inputs_hash, const std::vector<std::string>& notes,
    const std::string& out_dir, bool full_report = false,
    std::optional<report::ReportOptions::FeedbackCap> feedback_withheld = std::nullopt);

/// Gradescope's results.json for one submission kept valid at every moment
/// while it is graded (docs/grading.md, "Gradescope's limits"): an
/// autograder stopped by Gradescope's timeout still leaves the tests that
/// finished, with their points. Each write goes to a temporary file beside
/// `path` and is renamed over it, so a reader never sees half a file.
/// Record may be called from several threads.
class LiveResultsFile {
 public:
  /// `assignment` is the assignment as graded (GradedAssignment), `planned`
  /// a result whose tests are the plan (PlanTests), none of them run.
  /// `options` as the final results.json is written with (its feedback cap).
  LiveResultsFile(std::string path, const assignment::Assignment& assignment, assignment::SubmissionResult planned,
                  report::ReportOptions options = {});

  /// Writes the plan: score 0, every test "not graded" with the reason
  /// kNotGraded. Returns what failed, if anything.
  std::optional<lab::Error> Begin();
  /// One test graded (as GradeOptions::on_test gives it): it replaces the
  /// planned test of the same name, the total is added up again, the file
  /// rewritten. Returns what failed, if anything.
  std::optional<lab::Error> Record(const assignment::TestResult& test);
  /// The final result: the file then holds the same bytes as the reports'
  /// results.json. Returns what failed, if anything.
  std::optional<lab::Error> Finish(const assignment::SubmissionResult& result);

  /// The reason a test not graded yet carries in the file.
  static constexpr const char* kNotGraded =
      "not graded: grading stopped before this test finished (the autograder's time limit?)";

 private:
  std::optional<lab::Error> Write(const assignment::SubmissionResult& result);

  std::string path_;
  const assignment::Assignment& assignment_;
  assignment::SubmissionResult current_;
  report::ReportOptions options_;
  std::mutex mutex_;
};

}  // namespace syrof::grader
