// What the CLI's tests share: reading an output file whole, a fresh folder
// under the temporary directory, and a command's outcome.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace syrof::cli::testing
