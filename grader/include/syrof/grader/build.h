// Building a student's submission (docs/grading.md, "A submission's score"
// and "Threat model").
//
// A submission is a folder with a CMakeLists.txt (as `syrof new` writes:
// find_package(SyROF) + syrof_add_app) or just C/C++ sources (then a
// CMakeLists.txt is generated that builds one MODULE library of every
// *.c/*.cc/*.cpp/*.cxx linked to SyROF::app). Its regular files (no
// symbolic or hard links) are copied to a private temporary folder and
// built there by CMake in a sandboxed child: uid 65534 when started as root
// (the copy handed to it); Landlock limiting it to reading the toolchain
// and a copy of SyROF's package beside its own, and writing its own copy;
// a seccomp filter refusing sockets; network, PID, IPC and UTS namespaces
// (every process it leaves behind dies with it); its own process
// group killed at the wall time limit; rlimits on file size, CPU time and
// processes; its folder a tmpfs of `work_limit_bytes` in a mount namespace
// of its own, so its writes are bounded in total; no descriptor but 0-2. Its output is kept in OUT/build.log (the first
// `log_keep_bytes`, the rest counted; past `output_limit_bytes` the build is
// stopped). When it is done and its processes are gone, the grader copies
// the sources it built into OUT/source/, the library into OUT/build/, and
// removes the temporary folder: nothing the build could write is ever read
// as the grader's own.
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
  /// What the build's folder (its copy, build/ and tmp/: the only places it
  /// may write) holds in all: a tmpfs of this size, in memory. A build that
  /// fills it fails (build_failed, "wrote more than its folder holds").
  uint64_t work_limit_bytes = 256ull << 20;
  uint64_t max_processes = 512;                    ///< RLIMIT_NPROC of the build (a fork bomb stops there)
  /// Build even where the kernel has no Landlock (`--unsafe-no-file-isolation`):
  /// the build can then read and write whatever its uid can. Off: such a
  /// build is refused (verdict "refused").
  bool allow_unconfined = false;
};

/// SyROF's CMake package for students' builds: beside the running
/// executable's folder (a build tree: build/bin/.. holds SyROFConfig.cmake)
/// or the installed lib/cmake/SyROF. Empty when neither exists.
std::string FindSyrofPackage();

/// Builds `submission_dir` into `out_dir` (source/: what was built; build/: the app library; build.log) and
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
