/* {{NAME}}: your app for this assignment (README.md says the task).
 * Every robot runs this code, each in its own process.
 *
 * As handed out it builds and loads but does nothing: every robot holds
 * still, so the goal is never reached. Fill in app_new_round. */
#include "syrof/app.h"

static syrof_app_info me; /* this robot's facts (id, arena, body, speed limit); globals are per robot */
static double radius_m = 1.0; /* the circle's radius; the scenario's app.params may change it */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  syrofAppParameter("radius_m", &radius_m); /* the default stays when the scenario gives none */
  return 0;
}

/* Called at the start of every epoch with the LDMap. Set *command for the
 * maneuver (it arrives as STOP) and return the global state. */
static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)clock_ms;
  if (map->mode != SYROF_MODE_COOPERATIVE) return state; /* the map is only this robot's view: hold still */
  /* TODO: from the map alone, place map->member_count points evenly on a
   * circle of radius_m around the members' centroid, choose who goes where
   * (syrof_queries_min_weighted_matching), and move this robot towards its
   * own point (SYROF_COMMAND_MOVE_TO), stopping short of the others. */
  return state;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("{{NAME}}_starter", app_init, app_new_round, app_end_of_round)
