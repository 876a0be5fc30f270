// A YAML document as a small tree of maps, lists and scalars, each node with
// its place in the file, built from yaml-cpp's event API.
//
// Only the subset a scenario needs is accepted: no anchors, aliases or
// explicit tags, scalar map keys without duplicates, nesting at most
// kMaxScenarioDepth deep, one document. yaml-cpp's node API (YAML::Load,
// LoadAll) is not used: LoadAll can loop forever on some inputs in Debian's
// 0.7.0, and a handler that sees every event can stop the parser at the
// first problem.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/lab/scenario/yaml/diagnostics.h"

namespace syrof::lab::scenario {

struct YamlNode {
  enum class Kind : uint8_t { kNull, kScalar, kSequence, kMap };

  Kind kind = Kind::kNull;
  int line = 0;    // 1-based
  int column = 0;  // 1-based
  std::string scalar;  // kScalar: the text, unquoted
  bool quoted = false;  // kScalar: written in quotes (so never a number)
  // kMap: keys[i] (scalars) maps to values[i], in file order.
  // kSequence: the elements are in values; keys is empty.
  std::vector<YamlNode> keys;
  std::vector<YamlNode> values;

  bool is_map() const { return kind == Kind::kMap; }
  bool is_sequence() const { return kind == Kind::kSequence; }
  bool is_scalar() const { return kind == Kind::kScalar; }
  bool is_null() const { return kind == Kind::kNull; }

  // kMap: the value under `key`, or nullptr.
  const YamlNode* Find(std::string_view key) const;
};

// Parses the first document of `text` (which CheckScenarioText() accepted).
// On success `root` is the document (kNull for an empty one); otherwise
// the error is recorded in `diagnostics` and false returned. Stops at the
// node after `max_nodes` (maps, lists and scalars, keys and the root
// included): a node costs a hundred bytes or more, so a file allowed more
// bytes than a scenario (a scripted channel's lost_file) bounds its tree.
bool ReadYamlDocument(const std::string& text, YamlNode& root, Diagnostics& diagnostics,
                      size_t max_nodes = std::numeric_limits<size_t>::max());

}  // namespace syrof::lab::scenario
