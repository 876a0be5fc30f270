// Reading a scenario from a file or a string: the size cap, the text
// checks, the YAML tree, then the schema.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "diagnostics.h"
#include "syrof/lab/scenario/yaml/document.h"
#include "schema.h"
#include "syrof/lab/scenario/scenario.h"
#include "text_checks.h"
#include "yaml_tree.h"

namespace syrof::lab::scenario {
namespace {

// The stem of `file` when it makes a valid scenario name, else "scenario".
std::string DefaultName(const std::string& file) {
  const std::string stem = std::filesystem::path(file).stem().string();
  for (char c : stem) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok) return "scenario";
  }
  return stem.empty() || stem.size() > 64 ? "scenario" : stem;
}

LoadResult Finish(Diagnostics& diagnostics, std::optional<Scenario> scenario) {
  LoadResult result;
  if (diagnostics.failed()) {
    result.error = diagnostics.error();
  } else {
    result.scenario = std::move(scenario);
  }
  return result;
}

LoadResult Load(const std::string& text, const std::string& file, const std::string& source,
                const Overrides& overrides) {
  Diagnostics diagnostics(file);
  YamlNode root;
  if (!CheckScenarioText(text, diagnostics) || !ReadYamlDocument(text, root, diagnostics)) {
    return Finish(diagnostics, std::nullopt);
  }
  Scenario scenario;
  scenario.name = DefaultName(file);
  scenario.source = source;
  if (!ReadScenario(root, overrides, scenario, diagnostics)) return Finish(diagnostics, std::nullopt);
  return Finish(diagnostics, std::move(scenario));
}

// The file's text, at most kMaxScenarioBytes; false with the error recorded.
// `what` names the file in messages ("scenario").
bool ReadCappedFile(const std::string& path, const std::string& what, std::string& text, Diagnostics& diagnostics) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    return diagnostics.Fail(0, 0, "is a directory, not a " + what + " file");
  }
  // Opened without blocking, then read blocking: a named pipe nobody writes
  // to would otherwise block the open forever (it now reads as empty), while
  // a pipe with a writer (`syrof run <(generate)`) still reads whole.
  const int descriptor = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0) return diagnostics.Fail(0, 0, std::string("cannot open: ") + std::strerror(errno));
  const int flags = fcntl(descriptor, F_GETFL);
  if (flags < 0 || fcntl(descriptor, F_SETFL, flags & ~O_NONBLOCK) < 0) {
    const int failure = errno;
    close(descriptor);
    return diagnostics.Fail(0, 0, std::string("cannot open: ") + std::strerror(failure));
  }
  // Read at most one byte past the cap: a larger file is refused without
  // being read whole (it may be a device or a pipe that never ends).
  text.assign(kMaxScenarioBytes + 1, '\0');
  size_t length = 0;
  while (length < text.size()) {
    const ssize_t got = read(descriptor, text.data() + length, text.size() - length);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      close(descriptor);
      return diagnostics.Fail(0, 0, "read error");
    }
    if (got == 0) break;
    length += static_cast<size_t>(got);
  }
  close(descriptor);
  text.resize(length);
  if (text.size() > kMaxScenarioBytes) {
    const auto size = std::filesystem::file_size(path, error);
    const std::string size_text = error ? "more than " + std::to_string(kMaxScenarioBytes) : std::to_string(size);
    return diagnostics.Fail(0, 0, "the " + what + " is " + size_text + " bytes; the limit is " +
                                      std::to_string(kMaxScenarioBytes) + " bytes");
  }
  return true;
}

}  // namespace

bool ReadYamlFile(const std::string& path, YamlNode& root, Diagnostics& diagnostics) {
  std::string text;
  return ReadCappedFile(path, "YAML", text, diagnostics) && CheckScenarioText(text, diagnostics) &&
         ReadYamlDocument(text, root, diagnostics);
}

LoadResult LoadScenarioFile(const std::string& path, const Overrides& overrides) {
  Diagnostics diagnostics(path);
  std::string text;
  if (!ReadCappedFile(path, "scenario", text, diagnostics)) return Finish(diagnostics, std::nullopt);
  return Load(text, path, path, overrides);
}

LoadResult LoadScenarioText(const std::string& text, const std::string& file, const Overrides& overrides) {
  return Load(text, file, "", overrides);
}

}  // namespace syrof::lab::scenario
