// Checking an assignment before students get it (`syrof assignment check`;
// docs/grading.md, "Writing an assignment"): its reference, its starter and
// every broken variant, each built and graded exactly as a student's
// submission is (GradeSubmission, grade.h) on every public and hidden run,
// then compared with what it must get:
//
//   reference         full marks on every run (and its expected.yaml, if any)
//   starter           fewer points than full marks (and its expected.yaml, if any)
//   broken/<variant>  exactly its expected.yaml (CompareWithExpected, syrof/assignment/expected.h)
//
// A broken variant's project is made from its reference and mistake.patch
// by scripts/broken-variant.sh, as the build makes it (docs/grading.md,
// "Broken variants"); the patching lives in that script alone.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/expected.h"
#include "syrof/assignment/result.h"
#include "syrof/grader/grade.h"
#include "syrof/grader/student_seeds.h"
#include "syrof/lab/base/error.h"

namespace syrof::grader {

enum class SubjectRole : uint8_t { kReference, kStarter, kBrokenVariant };

/// One submission folder of an assignment that the check grades.
struct CheckSubject {
  std::string name;     ///< "reference", "starter", "broken/<variant>"
  SubjectRole role = SubjectRole::kReference;
  std::string folder;   ///< the folder in the assignment (a variant's holds no sources, only its patch and notes)
  std::string variant;  ///< a broken variant's name; empty otherwise
  /// The folder's expected.yaml; required for a variant. Without one the
  /// reference must get full marks and the starter must lose points.
  std::optional<assignment::Expected> expected;
  /// Set on a probe (ProbeSubjects): the reference, graded on the hidden
  /// runs only, with the seeds derived for this student.
  std::optional<StudentSeeds> probe;
};

/// The reference, the starter and each broken variant (by name) of
/// `assignment`, each with its expected.yaml read. The first problem an
/// instructor must fix comes back as an error (with file:line:column when it
/// is in a file): no reference/ or starter/ folder; a variant without
/// mistake.patch or expected.yaml; an expected.yaml that does not load; a
/// reference expected to lose points; a starter or variant expected to get
/// full marks (it would check nothing).
std::optional<lab::Error> FindCheckSubjects(const assignment::Assignment& assignment,
                                            std::vector<CheckSubject>& subjects);

/// The secret probes derive their seeds with when the instructor gives no
/// course secret: any fixed text gives seeds as unrelated to the listed
/// ones as a student's are.
inline constexpr const char* kProbeSecret = "syrof assignment check: probe students";

/// `count` probes of `reference` (a subject of role kReference), named
/// "probe/1" .. "probe/<count>": each the reference graded on the hidden
/// runs only, with the seeds `course_secret` derives for student
/// "probe-<i>". A student's hidden seeds are derived, not listed
/// (docs/grading.md, "Hidden seeds per student"), so the reference must
/// get full marks on seeds no one has tried; this tries count x (seeds
/// per hidden entry) of them.
std::vector<CheckSubject> ProbeSubjects(const CheckSubject& reference, int count, const std::string& course_secret);

/// Why `result` is not what `subject` must get, one line each; empty when it
/// is. A subject that did not build never is. Pure.
std::vector<std::string> JudgeSubject(const CheckSubject& subject, const assignment::SubmissionResult& result);

/// One subject, checked.
struct SubjectOutcome {
  CheckSubject subject;
  /// As GradeSubmission returned it; a variant whose project could not be
  /// made has no tests and build.verdict BuildVerdict::kNotMade.
  assignment::SubmissionResult result;
  /// JudgeSubject's lines, or why it could not be graded (a variant's patch
  /// does not apply, the reports could not be written).
  std::vector<std::string> problems;
  double wall_seconds = 0;  ///< making, building and grading it
  bool ok() const { return problems.empty(); }
};

struct CheckOptions {
  /// How each subject is graded, as `syrof grade` sets it up (public_only is
  /// ignored: every run is checked; jobs is set from `jobs` below).
  GradeOptions grade;
  /// Threads in all: subjects side by side, and a subject's runs side by
  /// side when there are fewer subjects than threads.
  int jobs = 1;
  /// scripts/broken-variant.sh (needed only for broken variants).
  std::string broken_variant_script;
  /// Called when a subject is done (serialised), for progress lines.
  std::function<void(const SubjectOutcome&)> on_subject;
};

/// Grades every subject into `out_dir`/<subject name>/ (grade.json and the
/// reports, as `syrof grade --out` writes them); a variant's project is made
/// first in `out_dir`/variants/<variant>/. Outcomes in `subjects`' order.
std::vector<SubjectOutcome> CheckAssignment(const assignment::Assignment& assignment,
                                            const std::vector<CheckSubject>& subjects, const std::string& out_dir,
                                            const CheckOptions& options);

/// The table: one row per subject with what it must get, what it got,
/// PASS or FAIL and its seconds; under a failed row, why.
void PrintCheckTable(const std::vector<SubjectOutcome>& outcomes, double assignment_points, std::ostream& out);

}  // namespace syrof::grader
