/* An app that reads the scenario's parameters (syrofAppParameter) and acts on
 * them: every robot drives to x = target_x_m (default 0.5) at speed_mps, and
 * puts what it read in its payload: the target in centimetres, and a bit per
 * check of the statuses (a missing name, NULL arguments, an overlong name).
 * Built both as a library (the host) and into the test (in-process CAbiApp):
 * the runs must be byte-identical, and differ from a run without params. */
#include <stdio.h>
#include <string.h>

#include "syrof/app.h"

static double target_x_m = 0.5;
static double speed_mps = 0.1;
static uint8_t checks = 0;

static uint8_t ParamsInit(const syrof_app_info* info) {
  const int target = syrofAppParameter("target_x_m", &target_x_m);
  (void)syrofAppParameter("speed_mps", &speed_mps);
  double missing = 42;
  if (syrofAppParameter("no_such_name", &missing) == SYROF_APP_NO_SUCH_PARAMETER && missing == 42) checks |= 1;
  if (syrofAppParameter(NULL, &missing) == SYROF_APP_NULL_ARGUMENT) checks |= 2;
  if (syrofAppParameter("target_x_m", NULL) == SYROF_APP_NULL_ARGUMENT) checks |= 4;
  static char overlong[300];
  memset(overlong, 'a', sizeof overlong - 1);
  if (syrofAppParameter(overlong, &missing) == SYROF_APP_NO_SUCH_PARAMETER) checks |= 8;
  printf("robot %u: target_x_m %.3f (status %d), speed_mps %.3f, checks %u\n", (unsigned)info->self_id, target_x_m,
         target, speed_mps, (unsigned)checks);
  return checks;
}

static uint8_t ParamsNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state,
                              uint32_t clock_ms) {
  (void)clock_ms;
  const int centimetres = (int)(target_x_m * 100.0 + 0.5);
  const uint8_t payload[3] = {checks, (uint8_t)centimetres, (uint8_t)(centimetres >> 8)};
  (void)sendMessageData(payload, sizeof payload);
  for (uint16_t i = 0; i < ldmap->member_count; ++i) {
    if (ldmap->members[i].id != ldmap->self_id) continue;
    command->kind = SYROF_COMMAND_MOVE_TO;
    command->x_m = (float)target_x_m;
    command->y_m = (float)ldmap->members[i].y_mm / 1000.0f;
    command->speed_mps = (float)speed_mps;
  }
  return state;
}

static uint8_t ParamsEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("parameters", ParamsInit, ParamsNewRound, ParamsEndOfRound)
