/* coverage: your app (assignments/coverage/README.md). Every robot runs this
 * code, each in its own process, with its own copy of every variable.
 *
 * As it stands it builds, loads and keeps every robot where it is: it covers
 * nothing. Fill in the TODOs. */
#include <math.h>

#include "syrof/app.h"

#define BORDER_M 0.5f /* the area to cover is the arena less this border */
#define CELL_M 0.25f  /* in cells of this size: a robot visits a cell when the cell's centre is under its body */

static syrof_app_info me; /* this robot's facts (arena, body radius, speed limit) */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)state;
  (void)clock_ms;
  const int n = map->member_count;
  if (map->mode != SYROF_MODE_COOPERATIVE) return (uint8_t)n; /* only this robot's view: hold still */

  /* This robot's rank: its place in the member list (increasing ids). */
  int rank = 0;
  while (rank < n && map->members[rank].id != map->self_id) ++rank;

  /* TODO: the rank-th of n strips of the area; the next waypoint of a sweep
   * of it; a MOVE_TO towards it, at most max_speed_mps, cut short before
   * other members (command->kind = SYROF_COMMAND_MOVE_TO, x_m, y_m,
   * speed_mps). Left as STOP, the robot holds still. */
  return (uint8_t)n; /* the global state: computed from the map, so every robot returns the same */
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("coverage", app_init, app_new_round, app_end_of_round)
