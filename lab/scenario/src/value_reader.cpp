#include "value_reader.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include "nearest_name.h"

namespace syrof::lab::scenario {
namespace {

// What a node is, for "expected a number, got ...".
std::string Describe(const YamlNode& node) {
  switch (node.kind) {
    case YamlNode::Kind::kNull:
      return "nothing";
    case YamlNode::Kind::kMap:
      return "a map";
    case YamlNode::Kind::kSequence:
      return "a list";
    case YamlNode::Kind::kScalar:
      break;
  }
  constexpr size_t kShown = 40;
  std::string text = node.scalar.size() > kShown ? node.scalar.substr(0, kShown) + "..." : node.scalar;
  return node.quoted ? "the quoted string \"" + text + "\"" : "'" + text + "'";
}

bool ExpectType(const YamlNode& node, const std::string& path, const std::string& what, Diagnostics& diagnostics) {
  return FailAt(node, path, "expected " + what + ", got " + Describe(node), diagnostics);
}

// The text of a plain scalar without one leading '+' (YAML allows it,
// from_chars does not).
std::string_view Digits(const YamlNode& node) {
  std::string_view text = node.scalar;
  if (!text.empty() && text[0] == '+') text.remove_prefix(1);
  return text;
}

}  // namespace

bool NumberRange::Contains(double value) const {
  const bool above_min = min_open ? value > min : value >= min;
  const bool below_max = max_open ? value < max : value <= max;
  return above_min && below_max;
}

std::string NumberRange::ToString() const {
  return std::string(min_open ? "(" : "[") + FormatNumber(min) + ", " + FormatNumber(max) + (max_open ? ")" : "]");
}

std::string JoinPath(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

std::string IndexPath(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

std::string FormatNumber(double value) {
  // Shortest text that reads back as the same double, fixed or exponent
  // notation whichever is shorter ("1000", "0.1", "1e-05").
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return error == std::errc() ? std::string(buffer, end) : "?";
}

std::string FormatShort(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

bool FailAt(const YamlNode& node, const std::string& path, const std::string& what, Diagnostics& diagnostics) {
  return diagnostics.Fail(node.line, node.column, path.empty() ? what : path + ": " + what);
}

bool ExpectMap(const YamlNode& node, const std::string& path, Diagnostics& diagnostics) {
  return node.is_map() || ExpectType(node, path, "a map", diagnostics);
}

bool ExpectList(const YamlNode& node, const std::string& path, Diagnostics& diagnostics) {
  return node.is_sequence() || ExpectType(node, path, "a list", diagnostics);
}

bool CheckKeys(const YamlNode& map, const std::string& path, std::span<const std::string_view> allowed,
               Diagnostics& diagnostics) {
  for (const YamlNode& key : map.keys) {
    bool known = false;
    for (std::string_view name : allowed) known = known || key.scalar == name;
    if (known) continue;
    const std::string nearest = NearestName(key.scalar, allowed);
    const std::string hint =
        nearest.empty() ? " (valid keys: " + JoinNames(allowed) + ")" : " (did you mean '" + nearest + "'?)";
    return FailAt(key, path, "unknown key '" + key.scalar + "'" + hint, diagnostics);
  }
  return true;
}

bool RequireKey(const YamlNode& map, const std::string& path, std::string_view key, Diagnostics& diagnostics) {
  if (map.Find(key) != nullptr) return true;
  return FailAt(map, path, "missing required key '" + JoinPath(path, key) + "'", diagnostics);
}

bool ReadNumber(const YamlNode& node, const std::string& path, const NumberRange& range, double& value,
                Diagnostics& diagnostics) {
  if (!node.is_scalar() || node.quoted) return ExpectType(node, path, "a number", diagnostics);
  const std::string_view text = Digits(node);
  double parsed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  // from_chars also reads "inf" and "nan"; YAML's ".inf" and ".nan" fail it.
  const bool whole = error == std::errc() && end == text.data() + text.size() && !text.empty();
  if (!whole && error != std::errc::result_out_of_range) return ExpectType(node, path, "a number", diagnostics);
  if (error == std::errc::result_out_of_range || !std::isfinite(parsed)) {
    return FailAt(node, path, "expected a finite number, got " + Describe(node), diagnostics);
  }
  if (!range.Contains(parsed)) {
    return FailAt(node, path, "must be in " + range.ToString() + ", got " + node.scalar, diagnostics);
  }
  value = parsed;
  return true;
}

bool ReadInteger(const YamlNode& node, const std::string& path, int64_t min, int64_t max, int64_t& value,
                 Diagnostics& diagnostics) {
  if (!node.is_scalar() || node.quoted) return ExpectType(node, path, "an integer", diagnostics);
  const std::string_view text = Digits(node);
  int64_t parsed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), parsed, 10);
  const bool whole = end == text.data() + text.size() && !text.empty();
  if (error == std::errc::result_out_of_range && whole) {
    return FailAt(node, path, "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " + node.scalar,
                  diagnostics);
  }
  if (error != std::errc() || !whole) return ExpectType(node, path, "an integer", diagnostics);
  if (parsed < min || parsed > max) {
    return FailAt(node, path, "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " + node.scalar,
                  diagnostics);
  }
  value = parsed;
  return true;
}

bool ReadUnsigned64(const YamlNode& node, const std::string& path, uint64_t& value, Diagnostics& diagnostics) {
  if (!node.is_scalar() || node.quoted) return ExpectType(node, path, "an unsigned integer", diagnostics);
  const std::string_view text = node.scalar;
  for (char c : text) {
    if (c < '0' || c > '9') return ExpectType(node, path, "an unsigned integer in decimal digits", diagnostics);
  }
  uint64_t parsed = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), parsed, 10);
  if (error == std::errc::result_out_of_range) {
    return FailAt(node, path, "must be at most " + std::to_string(std::numeric_limits<uint64_t>::max()) + ", got " +
                                  node.scalar, diagnostics);
  }
  if (error != std::errc() || end != text.data() + text.size() || text.empty()) {
    return ExpectType(node, path, "an unsigned integer", diagnostics);
  }
  value = parsed;
  return true;
}

bool ReadString(const YamlNode& node, const std::string& path, std::string& value, Diagnostics& diagnostics) {
  if (!node.is_scalar()) return ExpectType(node, path, "a string", diagnostics);
  value = node.scalar;
  return true;
}

bool ReadChoice(const YamlNode& node, const std::string& path, std::span<const std::string_view> choices,
                size_t& index, Diagnostics& diagnostics) {
  if (!node.is_scalar()) return ExpectType(node, path, "one of " + JoinNames(choices), diagnostics);
  for (size_t i = 0; i < choices.size(); ++i) {
    if (node.scalar == choices[i]) {
      index = i;
      return true;
    }
  }
  const std::string nearest = NearestName(node.scalar, choices);
  const std::string hint = nearest.empty() ? "" : " (did you mean '" + nearest + "'?)";
  return FailAt(node, path, "unknown value '" + node.scalar + "'" + hint + "; expected one of " + JoinNames(choices),
                diagnostics);
}

bool ReadNumberAt(const YamlNode& map, const std::string& map_path, std::string_view key, const NumberRange& range,
                  double& value, Diagnostics& diagnostics) {
  const YamlNode* node = map.Find(key);
  return node == nullptr || ReadNumber(*node, JoinPath(map_path, key), range, value, diagnostics);
}

bool ReadIntegerAt(const YamlNode& map, const std::string& map_path, std::string_view key, int64_t min,
                   int64_t max, int64_t& value, Diagnostics& diagnostics) {
  const YamlNode* node = map.Find(key);
  return node == nullptr || ReadInteger(*node, JoinPath(map_path, key), min, max, value, diagnostics);
}

}  // namespace syrof::lab::scenario
