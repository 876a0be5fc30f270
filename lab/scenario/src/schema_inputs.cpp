// `inputs:`: each robot's private values (syrofAppInput), listed one per
// robot or drawn from the scenario's seed (docs/scenarios.md, "Private
// inputs").
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "schema.h"
#include "syrof/app.h"
#include "syrof/base/split_mix64.h"
#include "value_reader.h"

namespace syrof::lab::scenario {
namespace {

const NumberRange kAnyNumber{std::numeric_limits<double>::lowest(), std::numeric_limits<double>::max()};
// Whole numbers a draw of `integers` may span: exact in a double.
constexpr double kMaxWhole = 9007199254740992.0;  // 2^53

// 64 uniform bits for (seed, input name, robot): the same in every runtime,
// and another input's or robot's draw is independent of this one.
uint64_t DrawBits(uint64_t seed, const std::string& name, uint16_t robot) {
  uint64_t name_hash = 0xcbf29ce484222325ull;  // FNV-1a of the name
  for (const char c : name) name_hash = (name_hash ^ static_cast<uint8_t>(c)) * 0x100000001b3ull;
  return base::SplitMix64Hash(base::SplitMix64Hash(seed ^ base::SplitMix64Hash(name_hash)) + robot);
}

// A uniform double in [0, 1) from 53 of the bits.
double Unit(uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

// Reads a list of finite numbers.
bool ReadNumbers(const YamlNode& node, const std::string& path, std::vector<double>& numbers,
                 Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  for (size_t i = 0; i < node.values.size(); ++i) {
    double value = 0;
    if (!ReadNumber(node.values[i], IndexPath(path, i), kAnyNumber, value, diagnostics)) return false;
    numbers.push_back(value);
  }
  return true;
}

// `[low, high]` with low < high (whole numbers when `whole`).
bool ReadBounds(const YamlNode& node, const std::string& path, bool whole, double& low, double& high,
                Diagnostics& diagnostics) {
  std::vector<double> bounds;
  if (!ReadNumbers(node, path, bounds, diagnostics)) return false;
  if (bounds.size() != 2 || !(bounds[0] < bounds[1])) {
    return FailAt(node, path, "must be [low, high] with low below high", diagnostics);
  }
  if (whole && (bounds[0] != std::floor(bounds[0]) || bounds[1] != std::floor(bounds[1]) ||
                std::fabs(bounds[0]) > kMaxWhole || std::fabs(bounds[1]) > kMaxWhole)) {
    return FailAt(node, path, "must be two whole numbers (within 2^53)", diagnostics);
  }
  // A draw is low + (high - low) * u: a span past a double's range would
  // draw infinities and NaN.
  if (!std::isfinite(bounds[1] - bounds[0])) {
    return FailAt(node, path, "high - low must be a finite number, got [" + FormatNumber(bounds[0]) + ", " +
                                  FormatNumber(bounds[1]) + "]",
                  diagnostics);
  }
  low = bounds[0];
  high = bounds[1];
  return true;
}

// One input's values, one per robot: a list, or a draw.
bool ReadInput(const YamlNode& node, const std::string& path, const std::string& name, const Scenario& scenario,
               std::vector<double>& values, Diagnostics& diagnostics) {
  const size_t robots = scenario.robots.size();
  if (node.is_sequence()) {
    if (!ReadNumbers(node, path, values, diagnostics)) return false;
    if (values.size() != robots) {
      return FailAt(node, path,
                    "lists " + std::to_string(values.size()) + " values; the scenario has " + std::to_string(robots) +
                        " robots, one value each in id order (or draw them: {uniform: [low, high]}, "
                        "{integers: [low, high]} or {choice: [a, b, ...]})",
                    diagnostics);
    }
    return true;
  }
  static constexpr std::string_view kDraws[] = {"uniform", "integers", "choice"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kDraws, diagnostics)) return false;
  if (node.keys.size() != 1) {
    return FailAt(node, path, "give one value per robot as a list, or exactly one of uniform, integers, choice",
                  diagnostics);
  }
  const std::string& draw = node.keys[0].scalar;
  const YamlNode& spec = node.values[0];
  const std::string spec_path = JoinPath(path, draw);
  std::vector<double> choices;
  double low = 0, high = 0;
  if (draw == "choice") {
    if (!ReadNumbers(spec, spec_path, choices, diagnostics)) return false;
    if (choices.empty()) return FailAt(spec, spec_path, "must list at least one value", diagnostics);
  } else if (!ReadBounds(spec, spec_path, draw == "integers", low, high, diagnostics)) {
    return false;
  }
  for (uint16_t robot = 0; robot < robots; ++robot) {
    const uint64_t bits = DrawBits(scenario.seed, name, robot);
    if (draw == "choice") {
      values.push_back(choices[bits % choices.size()]);
    } else if (draw == "integers") {
      const auto span = static_cast<uint64_t>(high - low) + 1;
      values.push_back(low + static_cast<double>(bits % span));
    } else {
      values.push_back(low + (high - low) * Unit(bits));
    }
  }
  return true;
}

}  // namespace

bool ReadInputs(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  if (node == nullptr) return true;
  const std::string path = "inputs";
  if (!ExpectMap(*node, path, diagnostics)) return false;
  if (node->keys.size() > SYROF_APP_MAX_INPUTS) {
    return FailAt(node->keys[SYROF_APP_MAX_INPUTS], path,
                  "too many inputs: " + std::to_string(node->keys.size()) + ", a robot takes at most " +
                      std::to_string(SYROF_APP_MAX_INPUTS),
                  diagnostics);
  }
  for (size_t i = 0; i < node->keys.size(); ++i) {
    const std::string& name = node->keys[i].scalar;
    if (!CheckAppValueName(node->keys[i], path, "input", diagnostics)) return false;
    std::vector<double> values;
    if (!ReadInput(node->values[i], JoinPath(path, name), name, scenario, values, diagnostics)) return false;
    scenario.inputs[name] = std::move(values);
  }
  return true;
}

}  // namespace syrof::lab::scenario
