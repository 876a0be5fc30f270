#include "syrof/app.h"
static uint8_t Init(const syrof_app_info* info) {
  (void)info;
  return 0;
}
static uint8_t NewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)ldmap;
  (void)clock_ms;
  return state;
}
static uint8_t EndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}
/* As a library built against a later syrof/app.h would say. */
const syrof_app_descriptor* syrof_app_entry(void) {
  static const syrof_app_descriptor descriptor = {SYROF_APP_ABI_VERSION + 1, "future", Init, NewRound, EndOfRound};
  return &descriptor;
}
