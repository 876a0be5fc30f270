/* Prints while it loads (stdout, buffered, and stderr) and counts its
 * rounds in a global it sends: every copy of one held host must start as a
 * fresh host does, its count at 0 and its log opening with the load's
 * lines. */
#include <stdio.h>

#include "syrof/app.h"

static uint8_t rounds = 0;

__attribute__((constructor)) static void SayLoaded(void) {
  printf("loaded (stdout)\n");
  fprintf(stderr, "loaded (stderr)\n");
}

static uint8_t RoundsInit(const syrof_app_info* info) {
  printf("init of robot %u\n", (unsigned)info->self_id);
  return 0;
}

static uint8_t RoundsNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)clock_ms;
  ++rounds;
  printf("round %u of robot %u\n", (unsigned)rounds, (unsigned)ldmap->self_id);
  const uint8_t payload[1] = {rounds};
  (void)sendMessageData(payload, sizeof payload);
  return state;
}

static uint8_t RoundsEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("counts_rounds", RoundsInit, RoundsNewRound, RoundsEndOfRound)
