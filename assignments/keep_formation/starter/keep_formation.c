/* keep_formation: your app (assignments/keep_formation/README.md). Every
 * robot runs this code, each in its own process, with its own copy of every
 * variable.
 *
 * As it stands it builds, loads and keeps every robot where it is: no
 * formation. Fill in the TODOs. */
#include <math.h>

#include "syrof/app.h"

#define MAX_ROBOTS 64

static syrof_app_info me; /* this robot's facts (arena, body radius, speed limit) */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)state;
  (void)clock_ms;
  const size_t n = map->member_count; /* the current members: crashed robots have left, joiners are in */
  if (map->mode != SYROF_MODE_COOPERATIVE || n > MAX_ROBOTS) return (uint8_t)n; /* hold still */

  const float centre_x = me.arena_width_m / 2, centre_y = me.arena_height_m / 2;
  const float side = me.arena_width_m < me.arena_height_m ? me.arena_width_m : me.arena_height_m;
  const float radius = 0.36f * side;
  (void)centre_x;
  (void)centre_y;
  (void)radius;

  syrof_queries_member members[MAX_ROBOTS];
  syrofMembersForQueries(map, members);

  /* TODO: n points evenly spaced on the circle (choose their rotation from
   * the map), who goes where (syrof_queries_min_weighted_matching), and a
   * MOVE_TO towards this robot's point, at most max_speed_mps, cut short
   * before the others' paths. Left as STOP, the robot holds still. */
  return (uint8_t)n; /* the global state: computed from the map, so every robot returns the same */
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("keep_formation", app_init, app_new_round, app_end_of_round)
