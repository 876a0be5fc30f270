#include "placement.h"

#include <cmath>
#include <numbers>

#include "syrof/base/split_mix64.h"

namespace syrof::lab::scenario {
namespace {

// Random placement draws from its own stream of the scenario seed, so other
// users of the seed (sensors, channel) do not shift it.
constexpr uint64_t kPlacementStream = 0x706c6163656d656eull;  // "placemen"

double Uniform(base::SplitMix64& generator) {
  return static_cast<double>(generator.Next() >> 11) * 0x1.0p-53;  // [0, 1) on a 2^-53 grid
}

double Distance(const RobotSpec& a, const RobotSpec& b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m); }

void PlaceGrid(const PlacementRequest& request, std::vector<RobotSpec>& robots) {
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(request.count))));
  const int rows = (request.count + columns - 1) / columns;
  for (int id = 0; id < request.count; ++id) {
    RobotSpec& robot = robots[id];
    robot.x_m = request.centre_x_m + (id % columns - (columns - 1) / 2.0) * request.spacing_m;
    robot.y_m = request.centre_y_m + (id / columns - (rows - 1) / 2.0) * request.spacing_m;
    robot.heading_rad = 0;
  }
}

void PlaceCircle(const PlacementRequest& request, std::vector<RobotSpec>& robots) {
  for (int id = 0; id < request.count; ++id) {
    const double angle = 2 * std::numbers::pi * id / request.count;
    RobotSpec& robot = robots[id];
    robot.x_m = request.centre_x_m + request.radius_m * std::cos(angle);
    robot.y_m = request.centre_y_m + request.radius_m * std::sin(angle);
    robot.heading_rad = angle > std::numbers::pi ? angle - 2 * std::numbers::pi : angle;
  }
}

std::optional<int> PlaceRandom(const PlacementRequest& request, const Scenario& scenario, uint64_t seed,
                               std::vector<RobotSpec>& robots) {
  base::SplitMix64 generator(base::SplitMix64Hash(seed ^ kPlacementStream));
  const double radius_m = scenario.kind_spec(request.kind).body_radius_m;
  const double free_x_m = scenario.arena.width_m - 2 * radius_m;
  const double free_y_m = scenario.arena.height_m - 2 * radius_m;
  if (free_x_m < 0 || free_y_m < 0) return 0;
  for (int id = 0; id < request.count; ++id) {
    RobotSpec& robot = robots[id];
    bool placed = false;
    for (int attempt = 0; attempt < kMaxPlacementTries && !placed; ++attempt) {
      robot.x_m = radius_m + free_x_m * Uniform(generator);
      robot.y_m = radius_m + free_y_m * Uniform(generator);
      placed = true;
      for (int other = 0; other < id && placed; ++other) {
        placed = Distance(robot, robots[other]) >= 2 * radius_m + request.min_separation_m;
      }
    }
    if (!placed) return id;
    robot.heading_rad = std::numbers::pi * (2 * Uniform(generator) - 1);
  }
  return std::nullopt;
}

}  // namespace

std::optional<int> PlaceRobots(const PlacementRequest& request, const Scenario& scenario, uint64_t seed,
                               std::vector<RobotSpec>& robots) {
  robots.assign(request.count, RobotSpec{});
  for (int id = 0; id < request.count; ++id) {
    robots[id].id = static_cast<uint16_t>(id);
    robots[id].kind = request.kind;
  }
  switch (request.placement) {
    case Placement::kGrid:
      PlaceGrid(request, robots);
      return std::nullopt;
    case Placement::kCircle:
      PlaceCircle(request, robots);
      return std::nullopt;
    case Placement::kRandom:
      return PlaceRandom(request, scenario, seed, robots);
    case Placement::kExplicit:
      for (int id = 0; id < request.count; ++id) {
        robots[id] = request.poses[id];
        robots[id].id = static_cast<uint16_t>(id);
      }
      return std::nullopt;
  }
  return std::nullopt;
}

std::optional<int> FirstOutsideArena(const Scenario& scenario) {
  for (const RobotSpec& robot : scenario.robots) {
    const double radius_m = scenario.kind_spec(robot.kind).body_radius_m;
    const bool inside = robot.x_m - radius_m >= 0 && robot.x_m + radius_m <= scenario.arena.width_m &&
                        robot.y_m - radius_m >= 0 && robot.y_m + radius_m <= scenario.arena.height_m;
    if (!inside) return robot.id;
  }
  return std::nullopt;
}

std::optional<std::pair<int, int>> FirstOverlap(const Scenario& scenario) {
  const std::vector<RobotSpec>& robots = scenario.robots;
  for (size_t second = 1; second < robots.size(); ++second) {
    const double second_radius_m = scenario.kind_spec(robots[second].kind).body_radius_m;
    for (size_t first = 0; first < second; ++first) {
      const double reach_m = second_radius_m + scenario.kind_spec(robots[first].kind).body_radius_m;
      if (Distance(robots[first], robots[second]) < reach_m) {
        return std::pair<int, int>(static_cast<int>(first), static_cast<int>(second));
      }
    }
  }
  return std::nullopt;
}

}  // namespace syrof::lab::scenario
