// `syrof assignment` and its two subcommands' arguments; the work is in
// assignment_check_command.cpp and assignment_new_command.cpp.
#include "assignment_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "exit_status.h"

namespace syrof::cli {

CLI::App* SetupAssignmentCommand(CLI::App& app, AssignmentOptions& options) {
  CLI::App* assignment = app.add_subcommand(
      "assignment", "Write an assignment and check it before students get it (new, check); docs/grading.md");
  assignment->require_subcommand(1);

  CLI::App* check = assignment->add_subcommand(
      "check",
      "Build and grade an assignment's reference, starter and every broken variant as students are graded, and "
      "compare each with what it must get (exit 0 all match, 1 a mismatch, 2 bad input)");
  AssignmentCheckOptions& c = options.check;
  check->add_option("assignment", c.assignment, "The assignment: a folder holding assignment.yaml (or a NAME)")
      ->required();
  check->add_option("--jobs", c.jobs, "Threads: subjects graded side by side (default 1)")->check(CLI::Range(1, 256));
  check->add_option("--only", c.only,
                    "Check only this subject: reference, starter or a broken variant (VARIANT or broken/VARIANT); "
                    "repeat for more")
      ->allow_extra_args(false);  // one value each time: `--only starter DIR` leaves DIR the assignment
  check->add_option("--out", c.out_dir, "Where each subject's reports go (default check-out/<assignment>)");
  check->add_option("--build-timeout-s", c.build_timeout_s, "Wall time for a build, seconds (default 120)")
      ->check(CLI::Range(1.0, 3600.0));
  check->add_option("--gradescope-budget", c.gradescope_budget_s,
                    "Also grade the reference alone, measure its CPU time and warn when, under Gradescope's half a "
                    "CPU, it would take more than half of this many seconds (Gradescope's default timeout: 600)")
      ->check(CLI::Range(1.0, 86400.0));
  check->add_option("--probe-students", c.probe_students,
                    "Also grade the reference on the hidden seeds derived for N probe students (per-student seeds: "
                    "it must get full marks on seeds no file lists); default 0")
      ->check(CLI::Range(0, 1000));
  check->add_flag("--quiet", c.quiet, "No progress lines");
  check->add_flag("--unsafe-no-file-isolation", c.unsafe_no_file_isolation,
                  "Check even where the kernel has no Landlock (as syrof grade)");
  check->callback([&options] { options.subcommand = "check"; });

  CLI::App* make = assignment->add_subcommand(
      "new",
      "Write a skeleton assignment folder (assignment.yaml, README.md, starter/, reference/, scenarios/, hidden/, "
      "broken/) that `syrof assignment check` passes");
  make->add_option("name", options.new_assignment.name,
                   "The assignment's name: its folder and its app (a C identifier: letters, digits, '_')")
      ->required();
  make->add_option("--dir", options.new_assignment.parent,
                   "The folder to write it in (default: the current folder); PARENT/NAME must not exist");
  make->callback([&options] { options.subcommand = "new"; });
  return assignment;
}

int RunAssignmentCommand(const AssignmentOptions& options, std::ostream& out, std::ostream& err) {
  if (options.subcommand == "check") return RunAssignmentCheck(options.check, out, err);
  if (options.subcommand == "new") return RunAssignmentNew(options.new_assignment, out, err);
  fmt::print(err, "syrof assignment: give a subcommand: check or new\nRun with --help for more information.\n");
  return kBadInput;
}

}  // namespace syrof::cli
