/* The app API: how a robot application talks to SyROF (the paper's
 * Interface 2), as a plain C ABI.
 *
 * An app is three callbacks the platform calls on every robot:
 *   init        once, when the robot starts (or joins);
 *   newRound    at the start of every epoch, with the local dynamic map
 *               (LDMap): it sets the robot's command for the maneuver;
 *   endOfRound  when the maneuver ends and the robot's snapshot freezes;
 * and platform functions the app may call from any callback:
 *   sendMessageData  up to SYROF_APP_MAX_PAYLOAD_BYTES bytes, carried in the
 *               robot's next frozen snapshot, so every robot sees them in the
 *               next LDMap;
 *   syrofAppParameter  a number the scenario gives the app by name
 *               (`app: {library: ..., params: {radius_m: 1.5}}`), usually
 *               read in init.
 * Each returns the app's one-byte global state, which the platform hands back
 * on the next call (the paper's globalState).
 *
 * Every robot runs its own instance with its own memory: globals in an app
 * are per robot, and no robot can read another's memory. In COOPERATIVE mode
 * every robot that starts an epoch holds the same LDMap (docs/protocol.md),
 * so an app that computes from the map alone makes the same decisions on
 * every robot; in AUTONOMOUS mode the map is the robot's own best knowledge.
 *
 * A shared library exports one symbol, SYROF_APP_ENTRY_SYMBOL, returning its
 * descriptor (use SYROF_APP_DEFINE); the loader checks abi_version. The
 * swarm's size is not fixed by this ABI: maps carry a count and a pointer.
 *
 * Units: positions in millimetres and headings in milliradians in maps (the
 * beacon's fixed-point units, so every robot holds the same bytes); metres,
 * metres per second and radians in commands. Arena frame: x right, y up,
 * headings counter-clockwise from +x. docs/apps.md has the whole contract. */
#ifndef SYROF_APP_H
#define SYROF_APP_H

#include <stddef.h>
#include <stdint.h>

#include "syrof/queries/queries.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped whenever a struct, constant or signature below changes.
 *
 * Additions keep it: a new platform function or a new status code changes
 * nothing an existing library relies on, so every library built against an
 * older header still loads and runs. syrofAppParameter (and the status
 * SYROF_APP_NO_SUCH_PARAMETER) came that way, still version 1: a library
 * that calls it, run on a platform without it, fails to load with
 * "undefined symbol: syrofAppParameter", which the loader reports (verdict
 * load_failed, naming the symbol), a clearer message than a version number,
 * while a bump would have refused every library built before. The members'
 * `kind` came the same way: it fills the byte that was syrof_member_state's
 * padding (its size and every other offset are unchanged) and
 * syrof_app_info's `kind` follows its last field, so a library built before
 * reads what it always read. */
#define SYROF_APP_ABI_VERSION 1u

/* Most bytes sendMessageData accepts (the beacon's payload). */
#define SYROF_APP_MAX_PAYLOAD_BYTES 9u

/* Status codes of platform functions. */
typedef enum syrof_app_status {
  SYROF_APP_OK = 0,
  SYROF_APP_PAYLOAD_TOO_LONG = 1, /* more than SYROF_APP_MAX_PAYLOAD_BYTES; nothing was changed */
  SYROF_APP_NULL_ARGUMENT = 2,    /* payload NULL with a non-zero length */
  SYROF_APP_NOT_RUNNING = 3,      /* called outside a callback of a running robot */
  SYROF_APP_NO_SUCH_PARAMETER = 4, /* the scenario gives no parameter of that name; *value is unchanged */
  SYROF_APP_NO_SUCH_INPUT = 5      /* the scenario gives this robot no input of that name; *value is unchanged */
} syrof_app_status;

/* Most parameters a scenario gives an app, and the longest name of one
 * (bytes, without the terminating NUL). */
#define SYROF_APP_MAX_PARAMETERS 32u
#define SYROF_APP_MAX_PARAMETER_NAME_LENGTH 63u
/* Most private inputs a scenario gives each robot (syrofAppInput); their
 * names are at most SYROF_APP_MAX_PARAMETER_NAME_LENGTH bytes too. */
#define SYROF_APP_MAX_INPUTS 16u

/* The operation mode an epoch started in. */
typedef enum syrof_mode {
  SYROF_MODE_COOPERATIVE = 0, /* every COOPERATIVE robot holds this same map */
  SYROF_MODE_AUTONOMOUS = 1   /* the map is this robot's own knowledge only */
} syrof_mode;

/* A member's synchronizer phase when it was last heard. */
typedef enum syrof_phase {
  SYROF_PHASE_PROGRESS = 0,
  SYROF_PHASE_WAIT = 1,
  SYROF_PHASE_VOTE = 2
} syrof_phase;

/* A robot's kind (the scenario's `kind:`; docs/apps.md "Robot kinds"). */
typedef enum syrof_robot_kind {
  SYROF_KIND_OMNI = 0,  /* omnidirectional: moves in any direction at once */
  SYROF_KIND_ROVER = 1, /* differential drive: turns before it goes */
  SYROF_KIND_DRONE = 2, /* planar multirotor at a fixed height: faster, brakes later */
  SYROF_KIND_UNKNOWN = 255 /* never in the lab, over DDS or on an image configured
                              by syrof-firmware-config: a robot set up by hand
                              without its swarm's kinds */
} syrof_robot_kind;

/* One member's frozen snapshot: its estimated state when its previous
 * maneuver ended, and the payload it sent; and its kind. */
typedef struct syrof_member_state {
  uint16_t id;          /* robot id, 0 .. swarm_size - 1 */
  int16_t x_mm;         /* estimated position, millimetres */
  int16_t y_mm;
  int16_t heading_mrad; /* estimated heading, milliradians, -3142 .. 3142 */
  int16_t vx_mm_s;      /* estimated velocity, millimetres per second */
  int16_t vy_mm_s;
  uint8_t phase;        /* syrof_phase */
  uint8_t payload_length;                          /* 0 .. SYROF_APP_MAX_PAYLOAD_BYTES */
  uint8_t payload[SYROF_APP_MAX_PAYLOAD_BYTES];    /* unused tail is zero */
  uint8_t kind;         /* syrof_robot_kind, as the scenario gives every robot;
                           fixed for the run (the swarm's configuration, not
                           the beacon, tells it) */
} syrof_member_state;

/* The local dynamic map: what this robot knows of every member at the start
 * of an epoch. Valid only during the callback that receives it. */
typedef struct syrof_ldmap {
  uint16_t epoch;        /* the epoch that starts (newRound) or ends (endOfRound) */
  uint8_t mode;          /* syrof_mode */
  uint16_t self_id;      /* this robot's id; always one of the members */
  uint16_t member_count; /* at least 1 */
  const syrof_member_state* members; /* member_count entries, increasing id */
} syrof_ldmap;

/* What the robot does during the maneuver. The motion controller of the
 * robot's kind carries it out with the robot's own estimate; at the end of
 * the maneuver the robot stops. */
typedef enum syrof_command_kind {
  SYROF_COMMAND_STOP = 0,     /* hold still */
  SYROF_COMMAND_MOVE_TO = 1,  /* go to (x_m, y_m) at up to speed_mps, then stop */
  SYROF_COMMAND_VELOCITY = 2, /* move with (vx_mps, vy_mps), arena frame */
  SYROF_COMMAND_TURN_TO = 3   /* turn in place to heading_rad */
} syrof_command_kind;

typedef struct syrof_car_command {
  uint8_t kind;        /* syrof_command_kind; newRound receives STOP */
  float x_m;           /* MOVE_TO: target, metres */
  float y_m;
  float speed_mps;     /* MOVE_TO: cruise speed, > 0; capped by the robot kind */
  float vx_mps;        /* VELOCITY: metres per second, capped by the robot kind */
  float vy_mps;
  float heading_rad;   /* TURN_TO: target heading, radians */
} syrof_car_command;

/* Facts about the robot and the swarm, for init. */
typedef struct syrof_app_info {
  uint32_t abi_version;      /* SYROF_APP_ABI_VERSION of the platform */
  uint16_t self_id;
  uint16_t swarm_size;       /* robot ids are 0 .. swarm_size - 1 */
  uint32_t radio_round_ms;   /* the synchronizer's round (alpha) */
  uint32_t maneuver_ms;      /* how long PROGRESS lasts (the application round) */
  float arena_width_m;       /* the arena spans [0, width] x [0, height] */
  float arena_height_m;
  float body_radius_m;       /* this robot's body */
  float max_speed_mps;       /* this robot kind's speed limit */
  uint8_t kind;              /* this robot's syrof_robot_kind */
} syrof_app_info;

/* The callbacks. `clock_ms` is the robot's local clock, milliseconds since
 * it started. Each returns the new global state. */
typedef uint8_t (*syrof_app_init_fn)(const syrof_app_info* info);
typedef uint8_t (*syrof_app_new_round_fn)(syrof_car_command* command, const syrof_ldmap* ldmap,
                                          uint8_t global_state, uint32_t clock_ms);
typedef uint8_t (*syrof_app_end_of_round_fn)(const syrof_ldmap* ldmap, uint8_t global_state,
                                             uint32_t clock_ms);

/* What a library hands the loader. */
typedef struct syrof_app_descriptor {
  uint32_t abi_version; /* SYROF_APP_ABI_VERSION the app was built against */
  const char* name;     /* short, for logs and reports */
  syrof_app_init_fn init;
  syrof_app_new_round_fn new_round;
  syrof_app_end_of_round_fn end_of_round;
} syrof_app_descriptor;

/* The symbol a shared library exports. */
#define SYROF_APP_ENTRY_SYMBOL "syrof_app_entry"
typedef const syrof_app_descriptor* (*syrof_app_entry_fn)(void);

/* Defines the entry point of an app library:
 *   SYROF_APP_DEFINE("my_app", my_init, my_new_round, my_end_of_round) */
#define SYROF_APP_DEFINE(app_name, init_fn, new_round_fn, end_of_round_fn)                        \
  const syrof_app_descriptor* syrof_app_entry(void) {                                             \
    static const syrof_app_descriptor descriptor = {SYROF_APP_ABI_VERSION, (app_name), (init_fn), \
                                                    (new_round_fn), (end_of_round_fn)};           \
    return &descriptor;                                                                           \
  }

/* ---- Provided by the platform ------------------------------------------ */

/* Sets the payload of this robot's next snapshot (the paper's
 * sendMessageData): `length` bytes from `payload`, at most
 * SYROF_APP_MAX_PAYLOAD_BYTES; more is refused with
 * SYROF_APP_PAYLOAD_TOO_LONG and the previous payload stays. A length of 0
 * clears it. The payload is frozen with the snapshot when the maneuver ends. */
int sendMessageData(const uint8_t* payload, size_t length);

/* Reads the scenario's parameter `name` (`app.params` in the scenario,
 * docs/apps.md "Parameters") into *value: SYROF_APP_OK. When the scenario
 * gives none of that name: SYROF_APP_NO_SUCH_PARAMETER and *value is left as
 * it was, so the usual pattern keeps the app's default:
 *     double radius_m = 1.0;
 *     syrofAppParameter("radius_m", &radius_m);
 * `name` must be NUL-terminated; at most SYROF_APP_MAX_PARAMETER_NAME_LENGTH
 * + 1 of its bytes are read, and a longer name is never found (the scenario
 * refuses one). A name without a NUL that ends in unreadable memory cannot
 * be detected and crashes the app, as any bad pointer does.
 * SYROF_APP_NULL_ARGUMENT for a NULL `name` or `value`; SYROF_APP_NOT_RUNNING
 * outside a callback. Callable in any callback; the values never change
 * during a run. Added in ABI version 1 (see SYROF_APP_ABI_VERSION). */
int syrofAppParameter(const char* name, double* value);

/* Reads this robot's private input `name` (`inputs` in the scenario,
 * docs/apps.md "Private inputs") into *value: SYROF_APP_OK. Unlike a
 * parameter, each robot has its own value, and only this robot can read it:
 * the others learn it only from what this robot puts in its payload
 * (sendMessageData). When the scenario gives no input of that name:
 * SYROF_APP_NO_SUCH_INPUT and *value is left as it was. The same rules as
 * syrofAppParameter otherwise: `name` NUL-terminated, at most
 * SYROF_APP_MAX_PARAMETER_NAME_LENGTH + 1 of its bytes read;
 * SYROF_APP_NULL_ARGUMENT for a NULL `name` or `value`;
 * SYROF_APP_NOT_RUNNING outside a callback. The values never change during
 * a run. Added in ABI version 1 (see SYROF_APP_ABI_VERSION). */
int syrofAppInput(const char* name, double* value);

/* A workspace for the queries that need one (syrof/queries/queries.h),
 * owned by the platform; valid for the robot's lifetime. */
syrof_queries_workspace* syrofQueriesWorkspace(void);

/* The members of `ldmap` in the queries' input form. `out` must hold
 * ldmap->member_count entries. Returns the count written. */
size_t syrofMembersForQueries(const syrof_ldmap* ldmap, syrof_queries_member* out);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* SYROF_APP_H */
