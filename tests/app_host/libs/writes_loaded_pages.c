/* Writes 128 MiB of a global, one byte a page, while it loads, and each of
 * those pages again in init. A copy of a held host shares them
 * copy-on-write: unless the copy takes them over before its hello, its init
 * takes 32768 page faults under the CPU budget, which a fresh host paid
 * while it loaded. */
#include <stddef.h>

#include "syrof/app.h"

#define PAGES 32768
#define PAGE_BYTES 4096

static volatile unsigned char pages[(size_t)PAGES * PAGE_BYTES];

__attribute__((constructor)) static void WriteWhileLoading(void) {
  for (size_t page = 0; page < PAGES; ++page) pages[page * PAGE_BYTES] = 1;
}

static uint8_t WritesInit(const syrof_app_info* info) {
  for (size_t page = 0; page < PAGES; ++page) pages[page * PAGE_BYTES] = (unsigned char)(info->self_id + 2);
  return pages[0];
}

static uint8_t WritesNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)ldmap;
  (void)clock_ms;
  return state;
}

static uint8_t WritesEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("writes_loaded_pages", WritesInit, WritesNewRound, WritesEndOfRound)
