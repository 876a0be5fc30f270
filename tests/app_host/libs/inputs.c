/* An app that reads its robot's private input (syrofAppInput) and tells the
 * others in its payload: every robot reads "charge" (scenario `inputs`),
 * puts it in its payload in hundredths with a bit per check of the statuses
 * (a missing name, NULL arguments, an overlong name, a parameter's name),
 * and drives to x = charge. It reads the input in every callback, keeping
 * nothing in globals, so that built into the test (in-process CAbiApp, one
 * copy of the globals for every robot) it behaves as in its own host. */
#include <stdio.h>
#include <string.h>

#include "syrof/app.h"

static uint8_t Checks(void) {
  uint8_t checks = 0;
  double missing = 42;
  if (syrofAppInput("no_such_input", &missing) == SYROF_APP_NO_SUCH_INPUT && missing == 42) checks |= 1;
  if (syrofAppInput(NULL, &missing) == SYROF_APP_NULL_ARGUMENT) checks |= 2;
  if (syrofAppInput("charge", NULL) == SYROF_APP_NULL_ARGUMENT) checks |= 4;
  static char overlong[300];
  memset(overlong, 'a', sizeof overlong - 1);
  if (syrofAppInput(overlong, &missing) == SYROF_APP_NO_SUCH_INPUT) checks |= 8;
  /* A parameter is not an input, nor an input a parameter. */
  if (syrofAppInput("speed_mps", &missing) == SYROF_APP_NO_SUCH_INPUT) checks |= 16;
  if (syrofAppParameter("charge", &missing) == SYROF_APP_NO_SUCH_PARAMETER) checks |= 32;
  return checks;
}

static uint8_t InputsInit(const syrof_app_info* info) {
  double charge = -1;
  const int status = syrofAppInput("charge", &charge);
  const uint8_t checks = Checks();
  printf("robot %u: charge %.3f (status %d), checks %u\n", (unsigned)info->self_id, charge, status,
         (unsigned)checks);
  return checks;
}

static uint8_t InputsNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state,
                              uint32_t clock_ms) {
  (void)clock_ms;
  double charge = 0;
  (void)syrofAppInput("charge", &charge);
  const int hundredths = (int)(charge * 100.0 + 0.5);
  const uint8_t payload[3] = {state, (uint8_t)hundredths, (uint8_t)(hundredths >> 8)};
  (void)sendMessageData(payload, sizeof payload);
  for (uint16_t i = 0; i < ldmap->member_count; ++i) {
    if (ldmap->members[i].id != ldmap->self_id) continue;
    command->kind = SYROF_COMMAND_MOVE_TO;
    command->x_m = (float)(0.5 + charge);
    command->y_m = (float)ldmap->members[i].y_mm / 1000.0f;
    command->speed_mps = 0.2f;
  }
  return state;
}

static uint8_t InputsEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("inputs", InputsInit, InputsNewRound, InputsEndOfRound)
