/* march: the reference solution of assignments/march. Every robot runs
 * this code, each in its own process.
 *
 * The robots stand in a row along the x axis, SPACING_M apart, robot 0
 * (the lowest id) in front. The row marches to the right until its front
 * reaches FRONT_MARGIN_M from the right wall, and must stay a row, each
 * robot in its slot, at every epoch.
 *
 * Under FSYNC the obvious plan works: in every epoch the front robot steps
 * STEP_M forward and every other robot steps to its slot behind where the
 * front robot will be; all move at once, so the row holds. Under SSYNC the
 * scheduler may leave a robot out of an epoch: the others step on without
 * it, and if it is left out again the next epoch it falls two steps behind.
 *
 * So the front robot steps only when the row is in place: every member
 * within SETTLED_M of its slot behind the front robot. A robot left out
 * falls at most one step behind (or, when the front robot was left out,
 * the others stand one step ahead of their slots); the next epoch the row
 * is not in place, the front robot waits, and the others go back to their
 * slots. Every robot computes the same plan from the map: whether the front
 * steps is the global state (0 or 1). In AUTONOMOUS epochs it holds still. */
#include <math.h>

#include "syrof/app.h"

#define SPACING_M 0.6f       /* between slots along the row */
#define STEP_M 0.2f          /* the front robot's step in one epoch */
#define SETTLED_M 0.08f      /* a member this close to its slot is in place */
#define FRONT_MARGIN_M 0.6f  /* where the front stops: this far from the right wall */
#define MAX_ROBOTS 64

static syrof_app_info me; /* this robot's facts; globals are per robot */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  const size_t n = map->member_count;
  if (map->mode != SYROF_MODE_COOPERATIVE || n > MAX_ROBOTS) return 0; /* hold still */

  /* The front robot is the first member (members come in increasing id
   * order); a member's rank is its place in the row. */
  const float front_x = map->members[0].x_mm / 1000.0f, front_y = map->members[0].y_mm / 1000.0f;
  const float goal_x = me.arena_width_m - FRONT_MARGIN_M;
  int in_place = 1;
  size_t self = 0;
  for (size_t i = 0; i < n; ++i) {
    const float slot_x = front_x - (float)i * SPACING_M;
    const float x = map->members[i].x_mm / 1000.0f, y = map->members[i].y_mm / 1000.0f;
    if (hypotf(x - slot_x, y - front_y) > SETTLED_M) in_place = 0;
    if (map->members[i].id == map->self_id) self = i;
  }
  const float left = goal_x - front_x;
  const int steps = in_place && left > 0.01f;
  const float next_front_x = front_x + (steps ? (left < STEP_M ? left : STEP_M) : 0.0f);

  const float target_x = next_front_x - (float)self * SPACING_M;
  const float x = map->members[self].x_mm / 1000.0f, y = map->members[self].y_mm / 1000.0f;
  const float length = hypotf(target_x - x, front_y - y);
  if (length < 0.01f) return (uint8_t)steps;
  const float seconds = 0.8f * (float)me.maneuver_ms / 1000.0f;
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = target_x;
  command->y_m = front_y;
  command->speed_mps = length / seconds < me.max_speed_mps ? length / seconds : me.max_speed_mps;
  return (uint8_t)steps;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("march_reference", app_init, app_new_round, app_end_of_round)
