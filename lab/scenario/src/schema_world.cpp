// The arena, the robot kinds and the robots' start.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <string_view>

#include "placement.h"
#include "schema.h"
#include "syrof/estimation/arena.h"
#include "value_reader.h"

namespace syrof::lab::scenario {
namespace {

constexpr NumberRange kArenaSideRange{0, 1000, true};
// The largest position a beacon carries: 32767 mm (wire::ToMillimetres saturates beyond).
constexpr double kMaxArenaSideM = 32.767;
constexpr NumberRange kTagHeightRange{0, 10};
constexpr double kMaxAnchorHeightM = 20;
// Two anchors closer than this are one anchor listed twice.
constexpr double kMinAnchorSpacingM = 0.1;
// Twice the area of the largest triangle of anchors seen from above must
// reach this for multilateration in the plane to be well posed.
constexpr double kMinAnchorSpreadM2 = 0.01;

std::string PointText(double x_m, double y_m) { return "(" + FormatShort(x_m) + ", " + FormatShort(y_m) + ")"; }

bool ReadAnchor(const YamlNode& node, const std::string& path, const Scenario& scenario, world::AnchorSpec& anchor,
                Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"x_m", "y_m", "z_m"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics)) return false;
  if (!RequireKey(node, path, "x_m", diagnostics) || !RequireKey(node, path, "y_m", diagnostics)) return false;
  // Plausible: within one arena width (height) of the walls, on or above
  // the floor, below a high ceiling.
  const double width_m = scenario.arena.width_m;
  const double height_m = scenario.arena.height_m;
  return ReadNumberAt(node, path, "x_m", NumberRange{-width_m, 2 * width_m}, anchor.x_m, diagnostics) &&
         ReadNumberAt(node, path, "y_m", NumberRange{-height_m, 2 * height_m}, anchor.y_m, diagnostics) &&
         ReadNumberAt(node, path, "z_m", NumberRange{0, kMaxAnchorHeightM}, anchor.z_m, diagnostics);
}

bool ReadAnchors(const YamlNode& node, const std::string& path, Scenario& scenario, Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  const size_t count = node.values.size();
  if (count < 3 || count > static_cast<size_t>(estimation::kMaxAnchors)) {
    return FailAt(node, path,
                  "needs 3 to " + std::to_string(estimation::kMaxAnchors) + " anchors, got " + std::to_string(count),
                  diagnostics);
  }
  std::vector<world::AnchorSpec>& anchors = scenario.arena.anchors;
  anchors.assign(count, world::AnchorSpec{});
  for (size_t i = 0; i < count; ++i) {
    if (!ReadAnchor(node.values[i], IndexPath(path, i), scenario, anchors[i], diagnostics)) return false;
    for (size_t j = 0; j < i; ++j) {
      const double apart_m =
          std::hypot(anchors[i].x_m - anchors[j].x_m, anchors[i].y_m - anchors[j].y_m, anchors[i].z_m - anchors[j].z_m);
      if (apart_m < kMinAnchorSpacingM) {
        return FailAt(node.values[i], IndexPath(path, i),
                      "is within " + FormatNumber(kMinAnchorSpacingM) + " m of anchors[" + std::to_string(j) + "]",
                      diagnostics);
      }
    }
  }
  double spread_m2 = 0;
  for (size_t a = 0; a < count; ++a) {
    for (size_t b = a + 1; b < count; ++b) {
      for (size_t c = b + 1; c < count; ++c) {
        const double cross = (anchors[b].x_m - anchors[a].x_m) * (anchors[c].y_m - anchors[a].y_m) -
                             (anchors[b].y_m - anchors[a].y_m) * (anchors[c].x_m - anchors[a].x_m);
        spread_m2 = std::max(spread_m2, std::abs(cross));
      }
    }
  }
  if (spread_m2 < kMinAnchorSpreadM2) {
    return FailAt(node, path, "the anchors lie on one line seen from above; multilateration needs them spread out",
                  diagnostics);
  }
  return true;
}

// The paper's layout stretched over the arena: (0,0,0), (W,H,0), (0,H,h),
// (W,0,h) with h the default layout's height; DefaultArena() on 4 m x 4 m.
std::vector<world::AnchorSpec> DefaultAnchors(double width_m, double height_m) {
  const double top_m = estimation::DefaultAnchorLayout<double>().height_m;
  return {{0, 0, 0}, {width_m, height_m, 0}, {0, height_m, top_m}, {width_m, 0, top_m}};
}

void FillSensorArena(Scenario& scenario, double tag_height_m) {
  estimation::Arena<double>& arena = scenario.sensors.arena;
  arena.width_m = scenario.arena.width_m;
  arena.depth_m = scenario.arena.height_m;
  arena.tag_height_m = tag_height_m;
  arena.anchor_count = static_cast<int>(scenario.arena.anchors.size());
  for (int i = 0; i < estimation::kMaxAnchors; ++i) {
    const bool used = i < arena.anchor_count;
    const world::AnchorSpec anchor = used ? scenario.arena.anchors[i] : world::AnchorSpec{};
    arena.anchors[i] = estimation::Vector3<double>(anchor.x_m, anchor.y_m, anchor.z_m);
  }
}

bool ReadKind(const YamlNode& node, const std::string& path, world::RobotKind kind, world::KindSpec& spec,
              Diagnostics& diagnostics) {
  static constexpr std::string_view kOmniKeys[] = {"body_radius_m", "max_speed_mps", "max_accel_mps2",
                                                   "max_turn_rate_radps"};
  static constexpr std::string_view kRoverKeys[] = {"body_radius_m", "max_speed_mps", "max_accel_mps2",
                                                    "wheel_base_m"};
  static constexpr std::string_view kDroneKeys[] = {"body_radius_m",        "max_speed_mps",   "max_accel_mps2",
                                                    "max_turn_rate_radps",  "tilt_time_constant_s",
                                                    "drift_sigma_mps",      "flight_height_m"};
  if (!ExpectMap(node, path, diagnostics)) return false;
  std::span<const std::string_view> keys = kOmniKeys;
  if (kind == world::RobotKind::kRover) keys = kRoverKeys;
  if (kind == world::RobotKind::kDrone) keys = kDroneKeys;
  if (!CheckKeys(node, path, keys, diagnostics)) return false;
  return ReadNumberAt(node, path, "body_radius_m", NumberRange{0, 1, true}, spec.body_radius_m, diagnostics) &&
         ReadNumberAt(node, path, "max_speed_mps", NumberRange{0, 10, true}, spec.max_speed_mps, diagnostics) &&
         ReadNumberAt(node, path, "max_accel_mps2", NumberRange{0, 100, true}, spec.max_accel_mps2, diagnostics) &&
         ReadNumberAt(node, path, "max_turn_rate_radps", NumberRange{0, 100, true}, spec.max_turn_rate_radps,
                      diagnostics) &&
         ReadNumberAt(node, path, "wheel_base_m", NumberRange{0, 2, true}, spec.wheel_base_m, diagnostics) &&
         ReadNumberAt(node, path, "tilt_time_constant_s", NumberRange{0, 2}, spec.tilt_time_constant_s,
                      diagnostics) &&
         ReadNumberAt(node, path, "drift_sigma_mps", NumberRange{0, 0.5}, spec.drift_sigma_mps, diagnostics) &&
         ReadNumberAt(node, path, "flight_height_m", NumberRange{0, 3, true}, spec.flight_height_m, diagnostics);
}

constexpr std::string_view kKindNames[] = {"omni", "rover", "drone"};  // RobotKind's order
constexpr std::string_view kPlacementNames[] = {"explicit", "grid", "circle", "random"};  // Placement's order

bool ReadKindName(const YamlNode& node, const std::string& path, world::RobotKind& kind, Diagnostics& diagnostics) {
  size_t index = 0;
  if (!ReadChoice(node, path, kKindNames, index, diagnostics)) return false;
  kind = static_cast<world::RobotKind>(index);
  return true;
}

bool ReadPose(const YamlNode& node, const std::string& path, world::RobotKind default_kind, RobotSpec& robot,
              Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"x_m", "y_m", "heading_rad", "kind"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics)) return false;
  if (!RequireKey(node, path, "x_m", diagnostics) || !RequireKey(node, path, "y_m", diagnostics)) return false;
  // Positions are checked against the arena once every robot is known.
  constexpr NumberRange kAnyPosition{-1e6, 1e6};
  constexpr NumberRange kHeading{-2 * std::numbers::pi, 2 * std::numbers::pi};
  robot.kind = default_kind;
  const YamlNode* kind = node.Find("kind");
  return ReadNumberAt(node, path, "x_m", kAnyPosition, robot.x_m, diagnostics) &&
         ReadNumberAt(node, path, "y_m", kAnyPosition, robot.y_m, diagnostics) &&
         ReadNumberAt(node, path, "heading_rad", kHeading, robot.heading_rad, diagnostics) &&
         (kind == nullptr || ReadKindName(*kind, JoinPath(path, "kind"), robot.kind, diagnostics));
}

// Keys that only some placements use, and which.
struct PlacementKey {
  std::string_view key;
  Placement placement;
  Placement also;  // a second placement using it (same as `placement` if none)
};
constexpr PlacementKey kPlacementKeys[] = {
    {"spacing_m", Placement::kGrid, Placement::kGrid},
    {"centre", Placement::kGrid, Placement::kCircle},
    {"radius_m", Placement::kCircle, Placement::kCircle},
    {"min_separation_m", Placement::kRandom, Placement::kRandom},
    {"poses", Placement::kExplicit, Placement::kExplicit},
};

bool CheckPlacementKeys(const YamlNode& node, const std::string& path, Placement placement,
                        Diagnostics& diagnostics) {
  for (size_t i = 0; i < node.keys.size(); ++i) {
    for (const PlacementKey& rule : kPlacementKeys) {
      if (node.keys[i].scalar != rule.key || placement == rule.placement || placement == rule.also) continue;
      std::string users = std::string(kPlacementNames[static_cast<size_t>(rule.placement)]);
      if (rule.also != rule.placement) users += " and " + std::string(kPlacementNames[static_cast<size_t>(rule.also)]);
      return FailAt(node.keys[i], path,
                    "'" + std::string(rule.key) + "' applies to placement " + users + " only (placement is " +
                        std::string(kPlacementNames[static_cast<size_t>(placement)]) + ")",
                    diagnostics);
    }
  }
  return true;
}

bool ReadCentre(const YamlNode& node, const std::string& path, const Scenario& scenario, PlacementRequest& request,
                Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"x_m", "y_m"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics)) return false;
  return ReadNumberAt(node, path, "x_m", NumberRange{0, scenario.arena.width_m}, request.centre_x_m, diagnostics) &&
         ReadNumberAt(node, path, "y_m", NumberRange{0, scenario.arena.height_m}, request.centre_y_m, diagnostics);
}

// Reads count, kind, placement and the placement's own keys.
bool ReadPlacementRequest(const YamlNode& node, const Overrides& overrides, const Scenario& scenario,
                          PlacementRequest& request, Diagnostics& diagnostics) {
  const std::string path = "robots";
  const YamlNode* poses = node.Find("poses");
  request.placement = poses != nullptr ? Placement::kExplicit : Placement::kGrid;
  if (const YamlNode* placement = node.Find("placement")) {
    size_t index = 0;
    if (!ReadChoice(*placement, "robots.placement", kPlacementNames, index, diagnostics)) return false;
    request.placement = static_cast<Placement>(index);
  }
  if (!CheckPlacementKeys(node, path, request.placement, diagnostics)) return false;
  if (const YamlNode* kind = node.Find("kind")) {
    if (!ReadKindName(*kind, "robots.kind", request.kind, diagnostics)) return false;
  }
  const YamlNode* count = node.Find("count");
  int64_t file_count = 0;
  if (count != nullptr && !ReadInteger(*count, "robots.count", 1, MaxRobots(), file_count, diagnostics)) return false;

  request.centre_x_m = scenario.arena.width_m / 2;
  request.centre_y_m = scenario.arena.height_m / 2;
  request.radius_m = std::min(scenario.arena.width_m, scenario.arena.height_m) / 4;
  if (const YamlNode* centre = node.Find("centre")) {
    if (!ReadCentre(*centre, "robots.centre", scenario, request, diagnostics)) return false;
  }
  if (!ReadNumberAt(node, path, "spacing_m", NumberRange{0, 100, true}, request.spacing_m, diagnostics) ||
      !ReadNumberAt(node, path, "radius_m", NumberRange{0, 1000, true}, request.radius_m, diagnostics) ||
      !ReadNumberAt(node, path, "min_separation_m", NumberRange{0, 100}, request.min_separation_m, diagnostics)) {
    return false;
  }

  if (request.placement != Placement::kExplicit) {
    if (count == nullptr && !overrides.robots) return RequireKey(node, path, "count", diagnostics);
    request.count = static_cast<int>(overrides.robots ? *overrides.robots : file_count);
    return true;
  }
  if (poses == nullptr) return RequireKey(node, path, "poses", diagnostics);
  if (!ExpectList(*poses, "robots.poses", diagnostics)) return false;
  const size_t listed = poses->values.size();
  if (listed == 0 || listed > static_cast<size_t>(MaxRobots())) {
    return FailAt(*poses, "robots.poses", "needs 1 to " + std::to_string(MaxRobots()) + " poses, got " +
                                               std::to_string(listed), diagnostics);
  }
  if (count != nullptr && static_cast<size_t>(file_count) != listed) {
    return FailAt(*count, "robots.count", std::to_string(file_count) + " does not match the " +
                                              std::to_string(listed) + " poses listed", diagnostics);
  }
  request.poses.assign(listed, RobotSpec{});
  for (size_t i = 0; i < listed; ++i) {
    if (!ReadPose(poses->values[i], IndexPath("robots.poses", i), request.kind, request.poses[i], diagnostics)) {
      return false;
    }
  }
  request.count = static_cast<int>(listed);
  if (overrides.robots) {
    if (static_cast<size_t>(*overrides.robots) > listed) {
      return diagnostics.Fail(0, 0, "robots override " + std::to_string(*overrides.robots) +
                                        ": the scenario lists only " + std::to_string(listed) + " poses");
    }
    request.count = *overrides.robots;
  }
  return true;
}

std::string RobotAt(const RobotSpec& robot) {
  return "robot " + std::to_string(robot.id) + " at " + PointText(robot.x_m, robot.y_m);
}

// Where a start problem of `robot` is reported: its pose when the file
// lists it, else the robots map.
const YamlNode& StartNode(const YamlNode& robots, const PlacementRequest& request, int robot) {
  if (request.placement != Placement::kExplicit) return robots;
  return robots.Find("poses")->values[robot];
}

std::string StartPath(const PlacementRequest& request, int robot) {
  return request.placement == Placement::kExplicit ? IndexPath("robots.poses", robot) : "robots";
}

}  // namespace

bool ReadArena(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"width_m", "height_m", "tag_height_m", "anchors"};
  const std::string path = "arena";
  double tag_height_m = estimation::DefaultArena<double>().tag_height_m;
  if (node != nullptr) {
    if (!ExpectMap(*node, path, diagnostics) || !CheckKeys(*node, path, kKeys, diagnostics)) return false;
    if (!ReadNumberAt(*node, path, "width_m", kArenaSideRange, scenario.arena.width_m, diagnostics) ||
        !ReadNumberAt(*node, path, "height_m", kArenaSideRange, scenario.arena.height_m, diagnostics) ||
        !ReadNumberAt(*node, path, "tag_height_m", kTagHeightRange, tag_height_m, diagnostics)) {
      return false;
    }
    // Beacons carry positions as int16 millimetres: beyond 32.767 m they
    // would be clipped silently, and every robot would plan with wrong maps.
    for (const std::string_view side : {std::string_view("width_m"), std::string_view("height_m")}) {
      const YamlNode* value = node->Find(side);
      const double metres = side == "width_m" ? scenario.arena.width_m : scenario.arena.height_m;
      if (value != nullptr && metres > kMaxArenaSideM) {
        return FailAt(*value, path + "." + std::string(side),
                      "the arena is " + value->scalar + " m " + (side == "width_m" ? "wide" : "high") +
                          ", more than the beacon can express: positions travel as int16 millimetres, so at most " +
                          FormatNumber(kMaxArenaSideM) + " m (docs/beacon.md, \"Fixed-point units\")",
                      diagnostics);
      }
    }
  }
  const YamlNode* anchors = node != nullptr ? node->Find("anchors") : nullptr;
  if (anchors != nullptr) {
    if (!ReadAnchors(*anchors, "arena.anchors", scenario, diagnostics)) return false;
  } else {
    scenario.arena.anchors = DefaultAnchors(scenario.arena.width_m, scenario.arena.height_m);
  }
  FillSensorArena(scenario, tag_height_m);
  return true;
}

bool ReadKinds(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  if (node == nullptr) return true;
  const std::string path = "kinds";
  if (!ExpectMap(*node, path, diagnostics) || !CheckKeys(*node, path, kKindNames, diagnostics)) return false;
  const YamlNode* omni = node->Find("omni");
  const YamlNode* rover = node->Find("rover");
  const YamlNode* drone = node->Find("drone");
  return (omni == nullptr || ReadKind(*omni, "kinds.omni", world::RobotKind::kOmni, scenario.omni, diagnostics)) &&
         (rover == nullptr || ReadKind(*rover, "kinds.rover", world::RobotKind::kRover, scenario.rover, diagnostics)) &&
         (drone == nullptr || ReadKind(*drone, "kinds.drone", world::RobotKind::kDrone, scenario.drone, diagnostics));
}

bool ReadRobots(const YamlNode& node, const Overrides& overrides, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"count",  "kind",     "placement",        "spacing_m",
                                               "centre", "radius_m", "min_separation_m", "poses"};
  const std::string path = "robots";
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics)) return false;
  PlacementRequest request;
  if (!ReadPlacementRequest(node, overrides, scenario, request, diagnostics)) return false;
  scenario.placement = request.placement;
  if (const std::optional<int> stuck = PlaceRobots(request, scenario, scenario.seed, scenario.robots)) {
    return FailAt(node, path,
                  "random placement found no free spot for robot " + std::to_string(*stuck) + " after " +
                      std::to_string(kMaxPlacementTries) + " tries (" + std::to_string(request.count) +
                      " robots, min_separation_m " + FormatNumber(request.min_separation_m) +
                      "); use a larger arena, fewer robots or a smaller separation",
                  diagnostics);
  }
  if (const std::optional<int> outside = FirstOutsideArena(scenario)) {
    const RobotSpec& robot = scenario.robots[*outside];
    return FailAt(StartNode(node, request, *outside), StartPath(request, *outside),
                  RobotAt(robot) + " is outside the arena: its body (radius " +
                      FormatNumber(scenario.kind_spec(robot.kind).body_radius_m) + " m) must lie within [0, " +
                      FormatNumber(scenario.arena.width_m) + "] x [0, " + FormatNumber(scenario.arena.height_m) + "]",
                  diagnostics);
  }
  if (const std::optional<std::pair<int, int>> overlap = FirstOverlap(scenario)) {
    const RobotSpec& first = scenario.robots[overlap->first];
    const RobotSpec& second = scenario.robots[overlap->second];
    const double apart_m = std::hypot(first.x_m - second.x_m, first.y_m - second.y_m);
    const double needed_m = scenario.kind_spec(first.kind).body_radius_m + scenario.kind_spec(second.kind).body_radius_m;
    return FailAt(StartNode(node, request, overlap->second), StartPath(request, overlap->second),
                  RobotAt(first) + " and " + RobotAt(second) + " overlap at start: centres " + FormatShort(apart_m) +
                      " m apart, their bodies need " + FormatShort(needed_m) + " m",
                  diagnostics);
  }
  // A drone flying at its top speed must be able to stop before the far
  // wall from the arena's middle: the safety filter brakes for the walls,
  // but an arena narrower than two stopping distances and a body leaves a
  // drone nowhere to go at speed (docs/scenarios.md, "Drones").
  const auto drone = std::find_if(scenario.robots.begin(), scenario.robots.end(),
                                  [](const RobotSpec& robot) { return robot.kind == world::RobotKind::kDrone; });
  if (drone != scenario.robots.end()) {
    const world::KindSpec& spec = scenario.drone;
    const double needed_m = 2 * (spec.body_radius_m + world::StoppingDistanceM(spec));
    const double side_m = std::min(scenario.arena.width_m, scenario.arena.height_m);
    if (side_m < needed_m) {
      const int index = static_cast<int>(drone - scenario.robots.begin());
      return FailAt(StartNode(node, request, index), StartPath(request, index),
                    "robot " + std::to_string(drone->id) + " is a drone, and the arena (" +
                        FormatNumber(scenario.arena.width_m) + " m x " + FormatNumber(scenario.arena.height_m) +
                        " m) is too small for its stopping distance: at " + FormatShort(spec.max_speed_mps) +
                        " m/s it needs " + FormatShort(world::StoppingDistanceM(spec)) +
                        " m to stop, so each side must be at least 2 x (radius + stopping distance) = " +
                        FormatShort(needed_m) + " m; use a larger arena or a slower drone (kinds.drone)",
                    diagnostics);
    }
  }
  return true;
}

}  // namespace syrof::lab::scenario
