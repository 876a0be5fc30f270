// `syrof assignment new NAME [--dir PARENT]`: writes PARENT/NAME, a skeleton
// assignment that `syrof assignment check` passes as written: the task is
// "spread on a circle", the reference is the app `syrof new` writes (the
// same template), the starter holds still, and one broken variant
// (off_by_one) spaces the points for one robot too few. Its templates are
// cli/new_assignment/ (and cli/new_project/ for the reference), built into
// the command.
#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "assignment_command.h"
#include "exit_status.h"
#include "new_command.h"
#include "new_project_files.h"
#include "syrof/lab/base/error.h"

namespace syrof::cli {
// A named namespace: the subcommands compile as one unity translation unit.
namespace assignment_new {

namespace fs = std::filesystem;

std::string FindTemplate(std::span<const TemplateFile> files, std::string_view name) {
  for (const TemplateFile& file : files) {
    if (name == file.name) return file.text;
  }
  return {};
}

// Fills the placeholders of the templates (cli/new_project_files.h). The
// projects carry no hint, as the shipped assignments' do not: students get
// them, and SyROF is found beneath the `syrof` on their PATH.
std::string Fill(std::string text, const std::string& name) {
  const std::pair<std::string_view, std::string> values[] = {{"{{NAME}}", name},
                                                             {"{{SOURCE}}", name + ".c"},
                                                             {"{{LANGUAGE}}", "C"},
                                                             {"{{HINTS}}", ""},
                                                             {"{{HINT_NOTE}}", ""}};
  for (const auto& [from, to] : values) {
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
  }
  return text;
}

// The skeleton's files: path under the assignment's folder, and text.
std::vector<std::pair<std::string, std::string>> SkeletonFiles(const std::string& name) {
  const auto assignment = [&](std::string_view file) { return Fill(FindTemplate(NewAssignmentTemplates(), file), name); };
  const auto project = [&](std::string_view file) { return Fill(FindTemplate(NewProjectTemplates(), file), name); };
  const std::string source = name + ".c";
  return {
      {"assignment.yaml", assignment("assignment.yaml.in")},
      {"README.md", assignment("README.md.in")},
      {"scenarios/spread_6.yaml", assignment("spread_6.yaml.in")},
      {"hidden/spread_8_loss.yaml", assignment("spread_8_loss.yaml.in")},
      {"search/spread_3_vote1.yaml", assignment("spread_3_vote1.yaml.in")},
      {"search/spread_3_ssync.yaml", assignment("spread_3_ssync.yaml.in")},
      {"reference/CMakeLists.txt", project("CMakeLists.txt.in")},
      {"reference/" + source, project("app.c")},
      {"reference/expected.yaml", assignment("reference_expected.yaml")},
      {"starter/CMakeLists.txt", project("CMakeLists.txt.in")},
      {"starter/" + source, assignment("starter.c")},
      {"starter/expected.yaml", assignment("starter_expected.yaml")},
      {"broken/off_by_one/NOTE.md", assignment("off_by_one_NOTE.md")},
      {"broken/off_by_one/expected.yaml", assignment("off_by_one_expected.yaml")},
      {"broken/off_by_one/mistake.patch", assignment("off_by_one_mistake.patch.in")},
  };
}

// Writes `files` under `dir`; what failed, if anything.
std::optional<lab::Error> WriteFiles(const fs::path& dir,
                                     const std::vector<std::pair<std::string, std::string>>& files) {
  for (const auto& [path, text] : files) {
    std::error_code error;
    fs::create_directories((dir / path).parent_path(), error);
    if (error) {
      return lab::Error{.where = "", .message = fmt::format("cannot create {}: {}", (dir / path).parent_path().string(),
                                                            error.message())};
    }
    std::ofstream file(dir / path, std::ios::binary | std::ios::trunc);
    file << text;
    if (!file.flush()) return lab::Error{.where = "", .message = fmt::format("cannot write {}", (dir / path).string())};
  }
  return std::nullopt;
}

}  // namespace assignment_new

int RunAssignmentNew(const AssignmentNewOptions& options, std::ostream& out, std::ostream& err) {
  namespace fs = std::filesystem;
  const std::string& name = options.name;
  if (name.find('/') != std::string::npos || name.find("..") != std::string::npos) {
    fmt::print(err, "syrof assignment new: '{}' is a path, not a name; give the folder to write in with --dir\n",
               name);
    return kBadInput;
  }
  if (const std::optional<lab::Error> problem = CheckProjectName(name)) {
    fmt::print(err, "syrof assignment new: bad assignment name: {}\n", problem->ToString());
    return kBadInput;
  }
  const fs::path dir = options.parent == "." ? fs::path(name) : fs::path(options.parent) / name;
  std::error_code error;
  if (fs::exists(fs::symlink_status(dir, error))) {
    fmt::print(err, "syrof assignment new: {} exists; nothing was written (choose another name or --dir)\n",
               dir.string());
    return kBadInput;
  }
  fs::create_directories(options.parent, error);
  if (error) {
    fmt::print(err, "syrof assignment new: cannot create {}: {}\n", options.parent, error.message());
    return kInternalError;
  }
  // Written beside it, then renamed: a failure leaves no half skeleton.
  const fs::path partial = fs::path(options.parent) / fmt::format(".{}.partial-{}", name, getpid());
  fs::remove_all(partial, error);
  std::optional<lab::Error> problem = assignment_new::WriteFiles(partial, assignment_new::SkeletonFiles(name));
  if (!problem) {
    fs::rename(partial, dir, error);
    if (error) {
      problem = lab::Error{.where = "", .message = fmt::format("cannot rename {} to {}: {}", partial.string(),
                                                               dir.string(), error.message())};
    }
  }
  if (problem) {
    fs::remove_all(partial, error);
    fmt::print(err, "syrof assignment new: {}\n", problem->ToString());
    return kInternalError;
  }
  fmt::print(out,
             "syrof assignment new: wrote {0}/: assignment.yaml, README.md, scenarios/spread_6.yaml, "
             "hidden/spread_8_loss.yaml, search/spread_3_vote1.yaml and search/spread_3_ssync.yaml (search tests', off), "
             "reference/, starter/, "
             "broken/off_by_one/\n"
             "The skeleton's task: spread on a circle; its reference is the app `syrof new` writes, its starter "
             "holds still, and broken/off_by_one spaces the points for one robot too few.\n"
             "Next: check it as written (every subject PASS), then make it yours and check again:\n"
             "  syrof assignment check {0}\n",
             dir.string());
  return kOk;
}

}  // namespace syrof::cli
