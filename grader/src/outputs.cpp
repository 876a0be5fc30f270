#include "syrof/grader/outputs.h"

#include <filesystem>
#include <fstream>

#include "syrof/grader/grade_json.h"
#include "syrof/report/reports.h"

namespace syrof::grader {

std::string WriteSubmissionOutputs(const assignment::SubmissionResult& result, const std::string& inputs_hash,
                                   const std::vector<std::string>& notes, const std::string& out_dir,
                                   bool full_report) {
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
  if (!out) return "cannot write " + path.string();
  // Every graded submission, single or in a class, passes here once.
  report::ReportOptions options;
  options.form = full_report ? report::ReportForm::kFull : report::ReportForm::kStudent;
  return report::WriteSubmissionReports(result, out_dir, options);
}

}  // namespace syrof::grader
