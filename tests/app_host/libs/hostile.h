/* Shared by the hostile test libraries: an app that behaves in init and
 * end_of_round and misbehaves in new_round through MISBEHAVE(ldmap), which
 * each library defines before including this file. */
#ifndef SYROF_TEST_HOSTILE_H
#define SYROF_TEST_HOSTILE_H

#include "syrof/app.h"

static uint8_t hostile_init(const syrof_app_info* info) {
  (void)info;
  return 1;
}

static uint8_t hostile_new_round(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state,
                                 uint32_t clock_ms) {
  (void)command;
  (void)clock_ms;
  MISBEHAVE(ldmap);
  return state;
}

static uint8_t hostile_end_of_round(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("hostile", hostile_init, hostile_new_round, hostile_end_of_round)

#endif
