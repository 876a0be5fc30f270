/* leader_follow, broken/fixed_leader (NOTE.md): the reference with one
 * mistake: robot 0 is taken to be the leader, always. While robot 0 is in
 * the map this is the reference; once it crashes, the others wait for it
 * for ever.
 *
 * The leader is robot 0.
 * It drives the README's route, at most STEP_M further along it per epoch.
 * The others form a column behind it along the route: slot k lies k x
 * SPACING_M behind the leader's next place, measured along the route (and
 * before the route's start, along its first leg extended backwards).
 * In every COOPERATIVE epoch each robot computes the same plan for the whole
 * swarm from the map:
 *   1. the leader and how far along the route it stands (its map position
 *      projected onto the route), its next place STEP_M further on;
 *   2. the followers' slots, and who goes where: MinWeightedMatching;
 *   3. every member's move, planned so that no two bodies come closer than
 *      two radii plus a margin (plan_moves, below).
 * Its global state is the leader's id, a decision every robot takes from
 * the map alone. In AUTONOMOUS epochs the map is only this robot's view, so
 * it holds still. */
#include <math.h>

#include "syrof/app.h"

#define MARGIN_M 0.25f      /* room between bodies: covers position errors, and the safety filter (docs/safety.md) never brakes */
#define WALL_MARGIN_M 0.08f /* room kept from the walls */
#define SPACING_M 0.6f  /* between consecutive robots of the column, along the route */
#define STEP_M 0.13f    /* the leader's advance per epoch: at most SPACING_M - (2R + MARGIN_M) - 0.02 */
#define MAX_ROBOTS 64
#define ROUTE_POINTS 4

static syrof_app_info me; /* this robot's facts; globals are per robot */

typedef struct {
  float x, y;
} point;

/* The route (README), in metres. */
static const point route[ROUTE_POINTS] = {{4.6f, 1.0f}, {6.2f, 1.0f}, {6.2f, 4.0f}, {4.0f, 4.0f}};

static float leg_length(int leg) {
  return hypotf(route[leg + 1].x - route[leg].x, route[leg + 1].y - route[leg].y);
}

/* The route's point `s` metres from its start: before the start along the
 * first leg extended backwards, past the end its end. */
static point route_point(float s) {
  if (s < 0) {
    const float length = leg_length(0);
    return (point){route[0].x + s * (route[1].x - route[0].x) / length,
                   route[0].y + s * (route[1].y - route[0].y) / length};
  }
  for (int leg = 0; leg + 1 < ROUTE_POINTS; ++leg) {
    const float length = leg_length(leg);
    if (s <= length) {
      return (point){route[leg].x + s * (route[leg + 1].x - route[leg].x) / length,
                     route[leg].y + s * (route[leg + 1].y - route[leg].y) / length};
    }
    s -= length;
  }
  return route[ROUTE_POINTS - 1];
}

static float route_length(void) {
  float total = 0;
  for (int leg = 0; leg + 1 < ROUTE_POINTS; ++leg) total += leg_length(leg);
  return total;
}

/* How far along the route the point of the route nearest `p` lies. */
static float route_position(point p) {
  float best_distance = INFINITY, best_s = 0, start = 0;
  for (int leg = 0; leg + 1 < ROUTE_POINTS; ++leg) {
    const point a = route[leg], b = route[leg + 1];
    const float length = leg_length(leg);
    float t = ((p.x - a.x) * (b.x - a.x) + (p.y - a.y) * (b.y - a.y)) / (length * length);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    const float distance = hypotf(p.x - (a.x + t * (b.x - a.x)), p.y - (a.y + t * (b.y - a.y)));
    if (distance < best_distance) {
      best_distance = distance;
      best_s = start + t * length;
    }
    start += length;
  }
  return best_s;
}

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
  const float reach = 0.8f * me.max_speed_mps * (float)me.maneuver_ms / 1000.0f;
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

  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);
  const uint16_t leader_id = 0; /* robot 0 leads */
  const uint8_t decided = (uint8_t)leader_id;

  /* 1. The leader's next place along the route. */
  point from[MAX_ROBOTS], to[MAX_ROBOTS], end[MAX_ROBOTS];
  size_t leader = n, self = 0;
  for (size_t i = 0; i < n; ++i) {
    from[i] = (point){members[i].x_mm / 1000.0f, members[i].y_mm / 1000.0f};
    to[i] = from[i];
    if (members[i].id == leader_id) leader = i;
    if (members[i].id == map->self_id) self = i;
  }
  if (leader == n) return decided; /* the leader is not in the map yet: wait for it */
  float next = route_position(from[leader]) + STEP_M;
  if (next > route_length()) next = route_length();
  to[leader] = route_point(next);

  /* 2. The column's slots behind it, and the followers matched to them. */
  syrof_queries_member followers[MAX_ROBOTS];
  size_t follower_index[MAX_ROBOTS], follower_count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (i == leader) continue;
    follower_index[follower_count] = i;
    followers[follower_count++] = members[i];
  }
  if (follower_count > 0) {
    syrof_queries_point slots[MAX_ROBOTS];
    for (size_t k = 0; k < follower_count; ++k) {
      const point slot = route_point(next - (float)(k + 1) * SPACING_M);
      syrof_queries_point_from_metres(slot.x, slot.y, &slots[k]);
    }
    syrof_queries_assignment by_follower[MAX_ROBOTS];
    uint16_t follower_of_slot[MAX_ROBOTS];
    if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), followers, follower_count, slots, follower_count,
                                            by_follower, follower_count, follower_of_slot, follower_count,
                                            NULL) != SYROF_QUERIES_OK) {
      return decided;
    }
    for (size_t k = 0; k < follower_count; ++k) {
      const syrof_queries_point slot = slots[by_follower[k].target_index];
      to[follower_index[k]] = (point){slot.x_mm / 1000.0f, slot.y_mm / 1000.0f};
    }
  }

  /* 3. Every member's move, and this robot's own driven. */
  plan_moves(n, from, to, end);
  drive(command, from[self], end[self]);
  return decided;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("leader_follow_fixed_leader", app_init, app_new_round, app_end_of_round)
