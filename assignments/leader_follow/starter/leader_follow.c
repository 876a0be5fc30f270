/* leader_follow: your solution (README.md). Every robot runs this code,
 * each in its own process. As handed out it builds and loads, but every
 * robot stays where it is.
 *
 * What to write, in newRound, in COOPERATIVE epochs only:
 *   - find the leader with syrof_queries_leader (never assume an id);
 *   - the leader moves at most STEP_M further along the route;
 *   - the others take the column's slots behind it, SPACING_M apart along
 *     the route, assigned with syrof_queries_min_weighted_matching;
 *   - stop short of the other robots' paths.
 * Return a global state every robot computes the same from the map (for
 * example the leader's id). */
#include <math.h>

#include "syrof/app.h"

#define SPACING_M 0.6f
#define STEP_M 0.13f
#define ROUTE_POINTS 4

typedef struct {
  float x, y;
} point;

/* The route (README), in metres. */
static const point route[ROUTE_POINTS] = {{4.6f, 1.0f}, {6.2f, 1.0f}, {6.2f, 4.0f}, {4.0f, 4.0f}};

static syrof_app_info me; /* this robot's facts; globals are per robot */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  (void)route;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)command; /* arrives as STOP: the robot holds still */
  (void)clock_ms;
  if (map->mode != SYROF_MODE_COOPERATIVE) return state;
  /* TODO: plan from the map and set *command for this robot. */
  return state;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("leader_follow", app_init, app_new_round, app_end_of_round)
