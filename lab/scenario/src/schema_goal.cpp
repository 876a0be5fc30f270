// `goal:`, the declarative goal checks (lab/goals): a list of maps, each
// naming its check and that check's keys, validated against the resolved
// arena, robots and duration.
#include <cmath>
#include <numbers>
#include <set>
#include <string_view>

#include "nearest_name.h"
#include "schema.h"
#include "syrof/lab/scenario/yaml/document.h"
#include "value_reader.h"

namespace syrof::lab::scenario {
namespace {

using goals::CheckKind;
using goals::GoalCheck;
using goals::Point;

constexpr double kMaxExtentM = 1000;

// The keys every check takes, and each kind's own.
constexpr std::string_view kCommonKeys[] = {"check", "name", "when", "from_s", "deadline_s"};
std::vector<std::string_view> KeysOf(CheckKind kind) {
  std::vector<std::string_view> keys(std::begin(kCommonKeys), std::end(kCommonKeys));
  switch (kind) {
    case CheckKind::kSlots:
      keys.insert(keys.end(), {"points", "assign", "tolerance_m"});
      break;
    case CheckKind::kShape:
      keys.insert(keys.end(), {"points", "tolerance_m"});
      break;
    case CheckKind::kLine:
      keys.insert(keys.end(), {"spacing_m", "direction_rad", "tolerance_m", "order_by"});
      break;
    case CheckKind::kGathered:
      keys.insert(keys.end(), {"radius_m", "centre", "centre_at_max", "group_by", "groups_apart_m"});
      break;
    case CheckKind::kCircle:
      keys.insert(keys.end(), {"radius_min_m", "radius_max_m", "centre", "angle_tolerance_rad"});
      break;
    case CheckKind::kCoverage:
      keys.insert(keys.end(), {"area_min", "area_max", "cell_m", "min_fraction"});
      break;
  }
  return keys;
}

// {x_m, y_m}, both required, each within `x_range` / `y_range`.
bool ReadPoint(const YamlNode& node, const std::string& path, const NumberRange& x_range, const NumberRange& y_range,
               Point& point, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"x_m", "y_m"};
  return ExpectMap(node, path, diagnostics) && CheckKeys(node, path, kKeys, diagnostics) &&
         RequireKey(node, path, "x_m", diagnostics) && RequireKey(node, path, "y_m", diagnostics) &&
         ReadNumberAt(node, path, "x_m", x_range, point.x_m, diagnostics) &&
         ReadNumberAt(node, path, "y_m", y_range, point.y_m, diagnostics);
}

bool ReadPoints(const YamlNode& node, const std::string& path, const NumberRange& x_range,
                const NumberRange& y_range, std::vector<Point>& points, Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  if (node.values.empty()) return FailAt(node, path, "needs at least one point", diagnostics);
  if (node.values.size() > static_cast<size_t>(MaxRobots())) {
    return FailAt(node, path, "has " + std::to_string(node.values.size()) + " points; at most " +
                                  std::to_string(MaxRobots()) + " are allowed", diagnostics);
  }
  points.resize(node.values.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!ReadPoint(node.values[i], IndexPath(path, i), x_range, y_range, points[i], diagnostics)) return false;
  }
  return true;
}

// `key` of `node`, the name of one of the scenario's inputs: the check reads
// its values (GoalCheck::input_values) the way `use` says.
bool ReadInputUse(const YamlNode& node, const std::string& path, std::string_view key, GoalCheck::InputUse use,
                  const Scenario& scenario, GoalCheck& check, Diagnostics& diagnostics) {
  const YamlNode* value = node.Find(key);
  if (value == nullptr) return true;
  const std::string key_path = JoinPath(path, key);
  if (check.input_use != GoalCheck::InputUse::kNone) {
    return FailAt(*value, key_path, "a check reads one input: give centre_at_max or group_by, not both",
                  diagnostics);
  }
  if (!ReadString(*value, key_path, check.input, diagnostics)) return false;
  const auto found = scenario.inputs.find(check.input);
  if (found == scenario.inputs.end()) {
    std::vector<std::string_view> names;
    for (const auto& [name, values] : scenario.inputs) names.push_back(name);
    const std::string nearest = NearestName(check.input, names);
    return FailAt(*value, key_path,
                  "no input '" + check.input + "' in the scenario" +
                      (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
                      (names.empty() ? "; it gives none (inputs: ...)" : "; its inputs: " + JoinNames(names)),
                  diagnostics);
  }
  check.input_use = use;
  check.input_values = found->second;
  return true;
}

std::string RobotsText(size_t count) {
  return std::to_string(count) + (count == 1 ? " robot" : " robots");
}

bool ReadKindKeys(const YamlNode& node, const std::string& path, const Scenario& scenario, GoalCheck& check,
                  Diagnostics& diagnostics) {
  const NumberRange arena_x{0, scenario.arena.width_m};
  const NumberRange arena_y{0, scenario.arena.height_m};
  const NumberRange any{-kMaxExtentM, kMaxExtentM};
  const NumberRange tolerance{0, 100, true};
  const size_t robots = scenario.robots.size();
  switch (check.kind) {
    case CheckKind::kSlots: {
      if (!RequireKey(node, path, "points", diagnostics) ||
          !ReadPoints(*node.Find("points"), JoinPath(path, "points"), arena_x, arena_y, check.points, diagnostics) ||
          !ReadNumberAt(node, path, "tolerance_m", tolerance, check.tolerance_m, diagnostics)) {
        return false;
      }
      if (const YamlNode* assign = node.Find("assign")) {
        static constexpr std::string_view kAssign[] = {"matching", "by_id"};
        size_t index = 0;
        if (!ReadChoice(*assign, JoinPath(path, "assign"), kAssign, index, diagnostics)) return false;
        check.by_id = index == 1;
      }
      const YamlNode& points = *node.Find("points");
      if (check.by_id && check.points.size() != robots) {
        return FailAt(points, JoinPath(path, "points"),
                      "with 'assign: by_id' needs one slot per robot: " + std::to_string(check.points.size()) +
                          " given, the scenario has " + RobotsText(robots),
                      diagnostics);
      }
      if (!check.by_id && check.points.size() < robots) {
        return FailAt(points, JoinPath(path, "points"),
                      "has " + std::to_string(check.points.size()) + " slots for " + RobotsText(robots) +
                          "; every robot needs one",
                      diagnostics);
      }
      return true;
    }
    case CheckKind::kShape:
      if (!RequireKey(node, path, "points", diagnostics) ||
          !ReadPoints(*node.Find("points"), JoinPath(path, "points"), any, any, check.points, diagnostics) ||
          !ReadNumberAt(node, path, "tolerance_m", tolerance, check.tolerance_m, diagnostics)) {
        return false;
      }
      if (check.points.size() != robots) {
        return FailAt(*node.Find("points"), JoinPath(path, "points"),
                      "the shape has " + std::to_string(check.points.size()) + " points; the scenario has " +
                          RobotsText(robots) + " (one point per robot)",
                      diagnostics);
      }
      return true;
    case CheckKind::kLine: {
      double direction = 0;
      if (!RequireKey(node, path, "spacing_m", diagnostics) ||
          !ReadNumberAt(node, path, "spacing_m", NumberRange{0, 100, true}, check.spacing_m, diagnostics) ||
          !ReadNumberAt(node, path, "tolerance_m", tolerance, check.tolerance_m, diagnostics)) {
        return false;
      }
      if (node.Find("direction_rad") != nullptr) {
        const double limit = 2 * std::numbers::pi;
        if (!ReadNumberAt(node, path, "direction_rad", NumberRange{-limit, limit}, direction, diagnostics)) return false;
        check.direction_rad = direction;
      }
      return ReadInputUse(node, path, "order_by", GoalCheck::InputUse::kOrderBy, scenario, check, diagnostics);
    }
    case CheckKind::kGathered:
      if (!RequireKey(node, path, "radius_m", diagnostics) ||
          !ReadNumberAt(node, path, "radius_m", NumberRange{0, kMaxExtentM, true}, check.radius_m, diagnostics)) {
        return false;
      }
      if (const YamlNode* centre = node.Find("centre")) {
        Point point;
        if (!ReadPoint(*centre, JoinPath(path, "centre"), arena_x, arena_y, point, diagnostics)) return false;
        check.centre = point;
      }
      if (!ReadInputUse(node, path, "centre_at_max", GoalCheck::InputUse::kCentreAtMax, scenario, check,
                        diagnostics) ||
          !ReadInputUse(node, path, "group_by", GoalCheck::InputUse::kGroupBy, scenario, check, diagnostics)) {
        return false;
      }
      if (check.centre && check.input_use != GoalCheck::InputUse::kNone) {
        return FailAt(*node.Find("centre"), JoinPath(path, "centre"),
                      "a given centre and centre_at_max or group_by exclude each other", diagnostics);
      }
      if (const YamlNode* apart = node.Find("groups_apart_m")) {
        if (check.input_use != GoalCheck::InputUse::kGroupBy) {
          return FailAt(*apart, JoinPath(path, "groups_apart_m"), "needs group_by", diagnostics);
        }
        if (!ReadNumber(*apart, JoinPath(path, "groups_apart_m"), NumberRange{0, kMaxExtentM}, check.groups_apart_m,
                        diagnostics)) {
          return false;
        }
      }
      return true;
    case CheckKind::kCircle: {
      if (!RequireKey(node, path, "radius_min_m", diagnostics) || !RequireKey(node, path, "radius_max_m", diagnostics) ||
          !ReadNumberAt(node, path, "radius_min_m", NumberRange{0, kMaxExtentM, true}, check.radius_min_m,
                        diagnostics) ||
          !ReadNumberAt(node, path, "radius_max_m", NumberRange{0, kMaxExtentM, true}, check.radius_max_m,
                        diagnostics) ||
          !ReadNumberAt(node, path, "angle_tolerance_rad", NumberRange{0, std::numbers::pi, true},
                        check.angle_tolerance_rad, diagnostics)) {
        return false;
      }
      if (check.radius_max_m < check.radius_min_m) {
        return FailAt(*node.Find("radius_max_m"), JoinPath(path, "radius_max_m"),
                      "must be at least radius_min_m (" + FormatNumber(check.radius_min_m) + "), got " +
                          FormatNumber(check.radius_max_m),
                      diagnostics);
      }
      if (const YamlNode* centre = node.Find("centre")) {
        Point point;
        if (!ReadPoint(*centre, JoinPath(path, "centre"), arena_x, arena_y, point, diagnostics)) return false;
        check.centre = point;
      }
      return true;
    }
    case CheckKind::kCoverage: {
      check.area_min = {0, 0};
      check.area_max = {scenario.arena.width_m, scenario.arena.height_m};
      if (!RequireKey(node, path, "min_fraction", diagnostics) ||
          !ReadNumberAt(node, path, "min_fraction", NumberRange{0, 1, true}, check.min_fraction, diagnostics) ||
          !ReadNumberAt(node, path, "cell_m", NumberRange{0, 100, true}, check.cell_m, diagnostics)) {
        return false;
      }
      if (const YamlNode* low = node.Find("area_min")) {
        if (!ReadPoint(*low, JoinPath(path, "area_min"), arena_x, arena_y, check.area_min, diagnostics)) return false;
      }
      if (const YamlNode* high = node.Find("area_max")) {
        if (!ReadPoint(*high, JoinPath(path, "area_max"), arena_x, arena_y, check.area_max, diagnostics)) return false;
      }
      const YamlNode& at = node.Find("area_max") ? *node.Find("area_max") : node.Find("area_min") ? *node.Find("area_min") : node;
      if (!(check.area_max.x_m > check.area_min.x_m && check.area_max.y_m > check.area_min.y_m)) {
        return FailAt(at, path, "the area is empty: area_max must be above and right of area_min", diagnostics);
      }
      const double cells = std::ceil((check.area_max.x_m - check.area_min.x_m) / check.cell_m) *
                           std::ceil((check.area_max.y_m - check.area_min.y_m) / check.cell_m);
      if (cells > static_cast<double>(goals::kMaxCoverageCells)) {
        const YamlNode& cell = node.Find("cell_m") ? *node.Find("cell_m") : node;
        return FailAt(cell, JoinPath(path, "cell_m"),
                      "the area would have " + (cells < 1e15 ? std::to_string(static_cast<int64_t>(cells)) : FormatShort(cells)) + " cells; at most " +
                          std::to_string(goals::kMaxCoverageCells) + " are allowed (use larger cells)",
                      diagnostics);
      }
      return true;
    }
  }
  return true;
}

bool ReadCheck(const YamlNode& node, const std::string& path, const Scenario& scenario, size_t index,
               GoalCheck& check, Diagnostics& diagnostics) {
  if (!ExpectMap(node, path, diagnostics) || !RequireKey(node, path, "check", diagnostics)) return false;
  size_t kind = 0;
  if (!ReadChoice(*node.Find("check"), JoinPath(path, "check"), goals::CheckKindNames(), kind, diagnostics)) {
    return false;
  }
  check.kind = static_cast<CheckKind>(kind);
  const std::vector<std::string_view> keys = KeysOf(check.kind);
  if (!CheckKeys(node, path, keys, diagnostics)) return false;
  check.name = std::string(goals::ToString(check.kind)) + "#" + std::to_string(index);
  if (const YamlNode* name = node.Find("name")) {
    if (!ReadString(*name, JoinPath(path, "name"), check.name, diagnostics)) return false;
    if (!IsValidName(check.name)) {
      return FailAt(*name, JoinPath(path, "name"),
                    "must be 1 to 64 letters, digits, '_', '-' or '.', got '" + name->scalar + "'", diagnostics);
    }
  }
  const double duration = scenario.timing.duration_s;
  if (const YamlNode* when = node.Find("when")) {
    static constexpr std::string_view kWhen[] = {"final", "every_epoch"};
    size_t choice = 0;
    if (!ReadChoice(*when, JoinPath(path, "when"), kWhen, choice, diagnostics)) return false;
    check.when = static_cast<goals::When>(choice);
    if (check.kind == CheckKind::kCoverage && check.when != goals::When::kFinal) {
      return FailAt(*when, JoinPath(path, "when"), "coverage is measured over the whole run; it takes no 'when'",
                    diagnostics);
    }
  }
  if (const YamlNode* from = node.Find("from_s")) {
    if (check.when != goals::When::kEveryEpoch) {
      return FailAt(KeyNode(node, "from_s"), path, "'from_s' needs 'when: every_epoch'", diagnostics);
    }
    if (!ReadNumber(*from, JoinPath(path, "from_s"), NumberRange{0, duration, false, true}, check.from_s,
                    diagnostics)) {
      return false;
    }
  }
  if (node.Find("deadline_s") != nullptr) {
    double deadline = 0;
    if (!ReadNumberAt(node, path, "deadline_s", NumberRange{0, duration, true}, deadline, diagnostics)) return false;
    check.deadline_s = deadline;
  }
  return ReadKindKeys(node, path, scenario, check, diagnostics);
}

}  // namespace

bool ReadGoal(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  return node == nullptr || ReadGoalChecks(*node, "goal", scenario, scenario.goal, diagnostics);
}

bool ReadGoalChecks(const YamlNode& goal, const std::string& path, const Scenario& scenario,
                    std::vector<goals::GoalCheck>& result, Diagnostics& diagnostics) {
  const YamlNode* node = &goal;
  if (!ExpectList(*node, path, diagnostics)) return false;
  std::vector<GoalCheck> checks(node->values.size());
  std::set<std::string> names;
  for (size_t i = 0; i < checks.size(); ++i) {
    const std::string item = IndexPath(path, i);
    if (!ReadCheck(node->values[i], item, scenario, i, checks[i], diagnostics)) return false;
    if (!names.insert(checks[i].name).second) {
      const YamlNode* name = node->values[i].Find("name");
      return FailAt(name != nullptr ? *name : node->values[i], JoinPath(item, "name"),
                    "another check is already named '" + checks[i].name + "'", diagnostics);
    }
  }
  // A lone check of a kind keeps the plain kind name.
  for (size_t i = 0; i < checks.size(); ++i) {
    if (node->values[i].Find("name") != nullptr) continue;
    size_t same_kind = 0;
    for (const GoalCheck& other : checks) same_kind += other.kind == checks[i].kind ? 1 : 0;
    const std::string plain(goals::ToString(checks[i].kind));
    if (same_kind == 1 && names.count(plain) == 0) checks[i].name = plain;
  }
  result = std::move(checks);
  return true;
}

}  // namespace syrof::lab::scenario
