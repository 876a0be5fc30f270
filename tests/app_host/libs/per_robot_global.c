/* Stores its id in a global at init and sends it back in every new_round:
 * with one process per robot, each robot keeps its own. */
#include "syrof/app.h"

static uint16_t stored_id = 0xFFFF;

static uint8_t GlobalInit(const syrof_app_info* info) {
  stored_id = info->self_id;
  return 0;
}

static uint8_t GlobalNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)command;
  (void)ldmap;
  (void)clock_ms;
  const uint8_t payload[2] = {(uint8_t)stored_id, (uint8_t)(stored_id >> 8)};
  (void)sendMessageData(payload, sizeof payload);
  return state;
}

static uint8_t GlobalEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("per_robot_global", GlobalInit, GlobalNewRound, GlobalEndOfRound)
