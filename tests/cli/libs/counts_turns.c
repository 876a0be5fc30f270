/* Holds still; its global state counts its own newRound calls. Under FSYNC
 * every robot is called in every epoch and the counts agree; under SSYNC a
 * robot left out of an epoch falls one behind, and its next newRound
 * disagrees with the others'. Only the activation search
 * (syrof search --activations ssync) finds a schedule that shows it. */
#include "syrof/app.h"
static uint8_t Init(const syrof_app_info* info) { (void)info; return 0; }
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command, (void)ldmap, (void)clock_ms;
  return (uint8_t)(state + 1);
}
static uint8_t EndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap, (void)clock_ms;
  return state;
}
SYROF_APP_DEFINE("counts_turns", Init, NewRound, EndOfRound)
