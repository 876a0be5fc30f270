/* 40 sendMessageData calls in one new_round (more than one reply frame
 * holds), alternating accepted and refused, then a NULL payload. */
#include "syrof/app.h"

static uint8_t ManyInit(const syrof_app_info* info) {
  (void)info;
  return 0;
}

static uint8_t ManyNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)ldmap;
  (void)clock_ms;
  uint8_t bytes[SYROF_APP_MAX_PAYLOAD_BYTES + 20] = {0};
  for (int i = 0; i < 40; ++i) {
    bytes[0] = (uint8_t)i;
    const size_t length = (i % 2 == 0) ? (size_t)(1 + i % SYROF_APP_MAX_PAYLOAD_BYTES) : SYROF_APP_MAX_PAYLOAD_BYTES + 1 + (size_t)i;
    const int result = sendMessageData(bytes, length);
    if (result != ((i % 2 == 0) ? SYROF_APP_OK : SYROF_APP_PAYLOAD_TOO_LONG)) return 0xEE;
  }
  if (sendMessageData(0, 3) != SYROF_APP_NULL_ARGUMENT) return 0xEF;
  return (uint8_t)(state + 40);
}

static uint8_t ManyEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("many_payloads", ManyInit, ManyNewRound, ManyEndOfRound)
