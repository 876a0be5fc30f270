#include "syrof/lab/apps/formation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "syrof/lab/apps/catalog.h"

namespace syrof::lab::apps {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

double Param(std::string_view app, const std::map<std::string, double>& params, std::string_view name) {
  return ParamValue(*FindBuiltinApp(app), params, name);
}

// `value` moved into [low, high]; the middle of the range when it is empty.
double ClampOrMiddle(double value, double low, double high) {
  if (low > high) return (low + high) / 2.0;
  return std::clamp(value, low, high);
}

// One lattice point i a + j b, a = (1, 0), b = (1/2, sqrt(3)/2), with its
// squared distance in units of spacing^2 (exact: i^2 + i j + j^2), which
// orders points without rounding.
struct LatticePoint {
  int64_t squared_units = 0;
  double angle_rad = 0;  // in [0, 2 pi), from +x
  double x = 0;
  double y = 0;
};

std::vector<LatticePoint> NearestLatticePoints(size_t count) {
  // Ring k of the lattice has 6k points at distances k sqrt(3)/2 .. k, so
  // rings 0 .. K hold 1 + 3K(K+1) points and every point nearer than the
  // farthest of them lies within ring ceil(K / (sqrt(3)/2)) < 2K + 1.
  int64_t rings = 0;
  while (static_cast<size_t>(1 + 3 * rings * (rings + 1)) < count) ++rings;
  const int64_t reach = 2 * rings + 1;
  std::vector<LatticePoint> points;
  for (int64_t i = -reach; i <= reach; ++i) {
    for (int64_t j = -reach; j <= reach; ++j) {
      LatticePoint point;
      point.squared_units = i * i + i * j + j * j;
      point.x = static_cast<double>(i) + static_cast<double>(j) / 2.0;
      point.y = static_cast<double>(j) * std::numbers::sqrt3 / 2.0;
      point.angle_rad = point.squared_units == 0 ? 0.0 : std::atan2(point.y, point.x);
      if (point.angle_rad < 0) point.angle_rad += kTwoPi;
      points.push_back(point);
    }
  }
  std::sort(points.begin(), points.end(), [](const LatticePoint& a, const LatticePoint& b) {
    if (a.squared_units != b.squared_units) return a.squared_units < b.squared_units;
    return a.angle_rad < b.angle_rad;
  });
  points.resize(std::min(points.size(), count));
  return points;
}

}  // namespace

GatherParams ReadGatherParams(const std::map<std::string, double>& params) {
  GatherParams out;
  out.gap_m = Param("gather", params, "gap_m");
  out.tolerance_m = Param("gather", params, "tolerance_m");
  out.margin_m = Param("gather", params, "margin_m");
  return out;
}

CircleParams ReadCircleParams(const std::map<std::string, double>& params) {
  CircleParams out;
  out.radius_m = Param("circle", params, "radius_m");
  out.centre_x_m = Param("circle", params, "centre_x_m");
  out.centre_y_m = Param("circle", params, "centre_y_m");
  out.tolerance_m = Param("circle", params, "tolerance_m");
  out.margin_m = Param("circle", params, "margin_m");
  return out;
}

LeaderFollowParams ReadLeaderFollowParams(const std::map<std::string, double>& params) {
  LeaderFollowParams out;
  out.speed_mps = Param("leader_follow", params, "speed_mps");
  out.spacing_m = Param("leader_follow", params, "spacing_m");
  out.path_radius_m = Param("leader_follow", params, "path_radius_m");
  out.tolerance_m = Param("leader_follow", params, "tolerance_m");
  out.margin_m = Param("leader_follow", params, "margin_m");
  return out;
}

Position ClampIntoArena(Position position, ArenaSize arena, double body_radius_m, double margin_m) {
  const double keep_off_m = body_radius_m + margin_m;
  return {ClampOrMiddle(position.x_m, keep_off_m, arena.width_m - keep_off_m),
          ClampOrMiddle(position.y_m, keep_off_m, arena.height_m - keep_off_m)};
}

double GatherSpacingM(const GatherParams& params, double body_radius_m) {
  return 2.0 * body_radius_m + std::max(params.gap_m, params.margin_m + kPlanSlackM);
}

std::vector<Position> HexSlots(size_t count, double spacing_m) {
  std::vector<Position> slots;
  slots.reserve(count);
  for (const LatticePoint& point : NearestLatticePoints(count)) {
    slots.push_back({point.x * spacing_m, point.y * spacing_m});
  }
  return slots;
}

double HexRingRadiusM(size_t count, double spacing_m) {
  const std::vector<LatticePoint> points = NearestLatticePoints(count);
  if (points.empty()) return 0.0;
  return std::sqrt(static_cast<double>(points.back().squared_units)) * spacing_m;
}

std::vector<Position> GatherSlots(Position centre, size_t count, const GatherParams& params, ArenaSize arena,
                                  double body_radius_m) {
  const double spacing_m = GatherSpacingM(params, body_radius_m);
  const double ring_m = HexRingRadiusM(count, spacing_m);
  const Position clamped = ClampIntoArena(centre, arena, body_radius_m + ring_m, params.margin_m);
  std::vector<Position> slots = HexSlots(count, spacing_m);
  for (Position& slot : slots) {
    slot.x_m += clamped.x_m;
    slot.y_m += clamped.y_m;
  }
  return slots;
}

CircleFormation MakeCircleFormation(const CircleParams& params, size_t count, ArenaSize arena, double body_radius_m) {
  double radius_m = params.radius_m;
  if (count >= 2) {
    const double chord_m = 2.0 * body_radius_m + params.margin_m + kPlanSlackM;
    radius_m = std::max(radius_m, chord_m / (2.0 * std::sin(std::numbers::pi / static_cast<double>(count))));
  }
  const double keep_off_m = body_radius_m + params.margin_m;
  const double largest_m = std::min(arena.width_m, arena.height_m) / 2.0 - keep_off_m;
  radius_m = std::max(0.0, std::min(radius_m, largest_m));
  const Position wanted{params.centre_x_m < 0 ? arena.width_m / 2.0 : params.centre_x_m,
                        params.centre_y_m < 0 ? arena.height_m / 2.0 : params.centre_y_m};
  return {ClampIntoArena(wanted, arena, body_radius_m + radius_m, params.margin_m), radius_m};
}

std::vector<Position> CircleTargets(const CircleParams& params, size_t count, ArenaSize arena, double body_radius_m) {
  const CircleFormation circle = MakeCircleFormation(params, count, arena, body_radius_m);
  std::vector<Position> targets;
  targets.reserve(count);
  for (size_t k = 0; k < count; ++k) {
    const double angle_rad = kTwoPi * static_cast<double>(k) / static_cast<double>(count);
    targets.push_back({circle.centre.x_m + circle.radius_m * std::cos(angle_rad),
                       circle.centre.y_m + circle.radius_m * std::sin(angle_rad)});
  }
  return targets;
}

LeaderPath MakeLeaderPath(const LeaderFollowParams& params, size_t count, ArenaSize arena, double body_radius_m) {
  LeaderPath path;
  path.centre = {arena.width_m / 2.0, arena.height_m / 2.0};
  const double largest_m = std::min(arena.width_m, arena.height_m) / 2.0 - body_radius_m - params.margin_m;
  path.radius_m = std::max(0.0, std::min(params.path_radius_m, largest_m));
  if (path.radius_m <= 0.0) return path;
  path.slot_angle_rad = 2.0 * std::asin(std::min(1.0, params.spacing_m / (2.0 * path.radius_m)));
  if (count >= 1) path.slot_angle_rad = std::min(path.slot_angle_rad, kTwoPi / static_cast<double>(count));
  return path;
}

double LeaderStepM(const LeaderFollowParams& params, double body_radius_m, double maneuver_s) {
  const double room_m = params.spacing_m - 2.0 * body_radius_m - params.margin_m - kPlanSlackM - kFilterGrowthM;
  return std::max(0.0, std::min(params.speed_mps * maneuver_s, room_m));
}

double PathAngleRad(const LeaderPath& path, Position position) {
  const double dx = position.x_m - path.centre.x_m;
  const double dy = position.y_m - path.centre.y_m;
  if (dx == 0.0 && dy == 0.0) return 0.0;
  return std::atan2(dy, dx);
}

Position PathPoint(const LeaderPath& path, double angle_rad) {
  return {path.centre.x_m + path.radius_m * std::cos(angle_rad), path.centre.y_m + path.radius_m * std::sin(angle_rad)};
}

std::vector<Position> FollowerSlots(const LeaderPath& path, double leader_angle_rad, size_t follower_count) {
  std::vector<Position> slots;
  slots.reserve(follower_count);
  for (size_t k = 0; k < follower_count; ++k) {
    slots.push_back(PathPoint(path, leader_angle_rad - static_cast<double>(k + 1) * path.slot_angle_rad));
  }
  return slots;
}

}  // namespace syrof::lab::apps
