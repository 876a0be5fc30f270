/* keep_formation: the reference solution of assignments/keep_formation.
 * Every robot runs this code, each in its own process.
 *
 * The formation: the current members evenly on a circle around the arena's
 * centre, of radius 0.36 x the arena's smaller side (1.8 m in a 5 m arena).
 * In every COOPERATIVE epoch each robot computes the same plan for the whole
 * swarm from the map (every COOPERATIVE robot holds the same map):
 *   1. n, the map's member count (never the swarm size of init: robots crash
 *      and join, and the map is what the swarm agrees on);
 *   2. the circle's rotation phi that fits where the members stand: the
 *      n-fold mean angle, arg(sum of exp(i n theta)) / n, so a formation that
 *      holds does not move, and after a crash the survivors close the gap
 *      symmetrically (the crashed body ends up in the middle of a gap);
 *   3. the n points phi + 2 pi k / n, and who goes where by
 *      MinWeightedMatching (a SyROF query);
 *   4. collision safety: each robot's straight path is cut short where it
 *      would come closer than two body radii plus a margin to any other
 *      member's path.
 * Its global state is the member count, computed from the map, so it is the
 * same on every robot (app-level agreement). In AUTONOMOUS epochs the map is
 * only this robot's view, so it holds still. A robot that is joining is in
 * no map until the swarm has agreed on it, so nobody plans for it before. */
#include <math.h>

#include "syrof/app.h"

#define MARGIN_M 0.12f  /* extra room between bodies: covers both robots' position errors */
#define SETTLED_M 0.02f /* closer than this to its point, a robot stays put */
#define MAX_ROBOTS 64
#define TWO_PI 6.28318531f

static syrof_app_info me; /* this robot's facts; globals are per robot */

typedef struct {
  float x, y;
} point;

static float point_segment_distance(point p, point a, point b) {
  const float dx = b.x - a.x, dy = b.y - a.y;
  const float length2 = dx * dx + dy * dy;
  float t = length2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / length2 : 0;
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return hypotf(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

static float cross(point o, point a, point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

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
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  const size_t n = map->member_count;
  const uint8_t decided = (uint8_t)n; /* from the map alone: the same on every COOPERATIVE robot */
  if (map->mode != SYROF_MODE_COOPERATIVE || n > MAX_ROBOTS) return decided; /* hold still */

  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);
  const point centre = {me.arena_width_m / 2, me.arena_height_m / 2};
  const float side = me.arena_width_m < me.arena_height_m ? me.arena_width_m : me.arena_height_m;
  const float radius = 0.36f * side;

  /* The rotation that fits the members best: the mean of n x their angles. */
  float sum_sin = 0, sum_cos = 0;
  for (size_t i = 0; i < n; ++i) {
    const float theta = atan2f(members[i].y_mm / 1000.0f - centre.y, members[i].x_mm / 1000.0f - centre.x);
    sum_sin += sinf((float)n * theta);
    sum_cos += cosf((float)n * theta);
  }
  const float phi = sum_sin * sum_sin + sum_cos * sum_cos > 1e-6f ? atan2f(sum_sin, sum_cos) / (float)n : 0.0f;

  syrof_queries_point targets[MAX_ROBOTS];
  for (size_t k = 0; k < n; ++k) {
    const float angle = phi + TWO_PI * (float)k / (float)n;
    syrof_queries_point_from_metres(centre.x + radius * cosf(angle), centre.y + radius * sinf(angle), &targets[k]);
  }
  syrof_queries_assignment by_robot[MAX_ROBOTS];
  uint16_t robot_of_target[MAX_ROBOTS];
  if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), members, n, targets, n, by_robot, n,
                                          robot_of_target, n, NULL) != SYROF_QUERIES_OK) {
    return decided;
  }

  point from[MAX_ROBOTS], to[MAX_ROBOTS];
  size_t self = 0;
  const float reach = 0.8f * me.max_speed_mps * (float)me.maneuver_ms / 1000.0f;
  for (size_t i = 0; i < n; ++i) {
    const syrof_queries_point target = targets[by_robot[i].target_index];
    from[i] = (point){members[i].x_mm / 1000.0f, members[i].y_mm / 1000.0f};
    to[i] = (point){target.x_mm / 1000.0f, target.y_mm / 1000.0f};
    const float length = hypotf(to[i].x - from[i].x, to[i].y - from[i].y);
    if (length < SETTLED_M) {
      to[i] = from[i];
    } else if (length > reach) {
      to[i].x = from[i].x + (to[i].x - from[i].x) * reach / length;
      to[i].y = from[i].y + (to[i].y - from[i].y) * reach / length;
    }
    if (members[i].id == map->self_id) self = i;
  }

  const float clearance = 2 * me.body_radius_m + MARGIN_M;
  float low = 0, high = 1;
  for (int step = 0; step < 20; ++step) {
    const float t = (low + high) / 2;
    const point end = {from[self].x + t * (to[self].x - from[self].x), from[self].y + t * (to[self].y - from[self].y)};
    int clear = 1;
    for (size_t j = 0; j < n && clear; ++j) {
      if (j != self && segment_distance(from[self], end, from[j], to[j]) < clearance) clear = 0;
    }
    if (clear) low = t; else high = t;
  }
  const point end = {from[self].x + low * (to[self].x - from[self].x), from[self].y + low * (to[self].y - from[self].y)};
  const float length = hypotf(end.x - from[self].x, end.y - from[self].y);
  if (length < 0.005f) return decided;
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = end.x;
  command->y_m = end.y;
  command->speed_mps = length / (0.8f * (float)me.maneuver_ms / 1000.0f);
  if (command->speed_mps > me.max_speed_mps) command->speed_mps = me.max_speed_mps;
  return decided;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("keep_formation_reference", app_init, app_new_round, app_end_of_round)
