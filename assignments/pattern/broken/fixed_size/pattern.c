/* pattern, broken/fixed_size (NOTE.md): the reference with one mistake:
 * it takes the first SWARM_SIZE = 8 points of the letter, the public
 * scenarios' swarm, whatever the map's member count. With more robots
 * the ones the matching leaves without a point stay where they are.
 * In every COOPERATIVE epoch each robot computes the same
 * plan for the whole swarm from the map:
 *   1. who goes where: MinWeightedMatching of the members to the points
 *      (a SyROF query: the same answer on every robot for the same map);
 *   2. every member's move, planned so that no two bodies come closer than
 *      two radii plus a margin (plan_moves, below).
 * Its global state is a digest of the whole assignment, so the robots'
 * shared decision is what app-level agreement compares. In AUTONOMOUS
 * epochs the map is only this robot's view, so it holds still. */
#include <math.h>

#include "syrof/app.h"

#define MARGIN_M 0.25f      /* room between bodies: covers position errors, and the safety filter (docs/safety.md) never brakes */
#define WALL_MARGIN_M 0.08f /* room kept from the walls */
#define MAX_ROBOTS 64
#define LETTER_POINTS 12
#define SWARM_SIZE 8 /* the robots of the public scenarios */

static syrof_app_info me; /* this robot's facts; globals are per robot */

/* The letter T (README): n robots take its first n points. */
static const syrof_queries_point letter[LETTER_POINTS] = {
    {1500, 3800}, {2000, 3800}, {2500, 3800}, {3000, 3800}, {3500, 3800}, {2500, 3300},
    {2500, 2800}, {2500, 2300}, {2500, 1800}, {2500, 1300}, {1000, 3800}, {4000, 3800}};

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

/* ---- Moving without collisions (the same in every robot) ----
 * Every robot plans every member's move, in one fixed order: the member
 * farthest from its target first (ties: lower index first). Each member
 * gets a straight segment from its map position: towards its target, or,
 * when that way is blocked early, turned by 30, 60 or 90 degrees to either
 * side, whichever gets it closest to its target. A segment is allowed when
 *   - against every member planned before: it keeps `clearance` from that
 *     member's segment (or, for two already closer than that, does not come
 *     any closer to it);
 *   - against every member planned after: it keeps `clearance` from that
 *     member's position (the same exception);
 *   - it does not go nearer the walls than a body and the margin.
 * Then whatever two members do along their segments (one stops early,
 * the other is fast), their bodies never come closer than what their
 * segments allow. Each robot drives its own segment. */
static float clearance;

static int allowed_near(float distance_now, float distance) {
  const float limit = distance_now - 0.005f < clearance ? distance_now - 0.005f : clearance;
  return distance >= limit;
}

static float outside_walls(point p) {
  const float low = me.body_radius_m + WALL_MARGIN_M;
  const float high_x = me.arena_width_m - low, high_y = me.arena_height_m - low;
  float out = 0;
  out += p.x < low ? low - p.x : (p.x > high_x ? p.x - high_x : 0);
  out += p.y < low ? low - p.y : (p.y > high_y ? p.y - high_y : 0);
  return out;
}

static void plan_moves(size_t n, const point* from, const point* target, point* end) {
  size_t order[MAX_ROBOTS];
  int planned[MAX_ROBOTS];
  for (size_t i = 0; i < n; ++i) {
    order[i] = i;
    planned[i] = 0;
    end[i] = from[i];
  }
  for (size_t a = 1; a < n; ++a) { /* farthest first; insertion sort keeps equal ones in index order */
    const size_t i = order[a];
    const float d = hypotf(target[i].x - from[i].x, target[i].y - from[i].y);
    size_t b = a;
    while (b > 0 && hypotf(target[order[b - 1]].x - from[order[b - 1]].x, target[order[b - 1]].y - from[order[b - 1]].y) < d) {
      order[b] = order[b - 1];
      --b;
    }
    order[b] = i;
  }
  /* 0.7 of the speed limit, as the reference (docs/safety.md, "Twenty seeds"). */
  const float reach = 0.7f * me.max_speed_mps * (float)me.maneuver_ms / 1000.0f;
  static const float turns_deg[7] = {0, 30, -30, 60, -60, 90, -90};
  for (size_t k = 0; k < n; ++k) {
    const size_t i = order[k];
    const float dx = target[i].x - from[i].x, dy = target[i].y - from[i].y;
    const float distance = hypotf(dx, dy);
    planned[i] = 1;
    if (distance < 0.005f) continue;
    const float length = distance < reach ? distance : reach;
    float best_progress = 0.005f;
    for (int c = 0; c < 7; ++c) {
      const float angle = turns_deg[c] * 3.14159265f / 180.0f;
      const float ux = (dx * cosf(angle) - dy * sinf(angle)) / distance;
      const float uy = (dx * sinf(angle) + dy * cosf(angle)) / distance;
      const point full = {from[i].x + length * ux, from[i].y + length * uy};
      float low = 0, high = 1;
      for (int step = 0; step < 16; ++step) {
        const float t = (low + high) / 2;
        const point e = {from[i].x + t * (full.x - from[i].x), from[i].y + t * (full.y - from[i].y)};
        int ok = outside_walls(e) <= outside_walls(from[i]);
        for (size_t j = 0; j < n && ok; ++j) {
          if (j == i) continue;
          if (planned[j]) {
            ok = allowed_near(point_segment_distance(from[i], from[j], end[j]),
                              segment_distance(from[i], e, from[j], end[j]));
          } else {
            ok = allowed_near(hypotf(from[j].x - from[i].x, from[j].y - from[i].y),
                              point_segment_distance(from[j], from[i], e));
          }
        }
        if (ok) low = t; else high = t;
      }
      const point e = {from[i].x + low * (full.x - from[i].x), from[i].y + low * (full.y - from[i].y)};
      const float progress = distance - hypotf(target[i].x - e.x, target[i].y - e.y);
      if (progress > best_progress + 0.005f) {
        best_progress = progress;
        end[i] = e;
      }
    }
  }
}

/* Drives this robot along its planned segment: MOVE_TO its end, arriving
 * before the maneuver ends. */
static void drive(syrof_car_command* command, point from, point end) {
  const float length = hypotf(end.x - from.x, end.y - from.y);
  if (length < 0.005f) return; /* STOP */
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = end.x;
  command->y_m = end.y;
  command->speed_mps = length / (0.8f * (float)me.maneuver_ms / 1000.0f);
  if (command->speed_mps > me.max_speed_mps) command->speed_mps = me.max_speed_mps;
}

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  clearance = 2 * me.body_radius_m + MARGIN_M;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  const size_t n = map->member_count;
  if (map->mode != SYROF_MODE_COOPERATIVE || n > MAX_ROBOTS) return state; /* hold still */
  const size_t slot_count = SWARM_SIZE; /* the public scenarios' swarm */
  const syrof_queries_point* slots = letter;

  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);
  syrof_queries_assignment by_robot[MAX_ROBOTS];
  uint16_t robot_of_target[LETTER_POINTS];
  if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), members, n, slots, slot_count, by_robot, n,
                                          robot_of_target, slot_count, NULL) != SYROF_QUERIES_OK) {
    return (uint8_t)n;
  }
  /* The shared decision, from the map alone: the same on every COOPERATIVE robot. */
  uint8_t decided = (uint8_t)n;
  for (size_t i = 0; i < n; ++i) decided = (uint8_t)(decided * 31u + by_robot[i].target_index + 1u);

  point from[MAX_ROBOTS], to[MAX_ROBOTS], end[MAX_ROBOTS];
  size_t self = 0;
  for (size_t i = 0; i < n; ++i) {
    from[i] = (point){members[i].x_mm / 1000.0f, members[i].y_mm / 1000.0f};
    to[i] = from[i]; /* a robot without a point stays where it is */
    if (by_robot[i].target_index != SYROF_QUERIES_NO_TARGET) {
      const syrof_queries_point target = slots[by_robot[i].target_index];
      to[i] = (point){target.x_mm / 1000.0f, target.y_mm / 1000.0f};
    }
    if (members[i].id == map->self_id) self = i;
  }
  plan_moves(n, from, to, end);
  drive(command, from[self], end[self]);
  return decided;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("pattern_fixed_size", app_init, app_new_round, app_end_of_round)
