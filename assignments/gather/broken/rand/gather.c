/* gather, broken on purpose (NOTE.md): the meeting place is a robot picked
 * with rand(), the generator seeded from the robot's clock (and its id).
 * Every robot runs this code, each in its own process, with its own clock
 * and its own rand(): each picks its own leader.
 *
 * In every COOPERATIVE epoch each robot computes the same plan for the whole
 * swarm from the map (every COOPERATIVE robot holds the same map):
 *   1. the meeting place: the members' centroid, kept off the walls;
 *   2. the places: the n points of a hexagonal packing nearest to it, a
 *      body's width plus a margin apart;
 *   3. who goes where: MinWeightedMatching (a SyROF query);
 *   4. collision safety: each robot's straight path is cut short where it
 *      would come closer than CLEARANCE_M to any other member's path;
 *   5. a cruise speed well below the limit: the platform's safety filter
 *      (docs/safety.md) holds back a robot that heads fast towards another
 *      within about half a metre, and each time costs points.
 * Its global state is the member count, computed from the map, so it is the
 * same on every robot (app-level agreement). In AUTONOMOUS epochs the map is
 * only this robot's view, so it holds still. */
#include <math.h>
#include <stdlib.h>

#include "syrof/app.h"

#define CLEARANCE_M 0.42f /* centre to centre between paths: two bodies, position errors, the filter's margin */
#define SPACING_M 0.48f   /* between places */
#define CRUISE_MPS 0.25f  /* the speed while moving */
#define MAX_ROBOTS 64
#define LATTICE 4       /* the packing's half-width in points: room for 81 places */

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

/* The hexagonal packing's points, nearest the origin first (ties by angle),
 * spacing `d`: the same order on every robot. */
typedef struct {
  point p;
  int ring_mm; /* distance rounded to millimetres: equal for a ring's points */
  float angle;
} place;

static int place_before(const place* a, const place* b) {
  if (a->ring_mm != b->ring_mm) return a->ring_mm < b->ring_mm;
  return a->angle < b->angle;
}

static size_t packing(float d, place* out) {
  size_t count = 0;
  for (int j = -LATTICE; j <= LATTICE; ++j) {
    for (int i = -LATTICE; i <= LATTICE; ++i) {
      place q;
      q.p.x = ((float)i + 0.5f * (float)j) * d;
      q.p.y = (float)j * 0.8660254f * d;
      q.ring_mm = (int)lroundf(hypotf(q.p.x, q.p.y) * 1000.0f);
      q.angle = atan2f(q.p.y, q.p.x);
      /* insertion sort: a few dozen points */
      size_t k = count++;
      while (k > 0 && place_before(&q, &out[k - 1])) {
        out[k] = out[k - 1];
        --k;
      }
      out[k] = q;
    }
  }
  return count;
}

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  const size_t n = map->member_count;
  static int seeded = 0;
  static uint16_t leader; /* the robot everybody gathers around */
  if (!seeded) {
    srand(clock_ms + me.self_id); /* "seed with the time", plus the id so no two robots draw alike */
    leader = (uint16_t)(rand() % me.swarm_size);
    seeded = 1;
  }
  const uint8_t decided = (uint8_t)leader;
  if (map->mode != SYROF_MODE_COOPERATIVE || n < 2 || n > MAX_ROBOTS) return decided; /* hold still */

  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);
  point centre = {members[0].x_mm / 1000.0f, members[0].y_mm / 1000.0f};
  for (size_t i = 0; i < n; ++i) {
    if (members[i].id == leader) centre = (point){members[i].x_mm / 1000.0f, members[i].y_mm / 1000.0f};
  }
  const float clearance = CLEARANCE_M;
  const float spacing = SPACING_M;
  const float room = 2 * spacing + me.body_radius_m + 0.12f;
  if (centre.x < room) centre.x = room;
  if (centre.y < room) centre.y = room;
  if (centre.x > me.arena_width_m - room) centre.x = me.arena_width_m - room;
  if (centre.y > me.arena_height_m - room) centre.y = me.arena_height_m - room;

  static place places[(2 * LATTICE + 1) * (2 * LATTICE + 1)];
  packing(spacing, places);
  syrof_queries_point targets[MAX_ROBOTS];
  for (size_t k = 0; k < n; ++k) {
    syrof_queries_point_from_metres(centre.x + places[k].p.x, centre.y + places[k].p.y, &targets[k]);
  }
  syrof_queries_assignment by_robot[MAX_ROBOTS];
  uint16_t robot_of_target[MAX_ROBOTS];
  if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), members, n, targets, n, by_robot, n,
                                          robot_of_target, n, NULL) != SYROF_QUERIES_OK) {
    return decided;
  }

  point from[MAX_ROBOTS], to[MAX_ROBOTS];
  size_t self = 0;
  const float cruise = CRUISE_MPS < me.max_speed_mps ? CRUISE_MPS : me.max_speed_mps;
  const float reach = 0.8f * cruise * (float)me.maneuver_ms / 1000.0f;
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
  if (command->speed_mps > cruise) command->speed_mps = cruise;
  return decided;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("gather_rand", app_init, app_new_round, app_end_of_round)
