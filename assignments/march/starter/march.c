/* march: your app for assignments/march (README.md says the task). Every
 * robot runs this code, each in its own process.
 *
 * As handed out it builds and loads but does nothing: every robot holds
 * still, so the row never arrives. Fill in app_new_round. */
#include "syrof/app.h"

static syrof_app_info me; /* this robot's facts (id, arena, body, speed limit); globals are per robot */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  return 0;
}

/* Called at the start of every epoch this robot is active in, with the
 * LDMap. Set *command for the maneuver (it arrives as STOP) and return the
 * global state. */
static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)clock_ms;
  if (map->mode != SYROF_MODE_COOPERATIVE) return state; /* the map is only this robot's view: hold still */
  /* TODO: from the map alone, decide whether the front robot (the lowest
   * id) steps forward this epoch, and move this robot to its slot behind
   * where the front robot will be. Under SSYNC a robot may be left out of
   * an epoch: do not let the row step on while a robot is out of place. */
  return state;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("march_starter", app_init, app_new_round, app_end_of_round)
