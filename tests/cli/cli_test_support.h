// What the CLI's tests share: reading an output file whole, a fresh folder
// under the temporary directory, a command's outcome, and a subcommand's
// arguments parsed as main() parses them.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "usage.h"

namespace syrof::cli::testing {

/// The bytes of `path` (empty if it cannot be read).
inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// `<temp>/<prefix><name>`, removed with everything in it; not created.
inline std::filesystem::path FreshDir(const std::string& prefix, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / (prefix + name);
  std::filesystem::remove_all(dir);
  return dir;
}

/// A command's exit status and what it printed.
struct Outcome {
  int status;
  std::string out;
  std::string err;
};

/// `syrof SUBCOMMAND ARGUMENTS...` parsed as main() parses it: `setup(app,
/// options)` declares the subcommand, then `run(options, out, err)` runs it,
/// or a parse error is reported as main() reports it.
template <typename Options, typename Setup, typename Run>
Outcome ParseAndRun(const std::string& subcommand, std::vector<std::string> arguments, Setup setup, Run run) {
  CLI::App app{"syrof"};
  app.require_subcommand(1);
  Options options;
  setup(app, options);
  arguments.insert(arguments.begin(), subcommand);
  std::vector<const char*> argv = {"syrof"};
  for (const std::string& argument : arguments) argv.push_back(argument.c_str());
  std::ostringstream out;
  std::ostringstream err;
  int status = 0;
  try {
    app.parse(static_cast<int>(argv.size()), const_cast<char**>(argv.data()));
    status = run(options, out, err);
  } catch (const CLI::ParseError& error) {
    status = ReportParseError(app, error, out, err);
  }
  return {status, out.str(), err.str()};
}

}  // namespace syrof::cli::testing
