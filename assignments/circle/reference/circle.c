/* circle: the reference solution of assignments/circle. Every robot runs
 * this code, each in its own process.
 *
 * In every COOPERATIVE epoch each robot computes the same plan for the whole
 * swarm from the map (every COOPERATIVE robot holds the same map):
 *   1. the places: n points evenly spaced on the circle of RADIUS_M around
 *      the arena's centre, the first at angle 0 (n = the map's member count,
 *      so a robot that joins is given a place and the others re-space);
 *   2. who goes where: MinWeightedMatching (a SyROF query);
 *   3. collision safety: each robot's straight path is cut short where it
 *      would come closer than CLEARANCE_M to any other member's path;
 *   4. a cruise speed well below the limit: the platform's safety filter
 *      (docs/safety.md) holds back a robot that heads fast towards another
 *      within about half a metre, and each time costs points.
 * Its global state is the member count, computed from the map, so it is the
 * same on every robot (app-level agreement). In AUTONOMOUS epochs the map is
 * only this robot's view (others' positions may be old, some members may be
 * missing), so it holds still. */
#include <math.h>

#include "syrof/app.h"

#define RADIUS_M 1.2f     /* the circle's radius (README.md) */
#define CLEARANCE_M 0.465f /* centre to centre between paths: two bodies, position errors, the filter's margin and disc growth (four own sigmas, docs/safety.md) */
#define CRUISE_MPS 0.25f  /* the speed while moving */
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

/* This robot's move for the epoch: its own path of the swarm's plan, cut
 * short before it comes within CLEARANCE_M of another robot's path. */
static void move(syrof_car_command* command, const syrof_ldmap* map, const syrof_queries_member* members,
                 const syrof_queries_point* targets, const syrof_queries_assignment* by_robot) {
  const size_t n = map->member_count;
  const float cruise = CRUISE_MPS < me.max_speed_mps ? CRUISE_MPS : me.max_speed_mps;
  const float reach = 0.8f * cruise * (float)me.maneuver_ms / 1000.0f;
  point from[MAX_ROBOTS], to[MAX_ROBOTS];
  size_t self = 0;
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
  float low = 0, high = 1;
  for (int step = 0; step < 20; ++step) {
    const float t = (low + high) / 2;
    const point end = {from[self].x + t * (to[self].x - from[self].x), from[self].y + t * (to[self].y - from[self].y)};
    int clear = 1;
    for (size_t j = 0; j < n && clear; ++j) {
      if (j == self) continue;
      /* Two robots already closer than the clearance (after a join, or each
       * stopped short by the other) may still move, only not closer:
       * otherwise neither ever moves again. */
      const float apart = point_segment_distance(from[self], from[j], to[j]);
      const float limit = apart < CLEARANCE_M ? apart - 0.005f : CLEARANCE_M;
      if (segment_distance(from[self], end, from[j], to[j]) < limit) clear = 0;
    }
    if (clear) low = t; else high = t;
  }
  const point end = {from[self].x + low * (to[self].x - from[self].x), from[self].y + low * (to[self].y - from[self].y)};
  const float length = hypotf(end.x - from[self].x, end.y - from[self].y);
  if (length < 0.005f) return;
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = end.x;
  command->y_m = end.y;
  command->speed_mps = length / (0.8f * (float)me.maneuver_ms / 1000.0f);
  if (command->speed_mps > cruise) command->speed_mps = cruise;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  const size_t n = map->member_count;
  const uint8_t decided = (uint8_t)n; /* from the map alone: the same on every COOPERATIVE robot */
  if (map->mode != SYROF_MODE_COOPERATIVE || n < 2 || n > MAX_ROBOTS) return decided; /* hold still */

  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);
  const point centre = {me.arena_width_m / 2, me.arena_height_m / 2};
  syrof_queries_point targets[MAX_ROBOTS];
  for (size_t k = 0; k < n; ++k) {
    const float angle = TWO_PI * (float)k / (float)n;
    syrof_queries_point_from_metres(centre.x + RADIUS_M * cosf(angle), centre.y + RADIUS_M * sinf(angle), &targets[k]);
  }
  syrof_queries_assignment by_robot[MAX_ROBOTS];
  uint16_t robot_of_target[MAX_ROBOTS];
  if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), members, n, targets, n, by_robot, n,
                                          robot_of_target, n, NULL) != SYROF_QUERIES_OK) {
    return decided;
  }
  move(command, map, members, targets, by_robot);
  return decided;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("circle_reference", app_init, app_new_round, app_end_of_round)
