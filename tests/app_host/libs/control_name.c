/* An app whose descriptor name holds a terminal escape sequence and a byte
 * that is not UTF-8: the name is printed in run summaries and reports, so
 * the host must not hand it on as it is. */
#include "syrof/app.h"

static uint8_t ControlNameInit(const syrof_app_info* info) {
  (void)info;
  return 0;
}

static uint8_t ControlNameNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state,
                                   uint32_t clock_ms) {
  (void)command;
  (void)ldmap;
  (void)clock_ms;
  return state;
}

static uint8_t ControlNameEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("red\x1b[31m\xff", ControlNameInit, ControlNameNewRound, ControlNameEndOfRound)
