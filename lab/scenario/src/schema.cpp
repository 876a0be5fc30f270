// The top level of a scenario: which sections exist, which are required,
// the order they are read in, and the command-line overrides.
#include "schema.h"

#include <filesystem>
#include <limits>
#include <string_view>

#include "syrof/lab/scenario/yaml/document.h"
#include "value_reader.h"

namespace syrof::lab::scenario {

bool IsValidName(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameLength) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

const YamlNode& KeyNode(const YamlNode& map, std::string_view key) {
  for (const YamlNode& node : map.keys) {
    if (node.scalar == key) return node;
  }
  return map;
}

namespace {

bool CheckOverrides(const Overrides& overrides, Diagnostics& diagnostics) {
  if (overrides.robots && (*overrides.robots < 1 || *overrides.robots > MaxRobots())) {
    return diagnostics.Fail(0, 0, "robots override must be in [1, " + std::to_string(MaxRobots()) + "], got " +
                                      std::to_string(*overrides.robots));
  }
  if (overrides.duration_s && !(*overrides.duration_s > 0 && *overrides.duration_s <= kMaxDurationS)) {
    return diagnostics.Fail(0, 0, "duration override must be in (0, " + FormatNumber(kMaxDurationS) + "] seconds, got " +
                                      FormatNumber(*overrides.duration_s));
  }
  return true;
}

// The folder a library path in the file is relative to: the file's own
// folder, or the working directory ("") for a scenario read from a string.
std::string LibraryBaseDir(const Scenario& scenario) {
  if (scenario.source.empty()) return {};
  return std::filesystem::path(scenario.source).parent_path().string();
}

}  // namespace

bool ReadRobotId(const YamlNode& node, const std::string& path, const Scenario& scenario, uint16_t& id,
                 Diagnostics& diagnostics) {
  int64_t value = 0;
  constexpr int64_t kLowest = std::numeric_limits<int64_t>::min();
  constexpr int64_t kHighest = std::numeric_limits<int64_t>::max();
  if (!ReadInteger(node, path, kLowest, kHighest, value, diagnostics)) return false;
  const auto count = static_cast<int64_t>(scenario.robots.size());
  if (value < 0 || value >= count) {
    return FailAt(node, path,
                  "robot id " + std::to_string(value) + " is out of range: the scenario has " + std::to_string(count) +
                      (count == 1 ? " robot (id 0)" : " robots (ids 0.." + std::to_string(count - 1) + ")"),
                  diagnostics);
  }
  id = static_cast<uint16_t>(value);
  return true;
}

bool ReadScenario(const YamlNode& root, const Overrides& overrides, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"name",    "seed",   "arena",  "kinds", "robots",
                                               "timing",  "sensors", "channel", "clocks", "faults",
                                               "inputs",  "app",    "safety", "goal",
                                               "message", "activation"};
  if (root.is_null()) {
    return diagnostics.Fail(0, 0, "the scenario is empty; it needs at least 'robots' and 'app'");
  }
  if (!root.is_map()) {
    return diagnostics.Fail(root.line, root.column,
                            "the top level must be a map of keys (robots, app, ...), got " +
                                std::string(root.is_sequence() ? "a list" : "'" + root.scalar + "'"));
  }
  if (!CheckKeys(root, "", kKeys, diagnostics) || !RequireKey(root, "", "robots", diagnostics) ||
      !RequireKey(root, "", "app", diagnostics) || !CheckOverrides(overrides, diagnostics)) {
    return false;
  }
  if (const YamlNode* name = root.Find("name")) {
    if (!ReadString(*name, "name", scenario.name, diagnostics)) return false;
    if (!IsValidName(scenario.name)) {
      return FailAt(*name, "name",
                    "must be 1 to " + std::to_string(kMaxNameLength) +
                        " letters, digits, '_', '-' or '.', got '" + name->scalar + "'",
                    diagnostics);
    }
  }
  if (const YamlNode* seed = root.Find("seed")) {
    if (!ReadUnsigned64(*seed, "seed", scenario.seed, diagnostics)) return false;
  }
  if (overrides.seed) scenario.seed = *overrides.seed;

  if (!ReadArena(root.Find("arena"), scenario, diagnostics) || !ReadKinds(root.Find("kinds"), scenario, diagnostics) ||
      !ReadTiming(root.Find("timing"), overrides, scenario.timing, diagnostics) ||
      !ReadRobots(*root.Find("robots"), overrides, scenario, diagnostics) ||
      !ReadSensors(root.Find("sensors"), scenario, diagnostics) ||
      !ReadChannel(root.Find("channel"), scenario, diagnostics) ||
      !ReadClocks(root.Find("clocks"), scenario, diagnostics) ||
      !ReadFaults(root.Find("faults"), scenario, diagnostics) ||
      !ReadActivation(root.Find("activation"), scenario, diagnostics) ||
      !ReadInputs(root.Find("inputs"), scenario, diagnostics) ||
      !ReadGoal(root.Find("goal"), scenario, diagnostics) ||
      !ReadApp(*root.Find("app"), apps::BuiltinApps(), LibraryBaseDir(scenario), scenario.app, diagnostics)) {
    return false;
  }
  if (const YamlNode* message = root.Find("message")) {
    message::MessageFormat format;
    if (!ReadMessageFormat(*message, "message", format, diagnostics)) return false;
    scenario.message = std::move(format);
  }
  if (const YamlNode* safety = root.Find("safety")) {
    static constexpr std::string_view kSwitch[] = {"on", "off"};
    size_t choice = 0;
    if (!ReadChoice(*safety, "safety", kSwitch, choice, diagnostics)) return false;
    scenario.safety = choice == 0;
  }
  return !overrides.app || OverrideApp(*overrides.app, apps::BuiltinApps(), scenario.app, diagnostics);
}

}  // namespace syrof::lab::scenario
