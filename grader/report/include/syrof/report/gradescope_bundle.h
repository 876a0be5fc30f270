// The Gradescope autograder bundle (docs/grading.md, "Publishing to
// Gradescope"): the zip `syrof gradescope` writes. At its root, as
// Gradescope requires, `setup.sh` (installs a compiler, CMake and make from
// the image's own archive where missing, and checks that the bundled syrof
// runs) and `run_autograder` (grades /autograder/submission with the
// bundled `syrof grade` into /autograder/results/results.json); under
// syrof/, SyROF as a self-contained folder (its programs, libsyrof_app, the
// app API's headers, its CMake package, and every shared library they need
// that is not glibc's or the C++ runtime's: scripts/gradescope-prefix.sh);
// and the assignment's folder under assignment/, hidden sets included, its
// reference/ and broken/ folders (and dot files) left out.
//
// The zip is deterministic: entries sorted by name, every timestamp
// 1980-01-01 00:00, Unix modes (0755 for the scripts and folders, 0644
// otherwise), so the same inputs give the same bytes. With a course secret
// (per-student hidden seeds), it holds the secret too.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"

namespace syrof::grader::report {

/// One file of the bundle.
struct BundleFile {
  std::string name;         ///< its path in the zip, '/'-separated, relative
  std::string source_path;  ///< a file to copy; empty when `bytes` is the content
  std::string bytes;
  bool executable = false;  ///< mode 0755 instead of 0644 (the scripts, and files their owner may execute)
};

struct Bundle {
  std::vector<BundleFile> files;  ///< sorted by name
};

/// A bundle, or why there is none.
struct BundleResult {
  std::optional<Bundle> bundle;
  std::optional<lab::Error> error;
  bool ok() const { return bundle.has_value(); }
};

/// The scripts, as they go into the bundle (grader/report/gradescope/).
std::string GradescopeSetupScript();
std::string GradescopeRunScript();

/// Where a bundle with per-student hidden seeds holds the course secret
/// (docs/grading.md, "Hidden seeds per student"); run_autograder derives the
/// hidden seeds from it and the submitting users when it is there.
inline constexpr const char* kCourseSecretFile = "course_secret";

/// Where the bundle holds SyROF, and the file scripts/gradescope-prefix.sh
/// writes into a folder it made and checked (every ELF file fits Ubuntu
/// 22.04's glibc 2.35 and libstdc++; what it bundled).
inline constexpr const char* kSyrofFolder = "syrof";
inline constexpr const char* kSyrofFolderMark = "gradescope-prefix.txt";

/// Where the bundle holds run_autograder's deadline: whole seconds after
/// grading starts, past which no test is started (`syrof grade
/// --deadline-s`); below Gradescope's timeout, so that a slow submission's
/// finished tests keep their points. kDefaultDeadlineS: 8 of Gradescope's
/// default 10 minutes.
inline constexpr const char* kDeadlineFile = "deadline_s";
inline constexpr int kDefaultDeadlineS = 480;

/// The bundle of the assignment in `assignment_folder` (which holds
/// assignment.yaml) with the self-contained SyROF in `syrof_folder` (as
/// scripts/gradescope-prefix.sh makes it: it must hold bin/syrof, the app
/// host, libsyrof_app, the CMake package, the app API's header and
/// kSyrofFolderMark). Reads the folders' listings, not their files.
/// With `course_secret`, the bundle holds it as kCourseSecretFile: the zip
/// is then as secret as the secret.
/// `deadline_s` goes into kDeadlineFile.
BundleResult GradescopeBundle(const std::string& assignment_folder, const std::string& syrof_folder,
                              const std::optional<std::string>& course_secret = std::nullopt,
                              int deadline_s = kDefaultDeadlineS);

/// Writes `bundle` as a zip at `zip_path` (replacing it). Returns what went
/// wrong (naming the zip), if anything; nothing is written then.
std::optional<lab::Error> WriteBundleZip(const Bundle& bundle, const std::string& zip_path);

}  // namespace syrof::grader::report
