/* teams: your app for assignments/teams (README.md says the task).
 * Every robot runs this code, each in its own process.
 *
 * As handed out it builds and loads but does nothing: every robot holds
 * still, so the goal is never reached. Tell the others your team
 * (app_init), then fill in app_new_round. */
#include "syrof/app.h"

static syrof_app_info me; /* this robot's facts (id, arena, body, speed limit); globals are per robot */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  double team = 0;
  (void)syrofAppInput("team", &team); /* only this robot knows it */
  /* TODO: put the team in this robot's payload, in the README's format
   * (sendMessageData), so that the others see it in the next epoch's map. */
  return 0;
}

/* Called at the start of every epoch with the LDMap. Set *command for the
 * maneuver (it arrives as STOP) and return the global state. */
static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)clock_ms;
  if (map->mode != SYROF_MODE_COOPERATIVE) return state; /* the map is only this robot's view: hold still */
  /* TODO: read every member's team from its payload
   * (map->members[i].payload), give each team its own place, the teams
   * apart, and bring every robot to its team's place without crossing the
   * others' paths (SYROF_COMMAND_MOVE_TO). */
  return state;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("teams_starter", app_init, app_new_round, app_end_of_round)
