// The scenario loader's YAML machinery for other file formats of the lab's
// family (assignment files, grader/assignment): the same size cap, text
// checks, event-built tree with places, typed readers and nearest-key
// suggestions, so every YAML file a user writes is held to one standard
// (docs/scenarios.md, "The YAML accepted").
#pragma once

#include <string>

#include "syrof/lab/message/message_format.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/scenario/yaml/diagnostics.h"
#include "syrof/lab/scenario/yaml/value_reader.h"
#include "syrof/lab/scenario/yaml/yaml_tree.h"

namespace syrof::lab::scenario {

/// Reads `path` (at most kMaxScenarioBytes, UTF-8, no tab indentation, one
/// document, bounded nesting) into `root`; `diagnostics` names `path` in
/// errors (construct it with the path). False with the first error recorded.
bool ReadYamlFile(const std::string& path, YamlNode& root, Diagnostics& diagnostics);

/// Reads a `goal:` list at `node` (whose key path is `path`, e.g.
/// "goal" or "scenarios.public[0].goal") against `scenario` (its arena,
/// robots and duration) into `checks`, with the scenario files' rules
/// (docs/scenarios.md, "goal").
bool ReadGoalChecks(const YamlNode& node, const std::string& path, const Scenario& scenario,
                    std::vector<goals::GoalCheck>& checks, Diagnostics& diagnostics);

/// Reads a `message:` declaration at `node` (key path `path`): `none`, or
/// { length, fields: [ { name, type } ... ] } whose fields' sizes add up to
/// `length` (1 to 9 bytes; docs/grading.md, "The assignment file").
bool ReadMessageFormat(const YamlNode& node, const std::string& path, message::MessageFormat& format,
                       Diagnostics& diagnostics);

}  // namespace syrof::lab::scenario
