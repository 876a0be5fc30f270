// Grading one submission: build it (build.h), run every scenario x seed of
// the assignment through the app host, score each run with the rubric
// (syrof/assignment/score.h) and add the runs up as
// syrof/assignment/result.h says (docs/grading.md, "A submission's score").
//
// The submission's folder OUT holds:
//   source/, build/, build.log       what was built, the app library it made, the build's output
//   runs/<scenario>/seed-<seed>/     metrics.json, robots/<id>.log, and for a
//                                    failed run replay.bin (runs are
//                                    deterministic: a failed run is run again
//                                    with a replay, so passed runs keep none)
//   grade.json                       the SubmissionResult (grade_json.h)
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/result.h"
#include "syrof/grader/build.h"
#include "syrof/grader/student_seeds.h"

namespace syrof::grader {

struct GradeOptions {
  bool public_only = false;  ///< leave the hidden sets out (the total is then out of the public tests)
  int jobs = 1;              ///< runs side by side, each on its own thread
  BuildOptions build;
  /// Set: the hidden runs use seeds derived for this student (student_seeds.h)
  /// instead of the listed ones, and their replay commands are kept (the
  /// instructor needs the derived seed to rerun one).
  std::optional<StudentSeeds> student_seeds;
  /// Called after each test is graded (from the thread that ran it; calls
  /// are serialised). Optional: progress lines.
  std::function<void(const assignment::TestResult&)> on_test;
  /// Set: a test not started by then is not run; it gets 0 points and the
  /// run_error kNotRunDeadline, and the tests run before keep theirs
  /// (run_autograder's deadline below Gradescope's timeout).
  std::optional<std::chrono::steady_clock::time_point> deadline;
  /// The search tests load the library once and run each robot of each
  /// pattern as a copy of that load (docs/app_host.md, "The fork server").
  /// false: a fresh sandboxed host per robot and pattern, the same results
  /// slower. For the benches and tests that compare the two
  /// (bench_grade_search_class); no command-line option sets it.
  bool fork_server = true;
};

/// The run_error of a test that GradeOptions::deadline left unrun.
inline constexpr const char* kNotRunDeadline =
    "not run: grading reached its deadline before this test started (the autograder's own, set below "
    "Gradescope's timeout so that the tests already graded keep their points)";

/// The tests of `assignment`, in result.h's order (the runs, then the search
/// tests), with name, scenario, seed, visibility and output folder set,
/// nothing run.
std::vector<assignment::TestResult> PlanTests(const assignment::Assignment& assignment, bool public_only);

/// PlanTests without the search tests: the runs alone (what a mixed swarm
/// runs).
std::vector<assignment::TestResult> PlanRuns(const assignment::Assignment& assignment, bool public_only);

/// result.h's rule: a search test is worth its points, each run an equal
/// share of the rest (assignment::RunPoints); a test earns its share times
/// its fraction (0 with a run_error), passes with every point; the
/// submission's points and tests_passed are the sums. Rounds to the
/// hundredth.
void AddUp(assignment::SubmissionResult& result, const assignment::Assignment& assignment);

/// The assignment as `options` grades it: with the hidden seeds derived
/// for options.student_seeds when set (student_seeds.h), else as given.
assignment::Assignment GradedAssignment(const assignment::Assignment& assignment, const GradeOptions& options);

/// Grades an app library already built (and checked): every test run into
/// `out_dir`/runs/ (the seeds of GradedAssignment). The build part of the result says "ok" with `library`.
assignment::SubmissionResult GradeLibrary(const assignment::Assignment& assignment, const std::string& library,
                                          const std::string& out_dir, const GradeOptions& options);

/// Builds `submission_dir` into `out_dir` and grades it. A submission that
/// does not build gets every test with 0 points and a run_error naming the
/// build's verdict. `notes` receives the sandboxes' notes (build.h).
assignment::SubmissionResult GradeSubmission(const assignment::Assignment& assignment,
                                             const std::string& submission_dir, const std::string& out_dir,
                                             const GradeOptions& options, std::vector<std::string>& notes);

/// Where an assignment named on the command line is: `name_or_path` itself
/// when it is a folder holding assignment.yaml (or the file); else
/// $SYROF_ASSIGNMENTS_DIR/NAME; else the installed share/syrof/assignments/NAME
/// beside this executable's prefix; else `source_tree_dir`/NAME (the build
/// tree's own assignments/). Empty when none has it; `looked` lists the
/// places tried.
std::string FindAssignment(const std::string& name_or_path, const std::string& source_tree_dir,
                           std::vector<std::string>& looked);

/// Where a scenario file named as the grader's replay commands name it is:
/// `path` itself when it exists; else, for a relative `NAME/REST` (the
/// assignment's name, then the file inside its folder, as
/// `gather/scenarios/gather_6.yaml`), REST inside the assignment NAME found
/// as FindAssignment finds it. So the command a report prints runs from a
/// student's own project folder. Empty when neither exists.
std::string FindAssignmentFile(const std::string& path, const std::string& source_tree_dir);

}  // namespace syrof::grader
