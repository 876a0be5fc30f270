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

// The build tree the running syrof is in (build/bin/syrof -> build).
fs::path RunningBuildTree() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) return {};
  return self.parent_path().parent_path();
}

}  // namespace

std::string FindAssignmentFolder(const std::string& name_or_path, std::string& error) {
  std::error_code ignored;
  const fs::path given(name_or_path);
  if (fs::is_regular_file(given, ignored) && given.filename() == "assignment.yaml") {
    return given.parent_path().empty() ? "." : given.parent_path().string();
  }
  if (fs::is_directory(given, ignored)) {
    if (fs::is_regular_file(given / "assignment.yaml", ignored)) return given.string();
    error = fmt::format("{} holds no assignment.yaml", name_or_path);
    return {};
  }
  const bool plain_name = !name_or_path.empty() && name_or_path.find('/') == std::string::npos &&
                          name_or_path != "." && name_or_path != "..";
  if (plain_name) {
    const fs::path named = fs::path("assignments") / name_or_path;
    if (fs::is_regular_file(named / "assignment.yaml", ignored)) return named.string();
    error = fmt::format("no assignment '{}': neither a folder nor ./{}/assignment.yaml", name_or_path,
                        named.string());
    return {};
  }
  error = fmt::format("no assignment at {}", name_or_path);
  return {};
}

std::string PackageBesideBuild(const fs::path& build_dir, std::string& error) {
  const std::string prefix = fmt::format("syrof_{}_", SYROF_VERSION);
  std::vector<std::string> found;
  std::error_code ignored;
  for (fs::directory_iterator it(build_dir, ignored); !ignored && it != fs::directory_iterator();
       it.increment(ignored)) {
    const std::string name = it->path().filename().string();
    if (name.starts_with(prefix) && name.ends_with(".deb") && it->is_regular_file(ignored)) {
      found.push_back(it->path().string());
    }
  }
  std::sort(found.begin(), found.end());
  if (found.size() == 1) return found.front();
  if (found.empty()) {
    error = fmt::format(
        "no Debian package of SyROF {0} beside this build ({1}/{2}<arch>.deb): make one with `make package` "
        "(or `cmake --build {1} --target package`), or give one with --deb FILE",
        SYROF_VERSION, build_dir.string(), prefix);
  } else {
    error = fmt::format("{} Debian packages of SyROF {} in {}; choose one with --deb FILE", found.size(),
                        SYROF_VERSION, build_dir.string());
  }
  return {};
}

CLI::App* SetupGradescopeCommand(CLI::App& app, GradescopeOptions& options) {
  CLI::App* command = app.add_subcommand(
      "gradescope",
      "Write an assignment's Gradescope autograder: a zip with setup.sh, run_autograder, SyROF's Debian package "
      "and the assignment (hidden sets included)");
  command->add_option("ASSIGNMENT", options.assignment,
                      "NAME (the folder assignments/NAME here) or PATH (an assignment's folder)")
      ->required();
  command->add_option("-o,--output", options.output, "The zip to write")->capture_default_str();
  command->add_option("--deb", options.deb,
                      "SyROF's Debian package to install on Gradescope (default: syrof_<version>_<arch>.deb "
                      "beside the running build tree, as `make package` writes it)");
  command->add_flag("--per-student-seeds", options.per_student_seeds,
                    "Put the course secret ($SYROF_COURSE_SECRET or --course-secret-file) in the bundle: each "
                    "submission's hidden seeds are then derived from its Gradescope users (keep the zip private)");
  command->add_option("--course-secret-file", options.course_secret_file,
                      "With --per-student-seeds: the course secret, in a file")
      ->needs("--per-student-seeds");
  return command;
}

int RunGradescopeCommand(const GradescopeOptions& options, std::ostream& out, std::ostream& err) {
  std::string error;
  const std::string folder = FindAssignmentFolder(options.assignment, error);
  if (folder.empty()) {
    fmt::print(err, "syrof gradescope: {}\n", error);
    return kBadInput;
  }
  const grader::assignment::LoadResult loaded = grader::assignment::LoadAssignmentFile(folder);
  if (!loaded.ok()) {
    fmt::print(err, "syrof gradescope: the assignment does not load: {}\n", loaded.error->ToString());
    return kBadInput;
  }
  std::string deb = options.deb;
  if (deb.empty()) {
    deb = PackageBesideBuild(RunningBuildTree(), error);
    if (deb.empty()) {
      fmt::print(err, "syrof gradescope: {}\n", error);
      return kBadInput;
    }
  }
  std::optional<std::string> course_secret;
  if (options.per_student_seeds) {
    if (!options.course_secret_file.empty()) {
      course_secret = grader::ReadCourseSecretFile(options.course_secret_file, error);
    } else if (const char* variable = std::getenv(grader::kCourseSecretVariable);
               variable != nullptr && *variable != '\0') {
      error = grader::CheckCourseSecret(variable);
      if (error.empty()) course_secret = std::string(variable);
      else error = std::string(grader::kCourseSecretVariable) + ": " + error;
    } else {
      error = fmt::format("--per-student-seeds needs the course secret: set {} or give --course-secret-file FILE",
                          grader::kCourseSecretVariable);
    }
    if (!course_secret) {
      fmt::print(err, "syrof gradescope: {}\n", error);
      return kBadInput;
    }
  }
  const grader::report::BundleResult bundle = grader::report::GradescopeBundle(folder, deb, course_secret);
  if (!bundle.ok()) {
    fmt::print(err, "syrof gradescope: {}\n", bundle.error);
    return kBadInput;
  }
  if (std::string problem = grader::report::WriteBundleZip(*bundle.bundle, options.output); !problem.empty()) {
    fmt::print(err, "syrof gradescope: {}\n", problem);
    return kInternalError;
  }
  std::error_code ignored;
  const auto bytes = fs::file_size(options.output, ignored);
  const grader::assignment::Assignment& assignment = *loaded.assignment;
  fmt::print(out, "syrof gradescope: wrote {} ({} files, {:.1f} MiB)\n", options.output,
             bundle.bundle->files.size(), static_cast<double>(bytes) / (1024.0 * 1024.0));
  fmt::print(out, "  {:<15} installs {} with apt-get, then checks that syrof runs\n", "setup.sh",
             fs::path(deb).filename().string());
  fmt::print(out, "  {:<15} grades /autograder/submission into /autograder/results/results.json\n",
             "run_autograder");
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
