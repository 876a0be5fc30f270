/* rendezvous: the reference solution of assignments/rendezvous. Both
 * robots run this code, each in its own process.
 *
 * The meeting point is the midpoint of where the two robots STARTED. Under
 * FSYNC "move towards the midpoint of where we stand now" finds it: both
 * move in every epoch, by as much, so the midpoint never moves. Under SSYNC
 * the scheduler may activate one robot alone; it moves, and the midpoint of
 * where they stand moves with it. A robot that is activated cannot tell from
 * the positions whether the other has moved already (it sees only where the
 * other stands now).
 *
 * So each robot shows its start on its light, the payload (4 bytes: x and y
 * in millimetres, signed 16-bit, most significant byte first), before it
 * ever moves:
 *   1. its own start not yet on its light (not in the map): put its position
 *      on it, and hold still (it shows from the next epoch's map on);
 *   2. the other's start not on its light: wait, holding still;
 *   3. both starts known: the meeting point M is their midpoint, the same
 *      for both robots whoever moved and whenever; go to the point
 *      HALF_GAP_M from M on its own side of the line between the starts.
 * A light never changes once set, and a robot moves only after its own is
 * set, so a light always says where its robot started, in every schedule.
 * Its global state is how many starts the map shows (0, 1 or 2): from the
 * map alone, the same on every robot. In AUTONOMOUS epochs it holds still. */
#include <math.h>

#include "syrof/app.h"

#define HALF_GAP_M 0.20f /* from the meeting point: the two robots end 0.4 m apart */
#define CRUISE_MPS 0.40f /* the speed while far */
#define LIGHT_BYTES 4

static syrof_app_info me; /* this robot's facts; globals are per robot */

/* The start a member shows on its light; 0 when its light is not set. */
static int light_start(const syrof_member_state* member, float* x, float* y) {
  if (member->payload_length != LIGHT_BYTES) return 0;
  const int16_t x_mm = (int16_t)(((uint16_t)member->payload[0] << 8) | member->payload[1]);
  const int16_t y_mm = (int16_t)(((uint16_t)member->payload[2] << 8) | member->payload[3]);
  *x = x_mm / 1000.0f;
  *y = y_mm / 1000.0f;
  return 1;
}

static void show_start(const syrof_member_state* self) {
  const uint8_t light[LIGHT_BYTES] = {(uint8_t)((uint16_t)self->x_mm >> 8), (uint8_t)self->x_mm,
                                      (uint8_t)((uint16_t)self->y_mm >> 8), (uint8_t)self->y_mm};
  sendMessageData(light, LIGHT_BYTES);
}

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  uint8_t known = 0;
  for (size_t i = 0; i < map->member_count; ++i) known += map->members[i].payload_length == LIGHT_BYTES;
  if (map->mode != SYROF_MODE_COOPERATIVE || map->member_count != 2) return known; /* hold still */

  const syrof_member_state* self = &map->members[0];
  const syrof_member_state* other = &map->members[1];
  if (self->id != map->self_id) {
    self = &map->members[1];
    other = &map->members[0];
  }
  float ax = 0, ay = 0, bx = 0, by = 0;
  if (!light_start(self, &ax, &ay)) {
    show_start(self); /* 1. before any move */
    return known;
  }
  if (!light_start(other, &bx, &by)) return known; /* 2. wait for the other's light */

  /* 3. the midpoint of the starts, and this robot's side of it */
  const float mx = (ax + bx) / 2, my = (ay + by) / 2;
  const float apart = hypotf(ax - bx, ay - by);
  const float ux = apart > 0 ? (ax - bx) / apart : (self->id < other->id ? -1.0f : 1.0f);
  const float uy = apart > 0 ? (ay - by) / apart : 0.0f;
  const float tx = mx + HALF_GAP_M * ux, ty = my + HALF_GAP_M * uy;
  const float x = self->x_mm / 1000.0f, y = self->y_mm / 1000.0f;
  const float length = hypotf(tx - x, ty - y);
  if (length < 0.05f) return known; /* there, within what the estimates tell apart */
  const float seconds = 0.8f * (float)me.maneuver_ms / 1000.0f;
  const float cruise = CRUISE_MPS < me.max_speed_mps ? CRUISE_MPS : me.max_speed_mps;
  const float reach = cruise * seconds;
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = length > reach ? x + (tx - x) * reach / length : tx;
  command->y_m = length > reach ? y + (ty - y) * reach / length : ty;
  command->speed_mps = length > reach ? cruise : length / seconds; /* slow down near the end */
  return known;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("rendezvous_reference", app_init, app_new_round, app_end_of_round)
