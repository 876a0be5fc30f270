// Building a student's submission (docs/grading.md, "A submission's score").
//
// A submission is a folder with a CMakeLists.txt (as `syrof new` writes:
// find_package(SyROF) + syrof_add_app) or just C/C++ sources (then a
// CMakeLists.txt is generated that builds one MODULE library of every
// *.c/*.cc/*.cpp/*.cxx linked to SyROF::app). It is copied to OUT/source/
// and built in OUT/build/ by CMake in a sandboxed child: its own process
// group (killed at the wall time limit), no network (a user and network
// namespace where the kernel allows), rlimits on file size and CPU time,
// and its output kept in OUT/build.log (the first `log_keep_bytes`, the
// rest counted; past `output_limit_bytes` the build is stopped).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "syrof/assignment/result.h"

namespace syrof::grader {

struct BuildOptions {
  /// The folder holding SyROFConfig.cmake; empty: FindSyrofPackage().
  std::string syrof_dir;
  double timeout_s = 120;                          ///< wall time for configure + build
  uint64_t log_keep_bytes = 1ull << 20;            ///< build.log keeps this much
  uint64_t output_limit_bytes = 256ull << 20;      ///< more output stops the build (output_limit)
  uint64_t file_size_limit_bytes = 1ull << 30;     ///< RLIMIT_FSIZE of every build process
  uint64_t cpu_limit_s = 600;                      ///< RLIMIT_CPU of every build process
  uint64_t max_submission_bytes = 64ull << 20;     ///< a bigger submission is refused (build_failed)
};

/// SyROF's CMake package for students' builds: beside the running
/// executable's folder (a build tree: build/bin/.. holds SyROFConfig.cmake)
/// or the installed lib/cmake/SyROF. Empty when neither exists.
std::string FindSyrofPackage();

/// Builds `submission_dir` in `out_dir` (source/, build/, build.log) and
/// returns the verdict (assignment::BuildResult). `notes` receives what the
/// sandbox could not apply on this machine ("network not isolated: ..."),
/// one line each. Never throws for anything the submission does.
assignment::BuildResult BuildSubmission(const std::string& submission_dir, const std::string& out_dir,
                                        const BuildOptions& options, std::vector<std::string>& notes);

/// The source files a sources-only submission builds, relative to `dir`,
/// sorted (*.c, *.cc, *.cpp, *.cxx, in any folder except build/ and hidden
/// ones).
std::vector<std::string> FindSources(const std::string& dir);

}  // namespace syrof::grader
