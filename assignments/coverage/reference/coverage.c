/* coverage: the reference solution of assignments/coverage. Every robot runs
 * this code, each in its own process.
 *
 * The area to cover is the arena less a 0.5 m border, in 0.25 m cells. Its
 * cell columns are "lanes": driving along a lane through the cells' centres
 * visits every cell of that column. In every COOPERATIVE epoch each robot
 * finds its rank (its place in the map's member list, which is in increasing
 * id order) and the member count n, both the same on every robot, and takes
 * the rank-th of n strips of whole lanes. It sweeps its strip lane by lane,
 * left to right, up one lane and down the next (a boustrophedon): a path of
 * legs, whose ends are its waypoints. When the member count or its rank
 * changes (a robot crashed, or one joined), the strips are cut again and
 * every robot starts its new strip.
 *
 * The sweeps move in step. Every robot can compute every member's path (the
 * strips come from the map), so it can see in the map which waypoint each
 * member stands at. A robot at its waypoint k starts its next leg when every
 * member stands at a waypoint, none before its k (a member whose strip is
 * swept stands at its last), and catches up one leg when it sees a member
 * ahead of it (it missed a step while AUTONOMOUS). Strips are side by side,
 * at least two lanes wide, and swept left to right, so neighbours stay at
 * least two lanes (0.5 m) apart; without the step, a robot that fell behind
 * would meet its faster neighbour on adjacent lanes, 0.25 m apart, where the
 * platform's safety filter would have to hold them apart. Collision safety
 * besides: each move is cut short where it would come closer than a body's
 * width plus a margin to another member's position (or, when it already
 * stands closer, closer than it is now).
 *
 * Its global state is the member count, computed from the map, so it is the
 * same on every robot (app-level agreement). In AUTONOMOUS epochs the map is
 * only this robot's view, so it holds still. */
#include <math.h>

#include "syrof/app.h"

#define BORDER_M 0.5f   /* the area is the arena less this border */
#define CELL_M 0.25f    /* the goal's cell size: one lane per cell column */
#define MARGIN_M 0.2f   /* extra room to another robot's body: it may be moving too */
#define ARRIVED_M 0.1f  /* a waypoint this close counts as reached (the estimate wanders a few cm while a robot stands) */
#define MAX_ROBOTS 64

static syrof_app_info me;
static int lane_count;

/* The plan: the cut it belongs to, the lane end every strip starts at, and
 * the waypoint this robot heads for. */
static int plan_rank = -1;
static int plan_members = -1;
static int start_at_bottom = 1;
static int next_waypoint;

static float lane_x(int lane) { return BORDER_M + ((float)lane + 0.5f) * CELL_M; }
static float bottom_y(void) { return BORDER_M + 0.5f * CELL_M; }
static float top_y(void) { return me.arena_height_m - BORDER_M - 0.5f * CELL_M; }

/* Lanes [first, end) of strip `rank` out of `members`: whole lanes, as even
 * as they go, in rank order from the left. */
static void strip(int rank, int members, int* first, int* end) {
  *first = rank * lane_count / members;
  *end = (rank + 1) * lane_count / members;
}

/* Waypoints of strip `rank`'s path: two per lane (where it enters the lane
 * and where it leaves it). */
static int path_length(int rank, int members) {
  int first, end;
  strip(rank, members, &first, &end);
  return 2 * (end - first);
}

static void waypoint(int rank, int members, int index, float* x, float* y) {
  int first, end;
  strip(rank, members, &first, &end);
  const int lane = first + index / 2;
  const int up = ((index / 2) % 2 == 0) == start_at_bottom; /* this lane is driven upwards */
  const int entering = index % 2 == 0;
  *x = lane_x(lane);
  *y = (up == entering) ? bottom_y() : top_y();
}

/* The waypoint of its path member `rank` stands at, or -1 (on its way). */
static int standing_at(const syrof_member_state* member, int rank, int members) {
  const float x = member->x_mm / 1000.0f, y = member->y_mm / 1000.0f;
  const int length = path_length(rank, members);
  for (int index = 0; index < length; ++index) {
    float wx, wy;
    waypoint(rank, members, index, &wx, &wy);
    if (hypotf(wx - x, wy - y) < ARRIVED_M) return index;
  }
  return -1;
}

static float point_segment_distance(float px, float py, float ax, float ay, float bx, float by) {
  const float dx = bx - ax, dy = by - ay;
  const float length2 = dx * dx + dy * dy;
  float t = length2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / length2 : 0;
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return hypotf(px - (ax + t * dx), py - (ay + t * dy));
}

static uint8_t app_init(const syrof_app_info* info) {
  me = *info;
  lane_count = (int)floorf((me.arena_width_m - 2 * BORDER_M) / CELL_M + 0.5f);
  if (lane_count < 0) lane_count = 0;
  return 0;
}

static uint8_t app_new_round(syrof_car_command* command, const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)clock_ms;
  (void)state;
  const int n = map->member_count;
  const uint8_t decided = (uint8_t)n; /* from the map alone: the same on every COOPERATIVE robot */
  if (map->mode != SYROF_MODE_COOPERATIVE || n > MAX_ROBOTS) return decided; /* hold still */

  int rank = 0;
  while (rank < n && map->members[rank].id != map->self_id) ++rank;
  const float x = map->members[rank].x_mm / 1000.0f, y = map->members[rank].y_mm / 1000.0f;
  if (rank != plan_rank || n != plan_members) {
    /* The first epoch, a crash or a join: cut the strips again. Every strip
     * starts at the end of its first lane nearer to the swarm's mean height,
     * the same on every robot. */
    float mean_y = 0;
    for (int j = 0; j < n; ++j) mean_y += map->members[j].y_mm / 1000.0f / (float)n;
    start_at_bottom = mean_y - bottom_y() <= top_y() - mean_y;
    plan_rank = rank;
    plan_members = n;
    next_waypoint = 0;
  }

  const int length = path_length(rank, n);
  if (next_waypoint < length && standing_at(&map->members[rank], rank, n) == next_waypoint) {
    int everyone_here = 1, someone_ahead = 0;
    for (int j = 0; j < n; ++j) {
      const int at = standing_at(&map->members[j], j, n);
      const int last = path_length(j, n) - 1;
      if (at < 0 || at < (next_waypoint < last ? next_waypoint : last)) everyone_here = 0;
      if (at > next_waypoint) someone_ahead = 1;
    }
    if (everyone_here || someone_ahead) ++next_waypoint;
  }
  if (next_waypoint >= length) return decided; /* the strip is swept */

  float to_x, to_y;
  waypoint(rank, n, next_waypoint, &to_x, &to_y);
  const float reach = 0.8f * me.max_speed_mps * (float)me.maneuver_ms / 1000.0f;
  const float wanted = hypotf(to_x - x, to_y - y);
  if (wanted > reach) {
    to_x = x + (to_x - x) * reach / wanted;
    to_y = y + (to_y - y) * reach / wanted;
  }

  /* Stop short of the others: the longest prefix of the move that keeps the
   * clearance to every other member (or does not get closer, for one that
   * already stands closer). */
  const float clearance = 2 * me.body_radius_m + MARGIN_M;
  float low = 0, high = 1;
  for (int step = 0; step < 20; ++step) {
    const float t = (low + high) / 2;
    const float ex = x + t * (to_x - x), ey = y + t * (to_y - y);
    int clear = 1;
    for (int j = 0; j < n && clear; ++j) {
      if (j == rank) continue;
      const float ox = map->members[j].x_mm / 1000.0f, oy = map->members[j].y_mm / 1000.0f;
      const float now = hypotf(ox - x, oy - y);
      const float keep = now < clearance ? now - 0.001f : clearance;
      if (point_segment_distance(ox, oy, x, y, ex, ey) < keep) clear = 0;
    }
    if (clear) low = t; else high = t;
  }
  const float end_x = x + low * (to_x - x), end_y = y + low * (to_y - y);
  const float moved = hypotf(end_x - x, end_y - y);
  if (moved < 0.005f) return decided;
  command->kind = SYROF_COMMAND_MOVE_TO;
  command->x_m = end_x;
  command->y_m = end_y;
  command->speed_mps = moved / (0.8f * (float)me.maneuver_ms / 1000.0f);
  if (command->speed_mps > me.max_speed_mps) command->speed_mps = me.max_speed_mps;
  return decided;
}

static uint8_t app_end_of_round(const syrof_ldmap* map, uint8_t state, uint32_t clock_ms) {
  (void)map;
  (void)clock_ms;
  return state;
}

SYROF_APP_DEFINE("coverage_reference", app_init, app_new_round, app_end_of_round)
