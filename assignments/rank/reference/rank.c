/* rank: the reference solution of assignments/rank. Every robot runs this
 * code, each in its own process.
 *
 * The goal: the robots on a horizontal line through the arena's centre,
 * SPACING_M apart, in increasing order of their private keys from left to
 * right (ties by id). A robot's key is a private input
 * (syrofAppInput("key")): only it knows its own, so it tells the others in
 * its payload, two bytes big-endian (README.md, "Messages"), set in init;
 * the others see it in the next epoch's map. While some member's payload is
 * not in the map yet (a robot that has just joined), nobody moves: its rank,
 * and so every column, is unknown.
 *
 * Robot k (the member of rank k) belongs in column x_k = centre - (n-1)/2 S
 * + k S. Going straight there would cross other robots' paths, so every
 * epoch each robot works out, from the map alone (the same on every
 * COOPERATIVE robot, payloads included), which of three phases the swarm is
 * in:
 *   2. every robot is in its column: all move vertically onto the line
 *      (each in its own column; columns are S apart, so no two paths meet);
 *   1. else, every robot is in a lane of its own (lane j for the j-th lowest
 *      robot, lanes S apart): all move horizontally to their columns, each
 *      in its own lane;
 *   0. else: all move vertically to their lanes, keeping their order, with
 *      every move scaled by the same factor, so the robots stay at least as
 *      far apart as at the start or the end of the step.
 * Phases only go forward while the robots keep to their lanes and columns,
 * and a robot pushed out of place sends the swarm back a phase, which
 * repairs it. The cruise speeds stay well below the limit: the platform's
 * safety filter (docs/safety.md) holds back a robot that heads fast towards
 * another within about half a metre, and each time costs points.
 * Its global state is the phase and the member count, computed from the
 * map, so it is the same on every robot (app-level agreement). In
 * AUTONOMOUS epochs the map is only this robot's view, so it holds still. */
#include <math.h>

#include "syrof/app.h"

#define SPACING_M 0.45f       /* between neighbours on the line (README.md), and between lanes */
#define IN_PLACE_M 0.1f       /* how near a lane or a column counts as in it */
#define SORT_CRUISE_MPS 0.25f /* phase 0, when robots may share a column */
#define CRUISE_MPS 0.25f      /* phases 1 and 2, every robot in its own lane or column */
#define WALL_ROOM_M 0.35f     /* phase 0 keeps this far from the side walls */
#define MAX_ROBOTS 64
#define KEY_BYTES 2           /* the message: the key, 0 .. 65535, big-endian */
#define STATE_WAITING 255     /* a payload is missing: nobody moves */

static syrof_app_info me; /* this robot's facts; globals are per robot */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  double key = 0;
  (void)syrofAppInput("key", &key);
  const long whole = lround(key < 0 ? 0 : (key > 65535 ? 65535 : key));
  const uint8_t message[KEY_BYTES] = {(uint8_t)(whole >> 8), (uint8_t)(whole & 0xFF)};
  sendMessageData(message, sizeof message);
  return STATE_WAITING;
}

/* Each member's rank by the key in its payload (ties by id: members come in
 * increasing id); false while some member's payload is not in the map. */
static int rank_members(const syrof_ldmap* map, size_t* rank) {
  long key[MAX_ROBOTS];
  for (size_t k = 0; k < map->member_count; ++k) {
    const syrof_member_state* member = &map->members[k];
    if (member->payload_length != KEY_BYTES) return 0;
    key[k] = ((long)member->payload[0] << 8) | member->payload[1];
  }
  for (size_t k = 0; k < map->member_count; ++k) {
    rank[k] = 0;
    for (size_t j = 0; j < map->member_count; ++j) {
      if (key[j] < key[k] || (key[j] == key[k] && j < k)) ++rank[k];
    }
  }
  return 1;
}

static float x_of(const syrof_member_state* m) { return m->x_mm / 1000.0f; }
static float y_of(const syrof_member_state* m) { return m->y_mm / 1000.0f; }

/* Where slot k of n lies along an axis centred on `middle`. */
static float slot(size_t k, size_t n, float middle) { return middle + ((float)k - (float)(n - 1) / 2.0f) * SPACING_M; }

/* x kept WALL_ROOM_M from the side walls: the safety filter limits a robot
 * whose body is near a wall, even moving along it. */
static float away_from_walls(float x, float width) {
  if (x < WALL_ROOM_M) return WALL_ROOM_M;
  if (x > width - WALL_ROOM_M) return width - WALL_ROOM_M;
  return x;
}

static void move_to(syrof_car_command* command, float from_x, float from_y, float x, float y, float scale,
                    float cruise) {
  x = from_x + (x - from_x) * scale;
  y = from_y + (y - from_y) * scale;
  const float length = hypotf(x - from_x, y - from_y);
  if (length < 0.005f) return;
  const float seconds = 0.8f * (float)me.maneuver_ms / 1000.0f;
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = x;
  command->y_m = y;
  command->speed_mps = length / seconds < cruise ? length / seconds : cruise;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  const size_t n = map->member_count;
  if (map->mode != SYROF_MODE_COOPERATIVE || n < 2 || n > MAX_ROBOTS) return (uint8_t)n; /* hold still */
  const syrof_member_state* m = map->members; /* robot k's column is slot column[k], its rank by key */
  size_t column[MAX_ROBOTS];
  if (!rank_members(map, column)) return STATE_WAITING; /* a key is unknown: wait for the next epoch's map */
  const float centre_x = me.arena_width_m / 2, centre_y = me.arena_height_m / 2;
  const float cruise = CRUISE_MPS < me.max_speed_mps ? CRUISE_MPS : me.max_speed_mps;
  const float sort_cruise = SORT_CRUISE_MPS < me.max_speed_mps ? SORT_CRUISE_MPS : me.max_speed_mps;

  /* lane_of[k]: robot k's rank from the bottom (ties by id) */
  size_t lane_of[MAX_ROBOTS];
  for (size_t k = 0; k < n; ++k) {
    lane_of[k] = 0;
    for (size_t j = 0; j < n; ++j) {
      if (m[j].y_mm < m[k].y_mm || (m[j].y_mm == m[k].y_mm && j < k)) ++lane_of[k];
    }
  }
  int in_columns = 1, in_lanes = 1;
  size_t self = 0;
  for (size_t k = 0; k < n; ++k) {
    if (fabsf(x_of(&m[k]) - slot(column[k], n, centre_x)) > IN_PLACE_M) in_columns = 0;
    if (fabsf(y_of(&m[k]) - slot(lane_of[k], n, centre_y)) > IN_PLACE_M) in_lanes = 0;
    if (m[k].id == map->self_id) self = k;
  }
  const int phase = in_columns ? 2 : (in_lanes ? 1 : 0);
  const uint8_t decided = (uint8_t)(phase * 64 + n); /* from the map alone */
  const float x = x_of(&m[self]), y = y_of(&m[self]);

  if (phase == 2) {
    move_to(command, x, y, slot(column[self], n, centre_x), centre_y, 1.0f, cruise);
  } else if (phase == 1) {
    move_to(command, x, y, slot(column[self], n, centre_x), slot(lane_of[self], n, centre_y), 1.0f, cruise);
  } else {
    /* every robot's vertical move to its lane, all scaled alike */
    const float reach = 0.8f * sort_cruise * (float)me.maneuver_ms / 1000.0f;
    float longest = 0;
    for (size_t k = 0; k < n; ++k) {
      const float length = fabsf(slot(lane_of[k], n, centre_y) - y_of(&m[k]));
      if (length > longest) longest = length;
    }
    const float scale = longest > reach ? reach / longest : 1.0f;
    move_to(command, x, y, away_from_walls(x, me.arena_width_m), slot(lane_of[self], n, centre_y), scale, sort_cruise);
  }
  return decided;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("rank_reference", app_init, app_new_round, app_end_of_round)
