/* Robot 0 loops forever in its first newRound; the others hold still. */
#include "syrof/app.h"
static uint8_t Init(const syrof_app_info* info) { (void)info; return 0; }
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command, (void)clock_ms;
  volatile unsigned long sink = 0;
  while (ldmap->self_id == 0) sink = sink + 1;
  return state;
}
static uint8_t EndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap, (void)clock_ms;
  return state;
}
SYROF_APP_DEFINE("robot0_loops", Init, NewRound, EndOfRound)
