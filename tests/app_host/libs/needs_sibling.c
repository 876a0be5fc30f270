/* An app that links a library of its own beside it (libsibling.so) and
 * names itself after what that library answers. */
#include "syrof/app.h"

int SiblingAnswer(void);

static uint8_t NeedsSiblingInit(const syrof_app_info* info) {
  (void)info;
  return (uint8_t)SiblingAnswer();
}

static uint8_t NeedsSiblingNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state,
                                    uint32_t clock_ms) {
  (void)command;
  (void)ldmap;
  (void)clock_ms;
  return state;
}

static uint8_t NeedsSiblingEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("needs_sibling", NeedsSiblingInit, NeedsSiblingNewRound, NeedsSiblingEndOfRound)
