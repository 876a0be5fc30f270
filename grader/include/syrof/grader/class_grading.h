// Grading a class (docs/grading.md, "Grading a class"): every student's
// folder of SUBMISSIONS_DIR graded into OUT/<student>/ as one submission
// (grade.h), then OUT/class.csv and OUT/summary.txt.
//
// - Resumable: a student whose OUT/<student>/grade.json exists with the
//   same InputsHash (submission files, assignment files, SyROF's version)
//   is not graded again.
// - Sharded: the sorted student list is cut in N slices; shard I (1-based)
//   grades slice I. MergeClassOutputs then combines the shards' folders.
// - Isolated: each submission's build and runs have their own limits; one
//   that does not compile, crashes, loops or floods its output costs at most
//   its own limits and never stops the others.
// - Deterministic: class.csv and summary.txt hold no timings; rerunning
//   gives the same bytes.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/result.h"
#include "syrof/grader/grade.h"
#include "syrof/lab/base/error.h"

namespace syrof::grader {

/// One slice of a class: `index` of `count`, 1-based.
struct Shard {
  int index = 1;
  int count = 1;
};

/// A shard, or why the text names none.
struct ShardOrError {
  std::optional<Shard> shard;
  std::optional<lab::Error> error;
  bool ok() const { return shard.has_value(); }
};

/// Parses "I/N" (1 <= I <= N <= 10000); an error otherwise.
ShardOrError ParseShard(const std::string& text);

/// The students (folder names, sorted, hidden folders left out) of `submissions_dir`.
std::vector<std::string> ListStudents(const std::string& submissions_dir);

/// The slice of `students` that `shard` grades.
std::vector<std::string> ShardOf(const std::vector<std::string>& students, const Shard& shard);

struct ClassOptions {
  /// grade.jobs is ignored: each student is graded on one thread. With
  /// grade.student_seeds set, each student's hidden seeds are derived from
  /// its folder's name (student_seeds.student is ignored).
  GradeOptions grade;
  int jobs = 1;                 ///< students graded side by side
  Shard shard;
  bool resume = true;           ///< false: grade every student again
  std::string assignment_dir;   ///< the assignment's folder (for the inputs' hash)
  /// Each student's report.html in the instructor's full form (hidden tests
  /// whole); false: the student's form. A resumed student's reports are
  /// written again in the form asked (the same bytes for the same form).
  bool full_report = false;
  /// Called once per student when done (serialised): the result and whether it was resumed.
  std::function<void(const assignment::SubmissionResult&, bool resumed)> on_student;
};

struct ClassResult {
  std::vector<assignment::SubmissionResult> students;  ///< sorted by name
  int graded = 0;
  int resumed = 0;
  std::vector<std::string> notes;  ///< the sandboxes' notes, each once
};

/// Grades the class into `out_dir` and writes class.csv and summary.txt.
ClassResult GradeClass(const assignment::Assignment& assignment, const std::string& submissions_dir,
                       const std::string& out_dir, const ClassOptions& options);

/// class.csv: student, points, max_points, tests_passed, tests, build, then
/// one column per scenario (its points summed over seeds), rows by student.
std::string ClassCsv(const std::vector<assignment::SubmissionResult>& students);

/// summary.txt: count, mean, median, a histogram of the points in deciles,
/// build failures, the most-failed tests.
std::string ClassSummary(const std::vector<assignment::SubmissionResult>& students);

/// Writes class.csv and summary.txt into `out_dir`; what failed, if anything.
std::optional<lab::Error> WriteClassFiles(const std::vector<assignment::SubmissionResult>& students,
                                          const std::string& out_dir);

/// The students of merged class outputs, or why they cannot be merged.
struct MergedClass {
  std::optional<std::vector<assignment::SubmissionResult>> students;  ///< sorted by name
  std::optional<lab::Error> error;
  bool ok() const { return students.has_value(); }
};

/// Reads every OUT/<student>/grade.json of each of `shard_dirs` and writes
/// the combined class.csv and summary.txt into `out_dir`. An error when a
/// folder cannot be read, a shard did not finish, or a student appears
/// twice.
MergedClass MergeClassOutputs(const std::vector<std::string>& shard_dirs, const std::string& out_dir);

}  // namespace syrof::grader
