/* The app the app-host benchmark runs both ways: as a library in the host
 * and linked in (CAbiApp). Some real work per call: the members for the
 * queries, the leader, the enclosing circle, a payload, a move. */
#include "syrof/app.h"

static syrof_queries_member members[SYROF_MAX_SWARM_SIZE];

static uint8_t BenchInit(const syrof_app_info* info) {
  (void)info;
  return 0;
}

static uint8_t BenchNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  const size_t count = syrofMembersForQueries(ldmap, members);
  uint16_t leader = 0;
  syrof_queries_circle circle = {0};
  (void)syrof_queries_leader(members, count, &leader);
  if (syrof_queries_shortest_enclosing_circle(syrofQueriesWorkspace(), members, count, &circle) == SYROF_QUERIES_OK &&
      leader != ldmap->self_id) {
    command->kind = SYROF_COMMAND_MOVE_TO;
    command->x_m = circle.centre_x_m;
    command->y_m = circle.centre_y_m;
    command->speed_mps = 0.1f;
  }
  const uint8_t payload[2] = {(uint8_t)ldmap->self_id, (uint8_t)ldmap->epoch};
  (void)sendMessageData(payload, sizeof payload);
  return (uint8_t)(state + 1);
}

static uint8_t BenchEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("bench_app", BenchInit, BenchNewRound, BenchEndOfRound)
