// The scenario schema: one reader per top-level section, each filling its
// part of a Scenario from the YAML tree and checking every rule
// docs/scenarios.md states for it. The sections are read in dependency
// order (ReadScenario): what later checks need (the arena, the kinds, the
// duration, the robot count) comes first.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "diagnostics.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/scenario/scenario.h"
#include "yaml_tree.h"

namespace syrof::lab::scenario {

// The longest name a scenario, a goal check or an input may have.
inline constexpr size_t kMaxNameLength = 64;

// Names end up in file names and reports: 1 to kMaxNameLength letters,
// digits, '_', '-' and '.'.
bool IsValidName(const std::string& name);

// The key node of `key` in `map` (which holds it), else `map` itself.
const YamlNode& KeyNode(const YamlNode& map, std::string_view key);

// Reads the whole document into `scenario` (which holds the defaults and
// the name), applying `overrides`.
bool ReadScenario(const YamlNode& root, const Overrides& overrides, Scenario& scenario, Diagnostics& diagnostics);

// The sections. `node` is nullptr when the section is absent (defaults stay).
bool ReadArena(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);
bool ReadKinds(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);
bool ReadTiming(const YamlNode* node, const Overrides& overrides, TimingSpec& timing, Diagnostics& diagnostics);
// Needs the arena, the kinds and the seed; places the robots.
bool ReadRobots(const YamlNode& node, const Overrides& overrides, Scenario& scenario, Diagnostics& diagnostics);
bool ReadSensors(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);
// Needs the robots and the timing.
bool ReadChannel(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);
// Needs the robots, the timing and the seed.
bool ReadClocks(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);
// Needs the robots and the timing; marks joining robots absent at start.
bool ReadFaults(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);

// Needs the robots and the timing (the run's epochs).
bool ReadActivation(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);

// Needs the arena, the robots and the timing.
bool ReadGoal(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);

// `app:` against a catalog of built-in apps (the real one is
// apps::BuiltinApps(); tests pass their own). A library's relative path is
// resolved against `base_dir` (the scenario file's folder; "" for the
// working directory) and must be a file.
bool ReadApp(const YamlNode& node, std::span<const apps::BuiltinAppInfo> catalog, const std::string& base_dir,
             AppSpec& app, Diagnostics& diagnostics);
// An app given on the command line: "builtin:NAME" or a library's path
// (relative to the working directory). Keeps the file's parameters when it
// names the same built-in app, else drops them; keeps the file's library
// limits when a library replaces a library.
bool OverrideApp(const std::string& name, std::span<const apps::BuiltinAppInfo> catalog, AppSpec& app,
                 Diagnostics& diagnostics);

// `inputs:`, each robot's private values (docs/scenarios.md, "Private
// inputs"). Needs the robots and the seed: drawn values come from it.
bool ReadInputs(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics);

// A name an app reads a value by (a library's parameter, a private input):
// 1 to SYROF_APP_MAX_PARAMETER_NAME_LENGTH letters, digits and '_', not
// starting with a digit. `what` names the kind in the message ("parameter").
bool CheckAppValueName(const YamlNode& key, const std::string& path, const char* what, Diagnostics& diagnostics);

// "robot id 9 is out of range: the scenario has 6 robots (ids 0..5)" when
// `value` is not a robot id of `scenario`.
bool ReadRobotId(const YamlNode& node, const std::string& path, const Scenario& scenario, uint16_t& id,
                 Diagnostics& diagnostics);

}  // namespace syrof::lab::scenario
