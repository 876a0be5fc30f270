// What grading a submission produced: the build, one test per scenario and
// seed with its run's score, and the submission's total. The runner
// (`syrof grade`, grader/) fills it; the reports (grader/report: Gradescope
// results.json, JUnit XML, the HTML report, the class CSV) only read it.
//
// How runs add up (docs/grading.md, "A submission's score"): a search test
// is worth its own points, and every other test the same share of the rest,
// `(points - search points) / runs`; a test earns its share times its
// run's fraction (run points / run max points).
// The total is the exact sum rounded once to the hundredth (each test's
// points are rounded for display only), so full marks on every run is
// exactly the assignment's points whatever the number of tests.
// A test passes when its run earned every point. A submission that does not
// build gets 0 on every test. With `public_only` the hidden sets are not run
// and the total is out of the public tests alone.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/score.h"

namespace syrof::grader::assignment {

/// How building a submission ended. Its name (ToString) is what grade.json,
/// the reports and the messages say.
enum class BuildVerdict {
  kOk,           ///< "ok"
  kNoSources,    ///< "no_sources": nothing to build
  kBuildFailed,  ///< "build_failed": the compiler or CMake said no (or the build's sandbox failed)
  kTimeout,      ///< "timeout": over the build's time limit
  kOutputLimit,  ///< "output_limit": over the build's output limit
  kNoLibrary,    ///< "no_library": it built, but no app library (or more than one) came out
  kBadLibrary,   ///< "bad_library": refused by the app host's CheckLibrary (no entry point, wrong ABI, ...)
  kRefused,      ///< "refused": the machine cannot confine the build (no Landlock) and was not told to go on
  kNotMade,      ///< "not_made": `syrof assignment check` could not make the broken variant to build
};

inline constexpr BuildVerdict kBuildVerdicts[] = {
    BuildVerdict::kOk,        BuildVerdict::kNoSources,  BuildVerdict::kBuildFailed,
    BuildVerdict::kTimeout,   BuildVerdict::kOutputLimit, BuildVerdict::kNoLibrary,
    BuildVerdict::kBadLibrary, BuildVerdict::kRefused,    BuildVerdict::kNotMade};

constexpr const char* ToString(BuildVerdict verdict) {
  switch (verdict) {
    case BuildVerdict::kOk: return "ok";
    case BuildVerdict::kNoSources: return "no_sources";
    case BuildVerdict::kBuildFailed: return "build_failed";
    case BuildVerdict::kTimeout: return "timeout";
    case BuildVerdict::kOutputLimit: return "output_limit";
    case BuildVerdict::kNoLibrary: return "no_library";
    case BuildVerdict::kBadLibrary: return "bad_library";
    case BuildVerdict::kRefused: return "refused";
    case BuildVerdict::kNotMade: return "not_made";
  }
  return "?";
}

/// The verdict whose name is `name`; nullopt for a name no verdict has.
inline std::optional<BuildVerdict> BuildVerdictNamed(std::string_view name) {
  for (const BuildVerdict verdict : kBuildVerdicts) {
    if (name == ToString(verdict)) return verdict;
  }
  return std::nullopt;
}

/// How building the submission ended.
struct BuildResult {
  BuildVerdict verdict = BuildVerdict::kOk;
  std::string detail;        ///< one line a student understands, e.g. the first compiler error
  std::string log_path;      ///< the build's kept output, relative to the submission's out dir
  std::string library_path;  ///< the app library built (absolute), when verdict is "ok"
  double wall_seconds = 0;   ///< timing: not part of any byte-identical output
  bool ok() const { return verdict == BuildVerdict::kOk; }
};

/// One graded run: one scenario of a set with one seed; or a search test.
struct TestResult {
  std::string name;      ///< "<scenario name>/seed-<seed>", or "search/<name>"; unique in the submission
  std::string scenario;  ///< the ScenarioRun's name (the SearchTestSpec's for a search test)
  uint64_t seed = 0;     ///< a search test's: the scenario file's seed
  bool search = false;   ///< a search test: its score is one criterion, "search", all or nothing
  Visibility visibility = Visibility::kPublic;
  /// Its entry's `gradescope:`; kDefault: by `visibility` (report's
  /// GradescopeVisibilityOf).
  GradescopeVisibility gradescope = GradescopeVisibility::kDefault;
  RunScore score;              ///< per criterion (empty when the run did not finish)
  double max_points = 0;       ///< this test's share of the assignment's points
  double points = 0;           ///< earned: max_points x score.points / score.max_points, to the hundredth
  bool passed = false;         ///< every criterion at full points
  std::string run_error;       ///< empty, or why the run has no score ("time limit of 60 s reached", ...)
  /// Empty, or how the robots' payloads broke the assignment's message
  /// format (`message:`): reported so a student sees it before a mixed
  /// swarm does, not scored.
  std::string message_format;
  std::string replay_command;  ///< the command that reruns it, as a student types it
  std::string output_dir;      ///< the run's folder (metrics.json, robots/*.log), relative to the submission's out dir
  std::string replay_path;     ///< a failed run's replay, relative to the submission's out dir; empty when passed
  double wall_seconds = 0;     ///< timing: not part of any byte-identical output
};

/// One submission, graded.
struct SubmissionResult {
  std::string submission;  ///< the submission folder's name (the student, in a class)
  std::string assignment;  ///< Assignment::name
  std::string title;       ///< Assignment::title
  bool public_only = false;
  /// The student id the hidden seeds were derived from (docs/grading.md,
  /// "Hidden seeds per student"); empty when they are assignment.yaml's.
  std::string seed_student;
  BuildResult build;
  std::vector<TestResult> tests;  ///< public sets first, each in file order, seeds in order
  double points = 0;              ///< the exact sum of the tests' shares, rounded once to the hundredth
  double max_points = 0;          ///< the assignment's points
  int tests_passed = 0;
};

}  // namespace syrof::grader::assignment
