// Where robots start: grid, circle and seeded random placement, and the
// start checks (inside the arena, no two bodies overlapping).
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::scenario {

// What the placement rules need besides the arena and the kinds.
struct PlacementRequest {
  Placement placement = Placement::kGrid;
  int count = 0;
  world::RobotKind kind = world::RobotKind::kOmni;  // every robot's kind, except explicit poses
  double spacing_m = 0.5;             // grid
  double centre_x_m = 0;              // grid, circle
  double centre_y_m = 0;
  double radius_m = 1;                // circle
  double min_separation_m = 0.3;      // random: between body surfaces
  std::vector<RobotSpec> poses;       // explicit: at least `count`
};

// Draws per robot before random placement gives up.
inline constexpr int kMaxPlacementTries = 1000;

// Fills `robots` with `request.count` robots, ids 0.., by the request's
// rule. Grid: ceil(sqrt(n)) columns, row-major by id from the lower left,
// the block centred on the centre, heading 0. Circle: robot i at angle
// 2 pi i / n, facing outwards. Random: uniform with the body inside the
// walls, each at least min_separation_m from the bodies placed before it,
// heading uniform; the generator is seeded from `seed` alone. Explicit: the
// first `count` poses. Returns the id random placement could not place
// within kMaxPlacementTries draws, or nullopt on success.
std::optional<int> PlaceRobots(const PlacementRequest& request, const Scenario& scenario, uint64_t seed,
                               std::vector<RobotSpec>& robots);

// The first robot whose body is not inside the arena's walls.
std::optional<int> FirstOutsideArena(const Scenario& scenario);

// The first pair (by the second robot's id, then the first's) whose bodies
// overlap: centres closer than the sum of their body radii.
std::optional<std::pair<int, int>> FirstOverlap(const Scenario& scenario);

}  // namespace syrof::lab::scenario
