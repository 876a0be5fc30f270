#include "syrof/grader/outputs.h"

#include <filesystem>
#include <fstream>

#include "syrof/grader/grade.h"
#include "syrof/grader/grade_json.h"
#include "syrof/report/reports.h"

namespace syrof::grader {

std::optional<lab::Error> WriteSubmissionOutputs(const assignment::SubmissionResult& result,
                                                 const std::string& inputs_hash, const std::vector<std::string>& notes,
                                                 const std::string& out_dir, bool full_report,
                                                 std::optional<report::ReportOptions::FeedbackCap> feedback_withheld) {
  GradeFile file;
  file.result = result;
  file.inputs_hash = inputs_hash;
  file.syrof_version = SyrofVersion();
  file.notes = notes;
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  const std::filesystem::path path = std::filesystem::path(out_dir) / "grade.json";
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << GradeJson(file);
  if (!out) return lab::Error{.where = "", .message = "cannot write " + path.string()};
  // Every graded submission, single or in a class, passes here once.
  report::ReportOptions options;
  options.form = full_report ? report::ReportForm::kFull : report::ReportForm::kStudent;
  options.feedback_withheld = feedback_withheld;
  return report::WriteSubmissionReports(result, out_dir, options);
}

LiveResultsFile::LiveResultsFile(std::string path, const assignment::Assignment& assignment,
                                 assignment::SubmissionResult planned, report::ReportOptions options)
    : path_(std::move(path)), assignment_(assignment), current_(std::move(planned)), options_(std::move(options)) {
  current_.build.verdict = assignment::BuildVerdict::kOk;
  for (assignment::TestResult& test : current_.tests) test.run_error = kNotGraded;
  AddUp(current_, assignment_);
}

std::optional<lab::Error> LiveResultsFile::Begin() {
  const std::lock_guard<std::mutex> lock(mutex_);
  return Write(current_);
}

std::optional<lab::Error> LiveResultsFile::Record(const assignment::TestResult& test) {
  const std::lock_guard<std::mutex> lock(mutex_);
  for (assignment::TestResult& planned : current_.tests) {
    if (planned.name == test.name) planned = test;
  }
  AddUp(current_, assignment_);
  return Write(current_);
}

std::optional<lab::Error> LiveResultsFile::Finish(const assignment::SubmissionResult& result) {
  const std::lock_guard<std::mutex> lock(mutex_);
  return Write(result);
}

std::optional<lab::Error> LiveResultsFile::Write(const assignment::SubmissionResult& result) {
  const std::string temporary = path_ + ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << report::GradescopeResultsJson(result, options_);
    out.flush();
    if (!out) return lab::Error{.where = "", .message = "cannot write " + temporary};
  }
  std::error_code error;
  std::filesystem::rename(temporary, path_, error);
  if (error) return lab::Error{.where = "", .message = "cannot write " + path_ + ": " + error.message()};
  return std::nullopt;
}

}  // namespace syrof::grader
