// The Gradescope autograder bundle (docs/grading.md, "Publishing to
// Gradescope"): the zip `syrof gradescope` writes. At its root, as
// Gradescope requires, `setup.sh` (installs SyROF from the Debian package
// beside it) and `run_autograder` (grades /autograder/submission with
// `syrof grade` into /autograder/results/results.json); the package; and the
// assignment's folder under assignment/, hidden sets included, its
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

namespace syrof::grader::report {

/// One file of the bundle.
struct BundleFile {
  std::string name;         ///< its path in the zip, '/'-separated, relative
  std::string source_path;  ///< a file to copy; empty when `bytes` is the content
  std::string bytes;
  bool executable = false;  ///< mode 0755 instead of 0644
};

struct Bundle {
  std::vector<BundleFile> files;  ///< sorted by name
};

/// A bundle, or why there is none.
struct BundleResult {
  std::optional<Bundle> bundle;
  std::string error;
  bool ok() const { return bundle.has_value(); }
};

/// The scripts, as they go into the bundle (grader/report/gradescope/).
std::string GradescopeSetupScript();
std::string GradescopeRunScript();

/// Where a bundle with per-student hidden seeds holds the course secret
/// (docs/grading.md, "Hidden seeds per student"); run_autograder derives the
/// hidden seeds from it and the submitting users when it is there.
inline constexpr const char* kCourseSecretFile = "course_secret";

/// The bundle of the assignment in `assignment_folder` (which holds
/// assignment.yaml) with the package `deb_path`, which must be a Debian
/// package named syrof_*.deb. Reads the folder's listing, not its files.
/// With `course_secret`, the bundle holds it as kCourseSecretFile: the zip
/// is then as secret as the secret.
BundleResult GradescopeBundle(const std::string& assignment_folder, const std::string& deb_path,
                              const std::optional<std::string>& course_secret = std::nullopt);

/// Writes `bundle` as a zip at `zip_path` (replacing it). Returns "" or
/// what went wrong.
std::string WriteBundleZip(const Bundle& bundle, const std::string& zip_path);

}  // namespace syrof::grader::report
