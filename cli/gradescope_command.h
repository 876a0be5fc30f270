// `syrof gradescope NAME|PATH [-o autograder.zip] [--prefix DIR] [--per-student-seeds [--course-secret-file F]]`:
// the zip an instructor uploads to Gradescope as an assignment's autograder
// (setup.sh, run_autograder, SyROF as a self-contained folder, the assignment with its
// hidden sets, and with --per-student-seeds the course secret;
// grader/report's gradescope_bundle.h, docs/grading.md "Publishing to
// Gradescope").
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

#include "syrof/lab/base/error.h"

namespace syrof::cli {

struct GradescopeOptions {
  std::string assignment{};               ///< a name under ./assignments/, or a folder (or its assignment.yaml)
  std::string output{"autograder.zip"};  ///< the zip to write
  std::string prefix{};                   ///< the self-contained SyROF; empty: PrefixBesideBuild of the running syrof
  /// run_autograder's deadline, seconds: no test starts later (set it below
  /// the autograder timeout configured on Gradescope).
  /// 0: grader::report::kDefaultDeadlineS (8 of Gradescope's default 10 minutes).
  int deadline_s = 0;
  /// Per-student hidden seeds: the course secret (from `course_secret_file`,
  /// else $SYROF_COURSE_SECRET) goes into the bundle, and run_autograder
  /// derives each submission's hidden seeds from its users.
  bool per_student_seeds = false;
  std::string course_secret_file{};
};

/// Declares the subcommand on `app`.
CLI::App* SetupGradescopeCommand(CLI::App& app, GradescopeOptions& options);

/// Writes the bundle. Returns 0 when it is written; 2 for bad input (no
/// such assignment, an assignment that does not load, no self-contained
/// SyROF folder); 1 when
/// the zip cannot be written.
int RunGradescopeCommand(const GradescopeOptions& options, std::ostream& out, std::ostream& err);

/// A folder, or why there is none.
struct FolderOrError {
  std::optional<std::string> folder;
  std::optional<lab::Error> error;
  bool ok() const { return folder.has_value(); }
};

/// The assignment folder `name_or_path` names: a folder holding
/// assignment.yaml, an assignment.yaml itself, or a name NAME for
/// ./assignments/NAME. An error when there is none.
FolderOrError FindAssignmentFolder(const std::string& name_or_path);

/// The self-contained SyROF that `make gradescope-prefix` wrote into the
/// build tree `build_dir` (its gradescope-prefix/ folder). An error when
/// there is none, or when it is older than the build's syrof, app host or
/// libsyrof_app (it would ship old programs).
FolderOrError PrefixBesideBuild(const std::filesystem::path& build_dir);

}  // namespace syrof::cli
