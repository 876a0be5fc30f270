// `syrof grade`: grade a student's submission, a class, or a mixed swarm,
// and `syrof grade merge` (docs/grading.md):
//   syrof grade SUBMISSION_DIR --assignment NAME|PATH [--public-only] [--jobs N] [--out DIR]
//               [--student-seed ID | --gradescope-metadata FILE] [--course-secret-file FILE]
//               [--report student|full] [--deadline-s S] [--gradescope-results FILE]
//               [--submission-metadata FILE]
//   syrof grade --class SUBMISSIONS_DIR --assignment NAME --jobs N --out DIR [--shard I/N]
//               [--per-student-seeds] [--course-secret-file FILE] [--report student|full]
//   syrof grade --mix SUB1 SUB2 ... --assignment NAME [--out DIR]
//   syrof grade merge OUT1 OUT2 ... --out DIR
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace syrof::cli {

struct GradeOptions {
  std::string submission;               ///< one student's folder
  std::string assignment;               ///< NAME or a path to the assignment's folder
  std::string class_dir;                ///< --class: one folder per student
  std::vector<std::string> mix;         ///< --mix: submissions sharing a swarm
  bool public_only = false;
  int jobs = 1;
  std::string out_dir;                  ///< default: grade-out/<submission> (or grade-out/class, grade-out/mix)
  double build_timeout_s = 120;
  std::string shard;                    ///< "I/N"
  bool regrade = false;                 ///< --class: ignore earlier results
  bool quiet = false;
  bool unsafe_no_file_isolation = false;  ///< build and run untrusted code even without Landlock
  /// report.html's form: "student" (hidden tests as name, points and
  /// verdict only) or "full" (the instructor's: hidden tests whole).
  std::string report = "student";
  /// One submission: a test not started this many seconds after grading
  /// began is not run (0 points, the reason said); 0: no deadline.
  double deadline_s = 0;
  /// One submission: Gradescope's results.json also here, valid at every
  /// moment (rewritten after each test), for an autograder that may be
  /// stopped by Gradescope's timeout.
  std::string gradescope_results;
  /// One submission: Gradescope's submission_metadata.json, for which
  /// submission of its student(s) this is (the assignment's
  /// hidden_feedback_submissions cap); not for seeds.
  std::string submission_metadata;
  // Hidden seeds per student (docs/grading.md): the secret from
  // --course-secret-file, else $SYROF_COURSE_SECRET; never an argument.
  std::string student_seed;             ///< the student's id
  std::string gradescope_metadata;      ///< Gradescope's submission_metadata.json: the id from its users
  bool per_student_seeds = false;       ///< --class: each folder's name is its student's id
  std::string course_secret_file;
  // `syrof grade merge`
  bool merge = false;
  std::vector<std::string> merge_dirs;
  std::string merge_out;
};

/// Declares `grade` (and its `merge` subcommand) on `app`.
CLI::App* SetupGradeCommand(CLI::App& app, GradeOptions& options);

/// Whether this machine may grade: true on a kernel with Landlock; without
/// it, false with the reason on `err` unless `unsafe_no_file_isolation`, which
/// prints a warning on `out` instead (docs/grading.md, "Threat model").
/// `command` names the command in messages ("syrof grade").
bool MayGradeHere(const std::string& command, bool unsafe_no_file_isolation, std::ostream& out, std::ostream& err);

/// Runs it. 0 when graded (whatever the score), 2 for a usage error (the
/// message on `err`), 1 when grading itself failed (outputs not written).
int RunGradeCommand(const GradeOptions& options, std::ostream& out, std::ostream& err);

}  // namespace syrof::cli
