/* Holds still; its global state is the epoch number. Its bug: it assumes
 * every epoch is COOPERATIVE and reads the map's second member as a
 * neighbour it was promised, so it dereferences NULL when an epoch starts
 * AUTONOMOUS. Only a loss pattern that leaves a robot out makes one. */
#include <stddef.h>
#include "syrof/app.h"
static uint8_t Init(const syrof_app_info* info) { (void)info; return 0; }
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command, (void)clock_ms, (void)state;
  if (ldmap->mode == SYROF_MODE_AUTONOMOUS) {
    volatile int* volatile nowhere = NULL;
    *nowhere = 1;
  }
  return (uint8_t)ldmap->epoch;
}
static uint8_t EndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap, (void)clock_ms;
  return state;
}
SYROF_APP_DEFINE("assumes_cooperative", Init, NewRound, EndOfRound)
