/* pattern: your solution (README.md). Every robot runs this code, each in
 * its own process. As handed out it builds and loads, but every robot stays
 * where it is.
 *
 * What to write, in newRound, in COOPERATIVE epochs only:
 *   - the pattern: the first n points of `letter`, n the map's member count;
 *   - who goes where: syrof_queries_min_weighted_matching on the map's
 *     members (syrofMembersForQueries) and those points;
 *   - move this robot towards its point, stopping short of the other
 *     robots' paths.
 * Return a global state every robot computes the same from the map (for
 * example a digest of the whole assignment). */
#include <math.h>

#include "syrof/app.h"

#define LETTER_POINTS 12

/* The letter T (README), millimetres: n robots take its first n points. */
static const syrof_queries_point letter[LETTER_POINTS] = {
    {1500, 3800}, {2000, 3800}, {2500, 3800}, {3000, 3800}, {3500, 3800}, {2500, 3300},
    {2500, 2800}, {2500, 2300}, {2500, 1800}, {2500, 1300}, {1000, 3800}, {4000, 3800}};

static syrof_app_info me; /* this robot's facts; globals are per robot */

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  (void)letter;
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

SYROF_APP_DEFINE("pattern", app_init, app_new_round, app_end_of_round)
