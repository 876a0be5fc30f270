// `syrof assignment`: the instructor's loop for writing an assignment
// (docs/grading.md, "Writing an assignment"):
//   syrof assignment new NAME [--dir PARENT]
//       writes a skeleton assignment folder PARENT/NAME that checks clean
//   syrof assignment check DIR [--jobs N] [--only SUBJECT]... [--out OUT]
//       builds and grades DIR's reference, starter and every broken variant
//       as students are graded, and compares each with what it must get
// One file per subcommand: assignment_check_command.cpp and
// assignment_new_command.cpp; this header declares both.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace syrof::cli {

struct AssignmentCheckOptions {
  std::string assignment;            ///< a folder holding assignment.yaml (or a NAME, as syrof grade finds it)
  int jobs = 1;                      ///< threads: subjects side by side, a subject's runs when there are fewer
  std::vector<std::string> only;     ///< "reference", "starter", a variant ("rand" or "broken/rand"); empty: all
  std::string out_dir;               ///< reports; default check-out/<assignment>
  double build_timeout_s = 120;
  bool quiet = false;
  bool unsafe_no_file_isolation = false;
  /// --probe-students N: also grade the reference on the hidden seeds
  /// derived for N probe students (grader::ProbeSubjects).
  int probe_students = 0;
  /// --gradescope-budget S: grade the reference once more, alone, measuring
  /// its CPU time, and warn when its projected wall time under Gradescope's
  /// half a CPU (twice the CPU time) is more than half of S.
  double gradescope_budget_s = 0;
  /// Not a command-line option: scripts/broken-variant.sh. Empty: the
  /// source tree's, where this syrof was built.
  std::string broken_variant_script;
};

struct AssignmentNewOptions {
  std::string name;         ///< the assignment's folder name and its app's name: a C identifier
  std::string parent = ".";  ///< where the folder is made
};

struct AssignmentOptions {
  std::string subcommand;  ///< "check" or "new": the one given
  AssignmentCheckOptions check;
  AssignmentNewOptions new_assignment;
};

/// Declares `assignment` with its `check` and `new` subcommands on `app`.
CLI::App* SetupAssignmentCommand(CLI::App& app, AssignmentOptions& options);

/// Runs the subcommand given.
int RunAssignmentCommand(const AssignmentOptions& options, std::ostream& out, std::ostream& err);

/// `syrof assignment check`: 0 when every subject got what it must, 1 when
/// one did not (the table says which and why) or grading failed inside
/// syrof, 2 for bad input (a missing or malformed assignment.yaml or
/// expected.yaml, with file:line:column; a missing reference/ or starter/;
/// an unknown --only).
int RunAssignmentCheck(const AssignmentCheckOptions& options, std::ostream& out, std::ostream& err);

/// `syrof assignment new`: 0 when written, 2 when the name is bad or
/// PARENT/NAME exists (nothing written), 1 when writing failed.
int RunAssignmentNew(const AssignmentNewOptions& options, std::ostream& out, std::ostream& err);

}  // namespace syrof::cli
