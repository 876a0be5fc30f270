/* {{NAME}}: a SyROF app. Every robot runs this code, each in its own process.
 *
 * What it does: the robots spread evenly on a circle around the swarm's
 * centroid. In every COOPERATIVE epoch each robot computes the same plan for
 * the whole swarm from the map (every COOPERATIVE robot holds the same map):
 *   1. the points: n evenly spaced on a circle around the members' centroid;
 *   2. who goes where: MinWeightedMatching (a SyROF query);
 *   3. collision safety, taking turns by id: each robot's straight path is
 *      cut short where it would come closer than two body radii plus a
 *      margin to the whole path of a robot with a lower id, or to where a
 *      robot with a higher id stands now (that robot keeps clear of this
 *      one's path, or stays put). Of two robots whose paths cross, the lower
 *      id goes first and the other waits, so a packed group that must move
 *      never blocks itself; two robots already closer than that may still
 *      move, only not closer.
 * It then drives its own part. In AUTONOMOUS epochs the map is only this
 * robot's view, so it holds still (the command arrives as STOP).
 *
 * The radius and margin come from the scenario (app.params in
 * scenario.yaml, read with syrofAppParameter); without them the defaults
 * below stay. Change it: the radius, the shape, the rule. docs/apps.md has
 * the API. */
#include <math.h>
#include <stdio.h>

#include "syrof/app.h"

#define MAX_ROBOTS 64    /* this starter plans for at most this many members */

/* Defaults, replaced in init by the scenario's params of the same name. */
static double radius_m = 1.0;  /* the circle's radius, raised when the robots do not fit */
static double margin_m = 0.12; /* extra room between bodies: covers both robots' position errors */

static syrof_app_info me; /* this robot's facts; globals are per robot */

typedef struct {
  float x, y;
} point;

/* Distance from p to the segment a-b. */
static float point_segment_distance(point p, point a, point b) {
  const float dx = b.x - a.x, dy = b.y - a.y;
  const float length2 = dx * dx + dy * dy;
  float t = length2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / length2 : 0;
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return hypotf(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

static float cross(point o, point a, point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

/* Shortest distance between the segments a-b and c-d (0 when they cross). */
static float segment_distance(point a, point b, point c, point d) {
  const float d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return 0;
  float best = point_segment_distance(a, c, d);
  const float candidates[3] = {point_segment_distance(b, c, d), point_segment_distance(c, a, b),
                               point_segment_distance(d, a, b)};
  for (int i = 0; i < 3; ++i) best = candidates[i] < best ? candidates[i] : best;
  return best;
}

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  /* SYROF_APP_NO_SUCH_PARAMETER when the scenario gives none: the default stays. */
  syrofAppParameter("radius_m", &radius_m);
  syrofAppParameter("margin_m", &margin_m);
  /* Goes to this robot's log (out/<scenario>/robots/<id>.log); flushed at
   * once so it is there even if the robot is stopped later. */
  printf("robot %u of %u: spreading on a circle of radius %.2f m\n", (unsigned)info->self_id,
         (unsigned)info->swarm_size, radius_m);
  fflush(stdout);
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  const size_t n = map->member_count;
  if (map->mode != SYROF_MODE_COOPERATIVE || n < 2 || n > MAX_ROBOTS) return state; /* hold still */

  /* 1. n points on a circle around the centroid, inside the arena. */
  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);
  point centre = {0, 0};
  for (size_t i = 0; i < n; ++i) {
    centre.x += members[i].x_mm / 1000.0f / (float)n;
    centre.y += members[i].y_mm / 1000.0f / (float)n;
  }
  const float pi = 3.14159265f;
  const float clearance = 2 * me.body_radius_m + (float)margin_m;
  float radius = (float)radius_m;
  const float fit = (clearance + 0.05f) / (2 * sinf(pi / (float)n)); /* neighbours this far apart */
  if (radius < fit) radius = fit;
  const float room = radius + me.body_radius_m + (float)margin_m; /* keep the circle off the walls */
  if (centre.x < room) centre.x = room;
  if (centre.y < room) centre.y = room;
  if (centre.x > me.arena_width_m - room) centre.x = me.arena_width_m - room;
  if (centre.y > me.arena_height_m - room) centre.y = me.arena_height_m - room;
  syrof_queries_point targets[MAX_ROBOTS];
  for (size_t k = 0; k < n; ++k) {
    const float angle = 2 * pi * (float)k / (float)n;
    syrof_queries_point_from_metres(centre.x + radius * cosf(angle), centre.y + radius * sinf(angle), &targets[k]);
  }

  /* 2. Who goes where: the matching with the shortest longest trip. */
  syrof_queries_assignment by_robot[MAX_ROBOTS];
  uint16_t robot_of_target[MAX_ROBOTS];
  if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), members, n, targets, n, by_robot, n,
                                          robot_of_target, n, NULL) != SYROF_QUERIES_OK) {
    return state;
  }

  /* Every member's path: from where it stands towards its point, no longer
   * than it can drive in 80% of the maneuver. */
  point from[MAX_ROBOTS], to[MAX_ROBOTS];
  size_t self = 0;
  const float reach = 0.8f * me.max_speed_mps * (float)me.maneuver_ms / 1000.0f;
  for (size_t i = 0; i < n; ++i) {
    const syrof_queries_point target = targets[by_robot[i].target_index];
    from[i] = (point){members[i].x_mm / 1000.0f, members[i].y_mm / 1000.0f};
    to[i] = (point){target.x_mm / 1000.0f, target.y_mm / 1000.0f};
    const float length = hypotf(to[i].x - from[i].x, to[i].y - from[i].y);
    if (length > reach) {
      to[i].x = from[i].x + (to[i].x - from[i].x) * reach / length;
      to[i].y = from[i].y + (to[i].y - from[i].y) * reach / length;
    }
    if (members[i].id == map->self_id) self = i;
  }

  /* 3. Cut this robot's path where it would get too close to a lower id's
   * path or a higher id's place (bisection on the fraction of the path
   * driven): robot j's segment from[j]-keep_to[j], at least limit[j] away. */
  point keep_to[MAX_ROBOTS];
  float limit[MAX_ROBOTS];
  for (size_t j = 0; j < n; ++j) {
    keep_to[j] = members[j].id < map->self_id ? to[j] : from[j];
    /* Already closer than the clearance (after a join, or packed at the
     * start): move, only not closer; otherwise neither would ever move. */
    const float apart = point_segment_distance(from[self], from[j], keep_to[j]);
    limit[j] = apart < clearance ? apart - 0.005f : clearance;
  }
  float low = 0, high = 1;
  for (int step = 0; step < 20; ++step) {
    const float t = (low + high) / 2;
    const point end = {from[self].x + t * (to[self].x - from[self].x), from[self].y + t * (to[self].y - from[self].y)};
    int clear = 1;
    for (size_t j = 0; j < n && clear; ++j) {
      if (j != self && segment_distance(from[self], end, from[j], keep_to[j]) < limit[j]) clear = 0;
    }
    if (clear) low = t; else high = t;
  }
  const point end = {from[self].x + low * (to[self].x - from[self].x), from[self].y + low * (to[self].y - from[self].y)};
  const float length = hypotf(end.x - from[self].x, end.y - from[self].y);
  if (length < 0.005f) return state; /* nothing worth a move */
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = end.x;
  command->y_m = end.y;
  command->speed_mps = length / (0.8f * (float)me.maneuver_ms / 1000.0f);
  if (command->speed_mps > me.max_speed_mps) command->speed_mps = me.max_speed_mps;
  return state;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("{{NAME}}", app_init, app_new_round, app_end_of_round)
