// Typed reads from the YAML tree with the checks every key shares: the type,
// the range, and the key path and place of the offending value in errors.
//
// Every function records the first error in Diagnostics and returns false;
// on success it stores the value. Functions taking a map and a key leave the
// value untouched when the key is absent (the default stays).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "syrof/lab/scenario/yaml/diagnostics.h"
#include "syrof/lab/scenario/yaml/yaml_tree.h"

namespace syrof::lab::scenario {

// An interval of accepted numbers; an open end excludes its bound.
struct NumberRange {
  double min;
  double max;
  bool min_open = false;
  bool max_open = false;

  bool Contains(double value) const;
  // "[0, 1]", "(0, 1000]".
  std::string ToString() const;
};

// "x_m" under "robots.centre" is "robots.centre.x_m"; under "" just "x_m".
std::string JoinPath(const std::string& parent, std::string_view key);
// "robots.poses" and 3 give "robots.poses[3]".
std::string IndexPath(const std::string& parent, size_t index);

// Shortest decimal text that reads back as `value` ("0.1", "4", "1e-05").
std::string FormatNumber(double value);

// A computed number for messages, to 6 significant digits ("0.15", not
// "0.15000000000000002").
std::string FormatShort(double value);

// Records "`path`: `what`" at the node.
bool FailAt(const YamlNode& node, const std::string& path, const std::string& what, Diagnostics& diagnostics);

bool ExpectMap(const YamlNode& node, const std::string& path, Diagnostics& diagnostics);
bool ExpectList(const YamlNode& node, const std::string& path, Diagnostics& diagnostics);

// Fails at the first key of `map` not in `allowed`, suggesting the nearest
// allowed key or listing them all.
bool CheckKeys(const YamlNode& map, const std::string& path, std::span<const std::string_view> allowed,
               Diagnostics& diagnostics);

// Fails at the map when `key` is missing.
bool RequireKey(const YamlNode& map, const std::string& path, std::string_view key, Diagnostics& diagnostics);

// A finite number (a plain scalar in decimal or exponent notation) in range.
bool ReadNumber(const YamlNode& node, const std::string& path, const NumberRange& range, double& value,
                Diagnostics& diagnostics);
// A whole number (plain decimal digits, optional sign) in [min, max].
bool ReadInteger(const YamlNode& node, const std::string& path, int64_t min, int64_t max, int64_t& value,
                 Diagnostics& diagnostics);
// An unsigned 64-bit number written in decimal digits.
bool ReadUnsigned64(const YamlNode& node, const std::string& path, uint64_t& value, Diagnostics& diagnostics);
// A scalar's text (plain or quoted).
bool ReadString(const YamlNode& node, const std::string& path, std::string& value, Diagnostics& diagnostics);
// One of `choices`; `index` receives its position in the list.
bool ReadChoice(const YamlNode& node, const std::string& path, std::span<const std::string_view> choices,
                size_t& index, Diagnostics& diagnostics);

// The same under `key` of `map` (whose path is `map_path`); absent keys
// leave `value` as it is.
bool ReadNumberAt(const YamlNode& map, const std::string& map_path, std::string_view key, const NumberRange& range,
                  double& value, Diagnostics& diagnostics);
bool ReadIntegerAt(const YamlNode& map, const std::string& map_path, std::string_view key, int64_t min,
                   int64_t max, int64_t& value, Diagnostics& diagnostics);

}  // namespace syrof::lab::scenario
