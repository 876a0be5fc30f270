/* A well-behaved app that uses everything the platform offers: a global
 * (its own id), sendMessageData (accepted and refused), the queries through
 * the platform's workspace, output, and a command from the map. Built both
 * as a library (the host) and into the test (in-process CAbiApp): the runs
 * must be byte-identical. */
#include <stdio.h>
#include <string.h>

#include "syrof/app.h"

static syrof_queries_member members[SYROF_MAX_SWARM_SIZE];

static uint8_t CoopInit(const syrof_app_info* info) {
  printf("robot %u of %u starts\n", (unsigned)info->self_id, (unsigned)info->swarm_size);
  return 0;
}

static uint8_t CoopNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  const uint16_t my_id = ldmap->self_id;
  const size_t count = syrofMembersForQueries(ldmap, members);
  syrof_queries_circle circle;
  memset(&circle, 0, sizeof circle);
  const syrof_queries_status status =
      syrof_queries_shortest_enclosing_circle(syrofQueriesWorkspace(), members, count, &circle);
  uint16_t leader = 0;
  (void)syrof_queries_leader(members, count, &leader);
  uint8_t payload[3] = {(uint8_t)my_id, (uint8_t)(my_id >> 8), (uint8_t)ldmap->epoch};
  (void)sendMessageData(payload, sizeof payload);
  if (ldmap->epoch % 5 == 0) {
    uint8_t too_long[SYROF_APP_MAX_PAYLOAD_BYTES + 3] = {0};
    (void)sendMessageData(too_long, sizeof too_long);
  }
  if (status == SYROF_QUERIES_OK && my_id != leader) {
    command->kind = SYROF_COMMAND_MOVE_TO;
    command->x_m = circle.centre_x_m;
    command->y_m = circle.centre_y_m;
    command->speed_mps = 0.1f;
  }
  printf("epoch %u at %u ms: %u members, leader %u, ids seen %u\n", (unsigned)ldmap->epoch, (unsigned)clock_ms,
         (unsigned)count, (unsigned)leader, (unsigned)ldmap->self_id);
  return (uint8_t)(state + 1);
}

static uint8_t CoopEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return (uint8_t)(state ^ 0x80);
}

SYROF_APP_DEFINE("cooperative", CoopInit, CoopNewRound, CoopEndOfRound)
