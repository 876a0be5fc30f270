/* Holds still; robot 1 dereferences NULL in its second newRound. */
#include <stddef.h>
#include "syrof/app.h"
static int rounds = 0;
static uint8_t Init(const syrof_app_info* info) { (void)info; return 0; }
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command, (void)clock_ms;
  if (ldmap->self_id == 1 && ++rounds == 2) {
    volatile int* volatile nowhere = NULL;
    *nowhere = 1;
  }
  return state;
}
static uint8_t EndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap, (void)clock_ms;
  return state;
}
SYROF_APP_DEFINE("robot1_crashes", Init, NewRound, EndOfRound)
