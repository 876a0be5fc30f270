// OUT/grade.json: a graded submission in full (docs/grading.md, "grade.json").
//
// Format "syrof-grade", version 1: an object with format, version,
// syrof_version, inputs_hash, notes, then the SubmissionResult's fields
// (submission, assignment, title, public_only, seed_student, points, max_points,
// tests_passed, tests_total, build, tests: each with its criteria), and last
// "timings" (build_s, tests: name -> seconds). Wall times appear only in
// "timings", so two gradings of the same inputs give the same bytes but
// there. Pretty-printed, 2-space indent, keys in this fixed order.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "syrof/assignment/result.h"
#include "syrof/lab/base/error.h"

namespace syrof::grader {

inline constexpr int kGradeJsonVersion = 1;

/// A grade.json read back.
struct GradeFile {
  assignment::SubmissionResult result;
  std::string inputs_hash;           ///< InputsHash() of what was graded
  std::string syrof_version;
  std::vector<std::string> notes;    ///< the sandboxes' notes
};

/// The text of grade.json.
std::string GradeJson(const GradeFile& file);

/// A grade.json read back, or why it cannot be.
struct GradeFileOrError {
  std::optional<GradeFile> file;
  std::optional<lab::Error> error;
  bool ok() const { return file.has_value(); }
};

/// Reads `path`; an error, where `path`, when it is missing or not a
/// grade.json of this version.
GradeFileOrError ReadGradeJson(const std::string& path);

/// A hash (16 hex digits, FNV-1a 64) of everything a grade depends on: the
/// submission's files (names and bytes), the assignment folder's files,
/// SyROF's version and whether only public tests were graded; and, when
/// not empty, `hidden_seeds` (HiddenSeedsText of seeds derived per
/// student: a new course secret or student id then regrades).
std::string InputsHash(const std::string& submission_dir, const std::string& assignment_dir, bool public_only,
                       const std::string& hidden_seeds = "");

/// SyROF's version, e.g. "0.1.0".
std::string SyrofVersion();

}  // namespace syrof::grader
