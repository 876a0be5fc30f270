#include "new_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <array>
#include <cstdlib>
#include <fstream>
#include <string_view>
#include <system_error>
#include <vector>

#include "new_project_files.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;

constexpr size_t kMaxNameLength = 64;

// Target names CMake keeps for itself (a project target may not take them).
constexpr std::array<std::string_view, 10> kReservedNames = {
    "all", "clean", "help", "install", "test", "package", "package_source", "edit_cache", "rebuild_cache",
    "list_install_components"};

std::string TemplateText(std::string_view name) {
  for (const TemplateFile& file : NewProjectTemplates()) {
    if (name == file.name) return file.text;
  }
  return {};
}

void ReplaceAll(std::string& text, std::string_view from, std::string_view to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
}

// `path` as a CMake quoted argument.
std::string CMakeQuoted(const std::string& path) {
  std::string quoted = "\"";
  for (char c : path) {
    if (c == '\\' || c == '"' || c == '$') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

// "syrof" when the folder of `executable` is on PATH, else its path: what
// the student types to run it.
std::string CommandName(const fs::path& executable) {
  const char* path = std::getenv("PATH");
  std::error_code error;
  const fs::path folder = fs::weakly_canonical(executable.parent_path(), error);
  std::string_view rest = path == nullptr ? "" : path;
  while (!rest.empty()) {
    const size_t colon = rest.find(':');
    const std::string entry(rest.substr(0, colon));
    rest = colon == std::string_view::npos ? "" : rest.substr(colon + 1);
    if (!entry.empty() && fs::weakly_canonical(entry, error) == folder) return "syrof";
  }
  return executable.string();
}

fs::path RunningExecutable() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? fs::path() : self;
}

}  // namespace

CLI::App* SetupNewCommand(CLI::App& app, NewOptions& options) {
  CLI::App* command = app.add_subcommand(
      "new", "Write a project for your own app: a starter app, CMakeLists.txt, a scenario and a README");
  command->add_option("name", options.name, "The app's name (a C identifier); the library is lib<name>.so")
      ->required();
  command->add_option("--lang", options.lang, "The starter app's language")
      ->check(CLI::IsMember({"c", "cpp"}))
      ->capture_default_str();
  command->add_option("--dir", options.dir, "Folder to write (default: ./<name>); must not exist or be empty");
  return command;
}

std::string SyROFPackageDir(const fs::path& executable) {
  const fs::path prefix = executable.parent_path().parent_path();
  std::error_code error;
  if (fs::is_regular_file(prefix / "SyROFConfig.cmake", error)) return fs::weakly_canonical(prefix, error).string();
  const fs::path installed = prefix / "lib" / "cmake" / "SyROF";
  if (fs::is_regular_file(installed / "SyROFConfig.cmake", error)) {
    return fs::weakly_canonical(installed, error).string();
  }
  return {};
}

std::optional<lab::Error> CheckProjectName(const std::string& name) {
  auto refused = [](std::string message) { return lab::Error{.where = "", .message = std::move(message)}; };
  if (name.empty()) return refused("the name is empty");
  if (name.size() > kMaxNameLength) {
    return refused(fmt::format("'{}' is {} characters long; at most {}", name, name.size(), kMaxNameLength));
  }
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  if (!letter(name.front())) {
    return refused(
        fmt::format("'{}' must start with a letter or '_' (it names a C library and a CMake target)", name));
  }
  for (char c : name) {
    if (!letter(c) && !digit(c)) {
      return refused(fmt::format(
          "'{}' may hold only letters, digits and '_', not '{}' (it names a C library and a CMake target)", name, c));
    }
  }
  for (std::string_view reserved : kReservedNames) {
    if (name == reserved) return refused(fmt::format("'{}' is a target name CMake reserves; choose another", name));
  }
  return std::nullopt;
}

int RunNewCommand(const NewOptions& options, std::ostream& out, std::ostream& err) {
  if (const std::optional<lab::Error> problem = CheckProjectName(options.name)) {
    fmt::print(err, "syrof new: bad app name: {}\n", problem->ToString());
    return 2;
  }
  const bool cpp = options.lang == "cpp";
  if (!cpp && options.lang != "c") {
    fmt::print(err, "syrof new: --lang must be c or cpp, not '{}'\n", options.lang);
    return 2;
  }
  const fs::path dir = options.dir.empty() ? fs::path(options.name) : fs::path(options.dir);
  std::error_code error;
  if (fs::exists(dir, error)) {
    if (!fs::is_directory(dir, error)) {
      fmt::print(err, "syrof new: {} exists and is not a folder; choose another --dir\n", dir.string());
      return 2;
    }
    if (!fs::is_empty(dir, error)) {
      fmt::print(err, "syrof new: {} exists and is not empty; nothing was written (choose another name or --dir)\n",
                 dir.string());
      return 2;
    }
  }

  const fs::path executable = RunningExecutable();
  const std::string package_dir = options.package_dir ? *options.package_dir : SyROFPackageDir(executable);
  const std::string source = cpp ? "app.cpp" : "app.c";
  auto fill = [&](std::string text) {
    ReplaceAll(text, "{{NAME}}", options.name);
    ReplaceAll(text, "{{SOURCE}}", source);
    ReplaceAll(text, "{{LANGUAGE}}", cpp ? "CXX" : "C");
    ReplaceAll(text, "{{HINTS}}", package_dir.empty() ? "" : " HINTS " + CMakeQuoted(package_dir));
    ReplaceAll(text, "{{HINT_NOTE}}",
               package_dir.empty() ? "" : "\n# The hint is where `syrof new` found SyROF, for a shell without it on PATH.");
    return text;
  };
  const std::vector<std::pair<std::string, std::string>> files = {
      {source, fill(TemplateText(source))},
      {"CMakeLists.txt", fill(TemplateText("CMakeLists.txt.in"))},
      {"scenario.yaml", fill(TemplateText("scenario.yaml.in"))},
      {"README.md", fill(TemplateText("README.md.in"))},
      {".gitignore", fill(TemplateText("gitignore.in"))},
  };
  fs::create_directories(dir, error);
  if (error) {
    fmt::print(err, "syrof new: cannot create {}: {}\n", dir.string(), error.message());
    return 1;
  }
  for (const auto& [name, text] : files) {
    std::ofstream file(dir / name, std::ios::binary | std::ios::trunc);
    file << text;
    if (!file.flush()) {
      fmt::print(err, "syrof new: cannot write {}\n", (dir / name).string());
      return 1;
    }
  }

  fmt::print(out, "syrof new: wrote {}/ ({} app): {}, CMakeLists.txt, scenario.yaml, README.md, .gitignore\n",
             dir.string(), cpp ? "C++" : "C", source);
  if (package_dir.empty()) {
    fmt::print(out,
               "  note: no SyROF CMake package beside this syrof ({}); configure with "
               "-DSyROF_DIR=<the folder holding SyROFConfig.cmake>\n",
               executable.string());
  } else {
    fmt::print(out, "  SyROF's CMake package: {}\n", package_dir);
  }
  fmt::print(out, "Next:\n  cd {}\n  cmake -S . -B build && cmake --build build\n  {} run scenario.yaml\n",
             dir.string(), CommandName(executable));
  return 0;
}

}  // namespace syrof::cli
