// {{NAME}}: a SyROF app in C++. Every robot runs this code, each in its own
// process.
//
// What it does: the robots spread evenly on a circle around the swarm's
// centroid. In every COOPERATIVE epoch each robot computes the same plan for
// the whole swarm from the map (every COOPERATIVE robot holds the same map):
//   1. the points: n evenly spaced on a circle around the members' centroid;
//   2. who goes where: MinWeightedMatching (a SyROF query);
//   3. collision safety, taking turns by id: each robot's straight path is
//      cut short where it would come closer than two body radii plus a
//      margin to the whole path of a robot with a lower id, or to where a
//      robot with a higher id stands now (that robot keeps clear of this
//      one's path, or stays put). Of two robots whose paths cross, the lower
//      id goes first and the other waits, so a packed group that must move
//      never blocks itself; two robots already closer than that may still
//      move, only not closer.
// It then drives its own part. In AUTONOMOUS epochs the map is only this
// robot's view, so it holds still (the command arrives as STOP).
//
// The API is plain C (syrof/app.h); C++ is fine around it. Exceptions must
// not leave a callback. docs/apps.md has the API.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "syrof/app.h"

namespace {

// Defaults, replaced in Init by the scenario's params of the same name.
double radius_m = 1.0;   // the circle's radius, raised when the robots do not fit
double margin_m = 0.12;  // extra room between bodies: covers both robots' position errors

syrof_app_info me;  // this robot's facts; globals are per robot

struct Point {
  float x = 0, y = 0;
};

Point Lerp(Point a, Point b, float t) { return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; }
float Distance(Point a, Point b) { return std::hypot(b.x - a.x, b.y - a.y); }

float PointSegmentDistance(Point p, Point a, Point b) {
  const float dx = b.x - a.x, dy = b.y - a.y;
  const float length2 = dx * dx + dy * dy;
  const float t = length2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / length2, 0.0f, 1.0f) : 0.0f;
  return Distance(p, Lerp(a, b, t));
}

float Cross(Point o, Point a, Point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Shortest distance between the segments a-b and c-d (0 when they cross).
float SegmentDistance(Point a, Point b, Point c, Point d) {
  const float d1 = Cross(c, d, a), d2 = Cross(c, d, b), d3 = Cross(a, b, c), d4 = Cross(a, b, d);
  if (d1 * d2 < 0 && d3 * d4 < 0) return 0;
  return std::min({PointSegmentDistance(a, c, d), PointSegmentDistance(b, c, d), PointSegmentDistance(c, a, b),
                   PointSegmentDistance(d, a, b)});
}

uint8_t Init(const syrof_app_info* info) {
  me = *info;
  // SYROF_APP_NO_SUCH_PARAMETER when the scenario gives none: the default stays.
  syrofAppParameter("radius_m", &radius_m);
  syrofAppParameter("margin_m", &margin_m);
  // Goes to this robot's log (out/<scenario>/robots/<id>.log).
  std::printf("robot %u of %u: spreading on a circle of radius %.2f m\n", unsigned{info->self_id},
              unsigned{info->swarm_size}, radius_m);
  std::fflush(stdout);
  return 0;
}

uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t /*clock_ms*/) {
  const size_t n = map->member_count;
  if (map->mode != SYROF_MODE_COOPERATIVE || n < 2) return state;  // hold still

  // 1. n points on a circle around the centroid, inside the arena.
  std::vector<syrof_queries_member> members(n);
  syrofMembersForQueries(map, members.data());
  Point centre;
  for (const syrof_queries_member& member : members) {
    centre.x += member.x_mm / 1000.0f / static_cast<float>(n);
    centre.y += member.y_mm / 1000.0f / static_cast<float>(n);
  }
  const float pi = std::numbers::pi_v<float>;
  const float clearance = 2 * me.body_radius_m + static_cast<float>(margin_m);
  const float radius = std::max(static_cast<float>(radius_m), (clearance + 0.05f) / (2 * std::sin(pi / static_cast<float>(n))));
  const float room = radius + me.body_radius_m + static_cast<float>(margin_m);  // keep the circle off the walls
  centre.x = std::clamp(centre.x, room, std::max(room, me.arena_width_m - room));
  centre.y = std::clamp(centre.y, room, std::max(room, me.arena_height_m - room));
  std::vector<syrof_queries_point> targets(n);
  for (size_t k = 0; k < n; ++k) {
    const float angle = 2 * pi * static_cast<float>(k) / static_cast<float>(n);
    syrof_queries_point_from_metres(centre.x + radius * std::cos(angle), centre.y + radius * std::sin(angle),
                                    &targets[k]);
  }

  // 2. Who goes where: the matching with the shortest longest trip.
  std::vector<syrof_queries_assignment> by_robot(n);
  std::vector<uint16_t> robot_of_target(n);
  if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), members.data(), n, targets.data(), n,
                                          by_robot.data(), n, robot_of_target.data(), n,
                                          nullptr) != SYROF_QUERIES_OK) {
    return state;
  }

  // Every member's path: from where it stands towards its point, no longer
  // than it can drive in 80% of the maneuver.
  const float maneuver_s = static_cast<float>(me.maneuver_ms) / 1000.0f;
  const float reach = 0.8f * me.max_speed_mps * maneuver_s;
  std::vector<Point> from(n), to(n);
  size_t self = 0;
  for (size_t i = 0; i < n; ++i) {
    const syrof_queries_point target = targets[by_robot[i].target_index];
    from[i] = {members[i].x_mm / 1000.0f, members[i].y_mm / 1000.0f};
    to[i] = {target.x_mm / 1000.0f, target.y_mm / 1000.0f};
    const float length = Distance(from[i], to[i]);
    if (length > reach) to[i] = Lerp(from[i], to[i], reach / length);
    if (members[i].id == map->self_id) self = i;
  }

  // 3. Cut this robot's path where it would get too close to a lower id's
  // path or a higher id's place (bisection on the fraction of the path
  // driven): robot j's segment keep_from[j]-keep_to[j], at least limit[j] away.
  std::vector<Point> keep_to(n);
  std::vector<float> limit(n);
  for (size_t j = 0; j < n; ++j) {
    keep_to[j] = members[j].id < map->self_id ? to[j] : from[j];
    // Already closer than the clearance (after a join, or packed at the
    // start): move, only not closer; otherwise neither would ever move.
    const float apart = PointSegmentDistance(from[self], from[j], keep_to[j]);
    limit[j] = apart < clearance ? apart - 0.005f : clearance;
  }
  auto clear = [&](float t) {
    const Point end = Lerp(from[self], to[self], t);
    for (size_t j = 0; j < n; ++j) {
      if (j != self && SegmentDistance(from[self], end, from[j], keep_to[j]) < limit[j]) return false;
    }
    return true;
  };
  float low = 0, high = 1;
  for (int step = 0; step < 20; ++step) {
    const float t = (low + high) / 2;
    (clear(t) ? low : high) = t;
  }
  const Point end = Lerp(from[self], to[self], low);
  const float length = Distance(from[self], end);
  if (length < 0.005f) return state;  // nothing worth a move
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = end.x;
  command->y_m = end.y;
  command->speed_mps = std::min(me.max_speed_mps, length / (0.8f * maneuver_s));
  return state;
}

uint8_t EndOfRound(const syrof_ldmap* /*map*/, uint8_t state, uint32_t /*clock_ms*/) { return state; }

}  // namespace

extern "C" {
SYROF_APP_DEFINE("{{NAME}}", Init, NewRound, EndOfRound)
}
