// `syrof new NAME [--lang c|cpp] [--dir DIR]`: writes a project a student
// can build at once: a starter app (C or C++) that uses the queries, a
// CMakeLists.txt (find_package(SyROF) and syrof_add_app), a scenario that
// runs the library, a README with the three commands, and a .gitignore.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

#include "syrof/lab/base/error.h"

namespace syrof::cli {

struct NewOptions {
  std::string name;  ///< the app's name: a C identifier; the library is lib<name>.so
  std::string lang = "c";  ///< "c" or "cpp"
  std::string dir;   ///< where to write; default ./<name>. Must not exist or be empty.
  /// Not a command-line option: the folder holding SyROFConfig.cmake that
  /// the project's CMakeLists.txt names as a hint. Unset: found beside the
  /// running executable (SyROFPackageDir()).
  std::optional<std::string> package_dir;
};

/// Declares the subcommand's arguments on `app`.
CLI::App* SetupNewCommand(CLI::App& app, NewOptions& options);

/// Where SyROF's CMake package is for the `syrof` at `executable`: its
/// build tree (bin/.. holds SyROFConfig.cmake) or its installation
/// (bin/../lib/cmake/SyROF). Empty when neither holds it.
std::string SyROFPackageDir(const std::filesystem::path& executable);

/// Whether `name` can name an app project: 1 to 64 characters, a C
/// identifier (a letter or '_', then letters, digits, '_'), and not a
/// target name CMake reserves (all, test, install, ...). Nothing when it
/// can; else why not.
std::optional<lab::Error> CheckProjectName(const std::string& name);

/// Writes the project. Returns 0 on success, 2 when the name is bad or the
/// folder exists and is not empty (nothing written), 1 when writing failed.
/// Prints what it wrote and the next commands on `out`.
int RunNewCommand(const NewOptions& options, std::ostream& out, std::ostream& err);

}  // namespace syrof::cli
