/* strongest: the reference solution of assignments/strongest. Every robot
 * runs this code, each in its own process.
 *
 * Each robot's charge is a private input (syrofAppInput("charge")): only it
 * knows its own. It tells the others in its payload, two bytes big-endian
 * (README.md, "Messages"), set in init: the platform freezes the payload
 * with the robot's snapshot, so the others see it in the next epoch's map.
 *
 * In every COOPERATIVE epoch each robot computes the same plan for the
 * whole swarm from the map (every COOPERATIVE robot holds the same map,
 * payloads included):
 *   1. the strongest member: the largest charge in the members' payloads,
 *      the lowest id on a tie; while some member's payload is not in the
 *      map yet (a robot that has just joined), nobody moves;
 *   2. the meeting place: the strongest member, which stays where it is;
 *      the others go to the points of a hexagonal packing around it, a
 *      body's width plus a margin apart, the nearest ones inside the arena;
 *   3. who goes where: MinWeightedMatching (a SyROF query) for the others;
 *   4. collision safety: robots take turns (the strongest first, then by
 *      id), each going as far along its path as keeps it CLEARANCE_M from
 *      the robots before it, moving at the same time, and from those after
 *      it, standing;
 *   5. a cruise speed well below the limit (the safety filter holds back a
 *      robot that heads fast towards another, and each time costs points).
 * Its global state is the strongest member's id (STATE_UNDECIDED while a
 * payload is missing), computed from the map, so it is the same on every
 * robot (app-level agreement). In AUTONOMOUS epochs the map is only this
 * robot's view, so it holds still. Each epoch's map decides afresh: a
 * strongest robot that crashed is no member, and the next one is met. */
#include <math.h>

#include "syrof/app.h"

#define CLEARANCE_M 0.47f /* centre to centre while moving: two bodies, position errors, the filter's margin */
#define SPACING_M 0.52f   /* between places */
#define PASSING_M 0.45f   /* centre to centre when passing a robot that stands: two bodies, the filter's disc */
#define PASSING_MPS 0.08f /* the speed within NEAR_M of another robot */
#define NEAR_M 0.7f       /* centre to centre: closer than this, go slowly */
#define CRUISE_MPS 0.15f  /* the speed while moving */
#define MAX_ROBOTS 64
#define LATTICE 4       /* the packing's half-width in points: room for 81 places */
#define CHARGE_BYTES 2  /* the message: the charge, 0 .. 65535, big-endian */
#define STATE_UNDECIDED 255

static syrof_app_info me; /* this robot's facts; globals are per robot */

typedef struct {
  float x, y;
} point;

/* The least distance between two robots moving at once, each in a straight
 * line at a constant speed over the same time: one from a to b, the other
 * from c to d. */
static float moving_distance(point a, point b, point c, point d) {
  const float px = a.x - c.x, py = a.y - c.y;                         /* apart at the start */
  const float vx = (b.x - a.x) - (d.x - c.x), vy = (b.y - a.y) - (d.y - c.y); /* relative motion */
  const float vv = vx * vx + vy * vy;
  float s = vv > 0 ? -(px * vx + py * vy) / vv : 0;
  s = s < 0 ? 0 : (s > 1 ? 1 : s);
  return hypotf(px + s * vx, py + s * vy);
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
  double charge = 0;
  (void)syrofAppInput("charge", &charge);
  const long whole = lround(charge < 0 ? 0 : (charge > 65535 ? 65535 : charge));
  const uint8_t message[CHARGE_BYTES] = {(uint8_t)(whole >> 8), (uint8_t)(whole & 0xFF)};
  sendMessageData(message, sizeof message);
  return STATE_UNDECIDED;
}

/* The index of the member with the largest charge in its payload (the
 * lowest id on a tie: members come in increasing id), or -1 while some
 * member's payload is not in the map. */
static int strongest_member(const syrof_ldmap* map) {
  int best = -1;
  long best_charge = -1;
  for (size_t i = 0; i < map->member_count; ++i) {
    const syrof_member_state* member = &map->members[i];
    if (member->payload_length != CHARGE_BYTES) return -1;
    const long charge = ((long)member->payload[0] << 8) | member->payload[1];
    if (charge > best_charge) {
      best_charge = charge;
      best = (int)i;
    }
  }
  return best;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  const size_t n = map->member_count;
  if (map->mode != SYROF_MODE_COOPERATIVE || n < 2 || n > MAX_ROBOTS) return STATE_UNDECIDED; /* hold still */
  const int top = strongest_member(map);
  if (top < 0) return STATE_UNDECIDED; /* a payload is missing: wait for the next epoch's map */
  const uint8_t decided = (uint8_t)map->members[top].id; /* from the map alone: the same on every robot */

  /* The meeting place: the strongest member, which stays where it is; the
   * others take the points of a packing around it nearest to it that lie
   * inside the arena with room for a body, matched to them. */
  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);
  const point centre = {members[top].x_mm / 1000.0f, members[top].y_mm / 1000.0f};
  const float clearance = CLEARANCE_M;
  const float spacing = SPACING_M;
  const float margin = me.body_radius_m + 0.12f;
  static place places[(2 * LATTICE + 1) * (2 * LATTICE + 1)];
  const size_t place_count = packing(spacing, places);
  syrof_queries_point targets[MAX_ROBOTS];
  syrof_queries_member others[MAX_ROBOTS];
  size_t other_count = 0;
  for (size_t i = 0; i < n; ++i) {
    if ((int)i != top) others[other_count++] = members[i];
  }
  size_t target_count = 0;
  for (size_t k = 1; k < place_count && target_count < other_count; ++k) {
    const point p = {centre.x + places[k].p.x, centre.y + places[k].p.y};
    if (p.x < margin || p.y < margin || p.x > me.arena_width_m - margin || p.y > me.arena_height_m - margin) continue;
    syrof_queries_point_from_metres(p.x, p.y, &targets[target_count++]);
  }
  if (target_count < other_count) return decided; /* no room around it: hold still */
  syrof_queries_assignment by_other[MAX_ROBOTS];
  uint16_t other_of_target[MAX_ROBOTS];
  if (syrof_queries_min_weighted_matching(syrofQueriesWorkspace(), others, other_count, targets, other_count,
                                          by_other, other_count, other_of_target, other_count, NULL) != SYROF_QUERIES_OK) {
    return decided;
  }
  syrof_queries_point target_of[MAX_ROBOTS];
  target_of[top] = (syrof_queries_point){members[top].x_mm, members[top].y_mm};
  for (size_t i = 0, k = 0; i < n; ++i) {
    if ((int)i != top) target_of[i] = targets[by_other[k++].target_index];
  }

  point from[MAX_ROBOTS], to[MAX_ROBOTS];
  size_t self = 0;
  const float cruise = CRUISE_MPS < me.max_speed_mps ? CRUISE_MPS : me.max_speed_mps;
  const float reach = 0.8f * cruise * (float)me.maneuver_ms / 1000.0f;
  const float slow_reach = 0.8f * PASSING_MPS * (float)me.maneuver_ms / 1000.0f;
  for (size_t i = 0; i < n; ++i) {
    const syrof_queries_point target = target_of[i];
    from[i] = (point){members[i].x_mm / 1000.0f, members[i].y_mm / 1000.0f};
    to[i] = (point){target.x_mm / 1000.0f, target.y_mm / 1000.0f};
    const float length = hypotf(to[i].x - from[i].x, to[i].y - from[i].y);
    if (length > reach) {
      to[i].x = from[i].x + (to[i].x - from[i].x) * reach / length;
      to[i].y = from[i].y + (to[i].y - from[i].y) * reach / length;
    }
    if (members[i].id == map->self_id) self = i;
  }

  /* Collision safety, the same plan on every robot: robots take their turn
   * in order (the strongest first, then by id); each goes as far along its
   * path as it can while it stays CLEARANCE_M (or, if already closer, as far
   * as it is) from every robot that went before, moving along its own cut
   * path at the same time, and from every robot still to come, standing. */
  size_t order[MAX_ROBOTS];
  order[0] = (size_t)top;
  for (size_t i = 0, k = 1; i < n; ++i) {
    if ((int)i != top) order[k++] = i;
  }
  point end_of[MAX_ROBOTS];
  for (size_t i = 0; i < n; ++i) end_of[i] = from[i];
  for (size_t turn = 0; turn < n; ++turn) {
    const size_t i = order[turn];
    float low = 0, high = 1;
    for (int step = 0; step < 20; ++step) {
      const float t = (low + high) / 2;
      const point end = {from[i].x + t * (to[i].x - from[i].x), from[i].y + t * (to[i].y - from[i].y)};
      int clear = 1;
      for (size_t j = 0; j < n && clear; ++j) {
        if (j == i) continue;
        /* A robot that stands this maneuver may be passed closer, slowly. */
        const int standing = end_of[j].x == from[j].x && end_of[j].y == from[j].y;
        const float wanted = standing ? PASSING_M : clearance;
        const float start_apart = hypotf(from[i].x - from[j].x, from[i].y - from[j].y);
        const float least = start_apart < wanted ? start_apart - 0.001f : wanted;
        if (moving_distance(from[i], end, from[j], end_of[j]) < least) clear = 0;
      }
      if (clear) low = t; else high = t;
    }
    /* Coming within NEAR_M of another robot (passing it, or arriving next
     * to it): only as far as PASSING_MPS takes it in the maneuver, so that
     * it comes slowly and the safety filter need not hold it back. */
    float passing = 1;
    for (size_t j = 0; j < n; ++j) {
      const point end = {from[i].x + low * (to[i].x - from[i].x), from[i].y + low * (to[i].y - from[i].y)};
      if (j != i && moving_distance(from[i], end, from[j], end_of[j]) < NEAR_M) passing = slow_reach;
    }
    const float length = low * hypotf(to[i].x - from[i].x, to[i].y - from[i].y);
    if (length > passing) low *= passing / length;
    end_of[i] = (point){from[i].x + low * (to[i].x - from[i].x), from[i].y + low * (to[i].y - from[i].y)};
  }
  const point end = end_of[self];
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

SYROF_APP_DEFINE("strongest_reference", app_init, app_new_round, app_end_of_round)
