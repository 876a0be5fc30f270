/* A constructor that maps shared memory (MAP_SHARED | MAP_ANONYMOUS) for a
 * counter; each new_round counts in it and in a plain global and sends
 * both. A fresh host per robot starts both at 0; copies of one held host
 * would share the mapping and see each other's counts. */
#include <sys/mman.h>

#include "syrof/app.h"

static volatile uint8_t* shared = 0;
static uint8_t own = 0;

__attribute__((constructor)) static void MapOnLoad(void) {
  void* map = mmap(0, 4096, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (map != MAP_FAILED) shared = (volatile uint8_t*)map;
}

static uint8_t CountInit(const syrof_app_info* info) {
  (void)info;
  return shared != 0 ? 1 : 0;
}

static uint8_t CountNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)ldmap;
  (void)clock_ms;
  ++own;
  if (shared != 0) ++*shared;
  const uint8_t payload[2] = {shared != 0 ? *shared : 0, own};
  (void)sendMessageData(payload, sizeof payload);
  return state;
}

static uint8_t CountEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("shared_counter", CountInit, CountNewRound, CountEndOfRound)
