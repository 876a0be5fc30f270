/* rendezvous: your app for assignments/rendezvous (README.md says the
 * task). Both robots run this code, each in its own process.
 *
 * As handed out it builds and loads but does nothing: both robots hold
 * still, so they never meet. Fill in app_new_round. */
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
  /* TODO: meet the other robot at the midpoint of where the two STARTED.
   * Under SSYNC the other robot may have moved already, or may not move
   * this epoch: show your start on your light (sendMessageData, 4 bytes:
   * x_mm and y_mm, signed 16-bit, most significant byte first) before you
   * move, and read the other's from map->members[i].payload. */
  return state;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("rendezvous_starter", app_init, app_new_round, app_end_of_round)
