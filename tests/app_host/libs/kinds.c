/* An app that reads the robots' kinds: its own from init's info, and every
 * member's from the map (syrof_member_state's kind). It says its own kind
 * in its log, and at epoch 3 the kind of every member it holds; its payload
 * carries the members' kinds, one byte each (up to the payload's 9), so the
 * replay shows them in-process and hosted alike. No globals: built into the
 * test (in-process CAbiApp, one copy for every robot) it behaves as hosted. */
#include <stdio.h>

#include "syrof/app.h"

static const char* KindName(uint8_t kind) {
  switch (kind) {
    case SYROF_KIND_OMNI: return "omni";
    case SYROF_KIND_ROVER: return "rover";
    case SYROF_KIND_DRONE: return "drone";
    case SYROF_KIND_UNKNOWN: return "unknown";
  }
  return "?";
}

static uint8_t KindsInit(const syrof_app_info* info) {
  printf("robot %u is a %s\n", (unsigned)info->self_id, KindName(info->kind));
  return 0;
}

static uint8_t KindsNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t state,
                             uint32_t clock_ms) {
  (void)command;
  (void)clock_ms;
  uint8_t payload[SYROF_APP_MAX_PAYLOAD_BYTES] = {0};
  uint16_t count = ldmap->member_count < SYROF_APP_MAX_PAYLOAD_BYTES ? ldmap->member_count
                                                                       : (uint16_t)SYROF_APP_MAX_PAYLOAD_BYTES;
  for (uint16_t i = 0; i < count; ++i) payload[i] = (uint8_t)(0x10 * ldmap->members[i].id + ldmap->members[i].kind);
  (void)sendMessageData(payload, count);
  if (ldmap->epoch == 3) {
    printf("epoch 3:");
    for (uint16_t i = 0; i < ldmap->member_count; ++i) {
      printf(" %u %s", (unsigned)ldmap->members[i].id, KindName(ldmap->members[i].kind));
    }
    printf("\n");
  }
  return state;
}

static uint8_t KindsEndOfRound(const syrof_ldmap* ldmap, uint8_t state, uint32_t clock_ms) {
  (void)ldmap;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("kinds", KindsInit, KindsNewRound, KindsEndOfRound)
