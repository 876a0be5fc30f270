#include "gradescope_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <vector>

#include <cstdlib>

#include "syrof/assignment/assignment.h"
#include "syrof/grader/student_seeds.h"
#include "exit_status.h"
#include "syrof/report/gradescope_bundle.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;

size_t Tests(const std::vector<grader::assignment::ScenarioRun>& runs) {
  size_t tests = 0;
  for (const grader::assignment::ScenarioRun& run : runs) tests += run.seeds.size();
  return tests;
}

// The course secret for --per-student-seeds: --course-secret-file, else
// $SYROF_COURSE_SECRET (its error names the variable).
grader::CourseSecretOrError CourseSecret(const GradescopeOptions& options) {
  if (!options.course_secret_file.empty()) return grader::ReadCourseSecretFile(options.course_secret_file);
  const char* variable = std::getenv(grader::kCourseSecretVariable);
  if (variable == nullptr || *variable == '\0') {
    return {std::nullopt,
            lab::Error{.where = "",
                       .message = fmt::format("--per-student-seeds needs the course secret: set {} or give "
                                              "--course-secret-file FILE",
                                              grader::kCourseSecretVariable)}};
  }
  if (std::optional<lab::Error> problem = grader::CheckCourseSecret(variable)) {
    return {std::nullopt, lab::Error{.where = grader::kCourseSecretVariable, .message = problem->ToString()}};
  }
  return {std::string(variable), std::nullopt};
}

// The build tree the running syrof is in (build/bin/syrof -> build).
fs::path RunningBuildTree() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) return {};
  return self.parent_path().parent_path();
}

// No folder, and why.
FolderOrError NoFolder(std::string message) {
  return {std::nullopt, lab::Error{.where = "", .message = std::move(message)}};
}

}  // namespace

FolderOrError FindAssignmentFolder(const std::string& name_or_path) {
  std::error_code ignored;
  const fs::path given(name_or_path);
  if (fs::is_regular_file(given, ignored) && given.filename() == "assignment.yaml") {
    return {given.parent_path().empty() ? "." : given.parent_path().string(), std::nullopt};
  }
  if (fs::is_directory(given, ignored)) {
    if (fs::is_regular_file(given / "assignment.yaml", ignored)) return {given.string(), std::nullopt};
    return NoFolder(fmt::format("{} holds no assignment.yaml", name_or_path));
  }
  const bool plain_name = !name_or_path.empty() && name_or_path.find('/') == std::string::npos &&
                          name_or_path != "." && name_or_path != "..";
  if (plain_name) {
    const fs::path named = fs::path("assignments") / name_or_path;
    if (fs::is_regular_file(named / "assignment.yaml", ignored)) return {named.string(), std::nullopt};
    return NoFolder(fmt::format("no assignment '{}': neither a folder nor ./{}/assignment.yaml", name_or_path,
                                named.string()));
  }
  return NoFolder(fmt::format("no assignment at {}", name_or_path));
}

FolderOrError PrefixBesideBuild(const fs::path& build_dir) {
  const fs::path prefix = build_dir / "gradescope-prefix";
  const fs::path mark = prefix / grader::report::kSyrofFolderMark;
  std::error_code failed;
  if (!fs::is_regular_file(mark, failed)) {
    return NoFolder(fmt::format(
        "no self-contained SyROF for Gradescope beside this build ({}): make it with `make gradescope-prefix` "
        "(scripts/gradescope-prefix.sh), or give one with --prefix DIR",
        prefix.string()));
  }
  // A folder older than the programs it copied would ship an old syrof.
  for (const char* program : {"bin/syrof", "bin/syrof-app-host", "lib/libsyrof_app.so.1"}) {
    const fs::path built = build_dir / program;
    if (!fs::exists(built, failed)) continue;
    if (fs::last_write_time(built, failed) > fs::last_write_time(mark, failed)) {
      return NoFolder(fmt::format("{} is older than {}: make it again with `make gradescope-prefix`",
                                  prefix.string(), built.string()));
    }
  }
  return {prefix.string(), std::nullopt};
}

CLI::App* SetupGradescopeCommand(CLI::App& app, GradescopeOptions& options) {
  CLI::App* command = app.add_subcommand(
      "gradescope",
      "Write an assignment's Gradescope autograder: a zip with setup.sh, run_autograder, SyROF as a "
      "self-contained folder (it needs no package from apt but a compiler, CMake and make) and the assignment "
      "(hidden sets included)");
  command->add_option("ASSIGNMENT", options.assignment,
                      "NAME (the folder assignments/NAME here) or PATH (an assignment's folder)")
      ->required();
  command->add_option("-o,--output", options.output, "The zip to write")->capture_default_str();
  command->add_option("--prefix", options.prefix,
                      "SyROF as a self-contained folder, as `make gradescope-prefix` writes it (default: "
                      "gradescope-prefix/ in the running build tree)");
  command->add_option("--deadline-s", options.deadline_s,
                      "run_autograder starts no test after this many seconds: set it below the autograder "
                      "timeout you give Gradescope, so that a slow submission's finished tests keep their points")
      ->default_str(std::to_string(grader::report::kDefaultDeadlineS))
      ->check(CLI::Range(10, 86400));
  command->add_flag("--per-student-seeds", options.per_student_seeds,
                    "Put the course secret ($SYROF_COURSE_SECRET or --course-secret-file) in the bundle: each "
                    "submission's hidden seeds are then derived from its Gradescope users (keep the zip private)");
  command->add_option("--course-secret-file", options.course_secret_file,
                      "With --per-student-seeds: the course secret, in a file")
      ->needs("--per-student-seeds");
  return command;
}

int RunGradescopeCommand(const GradescopeOptions& options, std::ostream& out, std::ostream& err) {
  const FolderOrError found = FindAssignmentFolder(options.assignment);
  if (!found.ok()) {
    fmt::print(err, "syrof gradescope: {}\n", found.error->ToString());
    return kBadInput;
  }
  const std::string& folder = *found.folder;
  const grader::assignment::LoadResult loaded = grader::assignment::LoadAssignmentFile(folder);
  if (!loaded.ok()) {
    fmt::print(err, "syrof gradescope: the assignment does not load: {}\n", loaded.error->ToString());
    return kBadInput;
  }
  std::string prefix = options.prefix;
  if (prefix.empty()) {
    const FolderOrError beside = PrefixBesideBuild(RunningBuildTree());
    if (!beside.ok()) {
      fmt::print(err, "syrof gradescope: {}\n", beside.error->ToString());
      return kBadInput;
    }
    prefix = *beside.folder;
  }
  std::optional<std::string> course_secret;
  if (options.per_student_seeds) {
    grader::CourseSecretOrError secret = CourseSecret(options);
    if (!secret.ok()) {
      fmt::print(err, "syrof gradescope: {}\n", secret.error->ToString());
      return kBadInput;
    }
    course_secret = std::move(secret.secret);
  }
  const int deadline_s = options.deadline_s > 0 ? options.deadline_s : grader::report::kDefaultDeadlineS;
  const grader::report::BundleResult bundle = grader::report::GradescopeBundle(folder, prefix, course_secret, deadline_s);
  if (!bundle.ok()) {
    fmt::print(err, "syrof gradescope: {}\n", bundle.error->ToString());
    return kBadInput;
  }
  if (const std::optional<lab::Error> problem = grader::report::WriteBundleZip(*bundle.bundle, options.output)) {
    fmt::print(err, "syrof gradescope: {}\n", problem->ToString());
    return kInternalError;
  }
  std::error_code ignored;
  const auto bytes = fs::file_size(options.output, ignored);
  const grader::assignment::Assignment& assignment = *loaded.assignment;
  fmt::print(out, "syrof gradescope: wrote {} ({} files, {:.1f} MiB)\n", options.output,
             bundle.bundle->files.size(), static_cast<double>(bytes) / (1024.0 * 1024.0));
  fmt::print(out, "  {:<15} installs a compiler, CMake and make where the image lacks them, then checks that "
                  "syrof runs\n", "setup.sh");
  fmt::print(out, "  {:<15} grades /autograder/submission into /autograder/results/results.json, kept valid "
                  "after each test; starts no test after {} s (set Gradescope's timeout above that)\n",
             "run_autograder", deadline_s);
  fmt::print(out, "  {:<15} SyROF {} from {}: its programs and the libraries they need but glibc and the C++ "
                  "runtime (for Ubuntu 22.04, glibc 2.35 and up)\n",
             std::string(grader::report::kSyrofFolder) + "/", SYROF_VERSION, prefix);
  fmt::print(out, "  {:<15} '{}': {} public and {} hidden tests (its reference/ and broken/ left out)\n",
             "assignment/", assignment.title, Tests(assignment.public_runs), Tests(assignment.hidden_runs));
  if (course_secret) {
    fmt::print(out, "  {:<15} the course secret: hidden seeds per student, from Gradescope's submission metadata; "
                    "keep this zip private\n",
               grader::report::kCourseSecretFile);
  }
  fmt::print(out,
             "Upload it as the assignment's autograder on Gradescope (Configure Autograder, Zip file upload); "
             "docs/grading.md, \"Publishing to Gradescope\", says how\n");
  return kOk;
}

}  // namespace syrof::cli
