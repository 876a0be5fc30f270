/* The swarm queries as a plain C API, the one student apps call.
 *
 * The same queries as syrof/queries/swarm_queries.h (C++), on plain structs:
 * positions in integer millimetres (the beacon's resolution, int16, so
 * +-32.767 m), lengths returned in metres as float. Every function returns a
 * syrof_queries_status; on any status other than SYROF_QUERIES_OK the
 * outputs are left untouched. Answers depend only on the set of (id,
 * position) pairs, never on their order, and are bit-identical on every
 * platform (exact integer decisions). docs/queries.md has the definitions.
 *
 * Memory: the queries that need scratch space take a workspace the caller
 * places in memory it owns, once, at start-up:
 *
 *   static _Alignas(8) unsigned char memory[...];   // or malloc() at start-up
 *   syrof_queries_workspace* workspace = NULL;
 *   if (syrof_queries_workspace_init(memory, sizeof memory, &workspace) != SYROF_QUERIES_OK) ...
 *
 * A workspace needs no teardown; it serves one thread at a time. */
#ifndef SYROF_QUERIES_QUERIES_H
#define SYROF_QUERIES_QUERIES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped whenever a struct, constant or signature below changes. */
#define SYROF_QUERIES_ABI_VERSION 1u

/* "No robot" and "no target" in outputs; never a valid id or index. */
#define SYROF_QUERIES_NO_ROBOT 0xFFFFu
#define SYROF_QUERIES_NO_TARGET 0xFFFFu

/* Status codes; the same values as syrof::queries::QueryError. */
typedef enum syrof_queries_status {
  SYROF_QUERIES_OK = 0,
  SYROF_QUERIES_NO_MEMBERS = 1,              /* the query needs at least one member */
  SYROF_QUERIES_TOO_MANY_MEMBERS = 2,        /* more than syrof_queries_max_members() */
  SYROF_QUERIES_TOO_MANY_TARGETS = 3,        /* more than syrof_queries_max_targets() */
  SYROF_QUERIES_ID_OUT_OF_RANGE = 4,         /* an id >= syrof_queries_max_members() */
  SYROF_QUERIES_DUPLICATE_ID = 5,            /* two members with the same id */
  SYROF_QUERIES_NON_FINITE_COORDINATE = 6,   /* NaN or infinite coordinate in metres */
  SYROF_QUERIES_COORDINATE_OUT_OF_RANGE = 7, /* outside -32768 .. 32767 mm */
  SYROF_QUERIES_OUTPUT_TOO_SMALL = 8,        /* an output buffer is too short */
  SYROF_QUERIES_NULL_ARGUMENT = 9,           /* a required pointer is NULL */
  SYROF_QUERIES_WORKSPACE_TOO_SMALL = 10     /* workspace memory too small or misaligned */
} syrof_queries_status;

/* A position in millimetres. */
typedef struct syrof_queries_point {
  int16_t x_mm;
  int16_t y_mm;
} syrof_queries_point;

/* One robot of the map. */
typedef struct syrof_queries_member {
  uint16_t id; /* below syrof_queries_max_members() */
  int16_t x_mm;
  int16_t y_mm;
} syrof_queries_member;

/* The smallest circle holding every member. */
typedef struct syrof_queries_circle {
  float centre_x_m; /* each the float nearest to the exact value */
  float centre_y_m;
  float radius_m;
  uint16_t support_ids[3]; /* defining members, increasing; SYROF_QUERIES_NO_ROBOT past support_count */
  uint8_t support_count;   /* 1, 2 or 3 */
} syrof_queries_circle;

/* Where one robot goes. */
typedef struct syrof_queries_assignment {
  uint16_t robot_id;
  uint16_t target_index; /* SYROF_QUERIES_NO_TARGET when the robot gets none */
} syrof_queries_assignment;

/* The figures of a matching. */
typedef struct syrof_queries_matching_summary {
  uint64_t bottleneck_squared_mm2; /* longest matched distance squared, exact */
  uint64_t total_distance_q15_mm;  /* sum of matched distances, each in 2^-15 mm rounded down */
  float bottleneck_m;              /* longest matched distance, metres */
  float total_m;                   /* total_distance_q15_mm in metres */
  uint16_t matched_count;          /* min(robots, targets) */
} syrof_queries_matching_summary;

/* Opaque scratch memory for the queries. */
typedef struct syrof_queries_workspace syrof_queries_workspace;

/* SYROF_QUERIES_ABI_VERSION of the library linked in. */
uint32_t syrof_queries_abi_version(void);

/* The status's name ("DuplicateId"); "?" for an unknown value. Never NULL. */
const char* syrof_queries_status_name(syrof_queries_status status);

/* Largest member count and target count this build accepts (32 on the
 * Teensy, 1024 on the host). */
uint16_t syrof_queries_max_members(void);
uint16_t syrof_queries_max_targets(void);

/* Bytes and alignment a workspace needs. */
size_t syrof_queries_workspace_size(void);
size_t syrof_queries_workspace_alignment(void);

/* Prepares a workspace in `memory` (at least syrof_queries_workspace_size()
 * bytes, aligned to syrof_queries_workspace_alignment()), which must outlive
 * it, and stores its handle in *workspace. */
syrof_queries_status syrof_queries_workspace_init(void* memory, size_t size, syrof_queries_workspace** workspace);

/* Metres to millimetres: x1000 in float, round to nearest, ties away from
 * zero (the beacon encoder's rule); NaN, infinity or a result outside int16
 * is an error, not a saturated value. */
syrof_queries_status syrof_queries_point_from_metres(float x_m, float y_m, syrof_queries_point* point);

/* NumberOfMembers: the member count (validated: ids in range, no repeats).
 * `members` may be NULL when count is 0. */
syrof_queries_status syrof_queries_number_of_members(const syrof_queries_member* members, size_t count,
                                                     uint16_t* number_of_members);

/* Leader: the smallest member id. */
syrof_queries_status syrof_queries_leader(const syrof_queries_member* members, size_t count, uint16_t* leader_id);

/* ShortestEnclosingCircle: the smallest circle holding every member. */
syrof_queries_status syrof_queries_shortest_enclosing_circle(syrof_queries_workspace* workspace,
                                                             const syrof_queries_member* members, size_t count,
                                                             syrof_queries_circle* circle);

/* ConvexHull: ids of the members at the hull's corners, counter-clockwise
 * from the corner with the smallest x (then y); members sharing a corner all
 * listed, in increasing id order. `capacity` must be at least `count`. */
syrof_queries_status syrof_queries_convex_hull(syrof_queries_workspace* workspace, const syrof_queries_member* members,
                                               size_t count, uint16_t* hull_ids, size_t capacity, size_t* hull_count);

/* MinWeightedMatching: pairs robots with targets (min(count, target_count)
 * pairs), minimizing the longest travel, then the total travel.
 * `by_robot` (capacity >= count) receives one assignment per member in
 * increasing id order; `robot_of_target` (capacity >= target_count) the
 * robot sent to each target or SYROF_QUERIES_NO_ROBOT. `targets` may be NULL
 * when target_count is 0; `summary` may be NULL. */
syrof_queries_status syrof_queries_min_weighted_matching(syrof_queries_workspace* workspace,
                                                         const syrof_queries_member* members, size_t count,
                                                         const syrof_queries_point* targets, size_t target_count,
                                                         syrof_queries_assignment* by_robot, size_t by_robot_capacity,
                                                         uint16_t* robot_of_target, size_t robot_of_target_capacity,
                                                         syrof_queries_matching_summary* summary);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* SYROF_QUERIES_QUERIES_H */
