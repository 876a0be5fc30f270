// What a graded submission leaves in its folder besides its runs: grade.json
// (grade_json.h) and the reports (grader/report: results.json, junit.xml,
// report.html with the viewer of each failing run).
#pragma once

#include <string>
#include <vector>

#include "syrof/assignment/result.h"

namespace syrof::grader {

/// Writes `out_dir`/grade.json for `result` (with the inputs' hash and the
/// sandboxes' notes), then the reports: report.html in the student's form,
/// or with `full_report` the instructor's (report::ReportForm). Returns ""
/// or what failed.
std::string WriteSubmissionOutputs(const assignment::SubmissionResult& result, const std::string& inputs_hash,
                                   const std::vector<std::string>& notes, const std::string& out_dir,
                                   bool full_report = false);

}  // namespace syrof::grader
