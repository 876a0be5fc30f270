// The replay recording of a simulated run, in memory: the run's header, and
// per radio round one frame per robot plus the events of that round.
//
// writer.h writes these to a stream and reader.h reads them back; the byte
// layout is in format.h and docs/replay.md. Units are in the names; poses are
// in the arena frame (origin at the lower-left corner, x right, y up,
// headings counter-clockwise from +x).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace syrof::lab::replay {

/// Version of the byte layout (format.h) the writer writes. Any change to the
/// layout bumps it; a reader reads every version from kOldestFormatVersion on
/// and refuses a newer one (docs/replay.md, "Versions").
///   1: the first layout.
///   2: event kinds APP_FAULT, INVALID_COMMAND and PAYLOAD_REFUSED.
///   (Event kinds SAFETY_INTERVENTION and JOIN_WAIT are accepted from
///   version 2 on until the next version bump, which should list them.)
inline constexpr uint16_t kFormatVersion = 2;
inline constexpr uint16_t kOldestFormatVersion = 1;

/// Robot id meaning "no robot" in Event::robot and Event::other; no robot of
/// a replay may have it.
inline constexpr uint16_t kNoRobot = 0xFFFF;

/// Limits a reader enforces on an untrusted file, and a writer on its input.
inline constexpr size_t kMaxNameBytes = 256;              ///< scenario_name, app_name
inline constexpr uint32_t kMaxRobots = 65535;             ///< ids 0 .. 65534 (kNoRobot excluded)
inline constexpr uint32_t kMaxEventsPerRound = 1u << 20;  ///< far above any real round

/// One robot of the run.
struct RobotInfo {
  uint16_t id = 0;            ///< any value but kNoRobot; ids increase along Header::robots
  uint8_t kind = 0;           ///< world::RobotKind value (0 omni, 1 rover), stored as is
  float body_radius_m = 0;    ///< disc radius, finite and >= 0

  bool operator==(const RobotInfo& other) const = default;
};

/// What the run was. Names are at most kMaxNameBytes bytes with no ASCII
/// control characters (UTF-8 is fine), so a dump cannot garble a terminal.
struct Header {
  uint64_t seed = 0;            ///< the scenario's seed
  int64_t radio_round_ns = 0;   ///< alpha, > 0
  float arena_width_m = 0;      ///< finite, > 0
  float arena_height_m = 0;     ///< finite, > 0
  std::string scenario_name;
  std::string app_name;         ///< e.g. "builtin:idle"
  std::vector<RobotInfo> robots;  ///< at most kMaxRobots, ids strictly increasing

  bool operator==(const Header& other) const = default;
};

/// Whether a robot is in the arena and running.
enum class Presence : uint8_t {
  kAbsent = 0,   ///< not switched on yet (a later `join`)
  kRunning = 1,
  kPaused = 2,   ///< software stopped, body still in the arena
  kCrashed = 3,  ///< stopped for good, body an obstacle
};

/// One robot at the end of one radio round. The epoch, phase, mode and
/// status are the synchronizer's; the estimated pose is the robot's own
/// estimator's, the true pose the simulator's ground truth.
struct RobotFrame {
  uint16_t id = 0;                      ///< a Header::robots id
  Presence presence = Presence::kAbsent;
  uint8_t status = 0;                   ///< 0 member, 1 joining
  uint8_t phase = 0;                    ///< wire::Phase value, 0 .. 2
  uint8_t mode = 0;                     ///< wire::Mode value (0 .. 1) of the epoch the robot is in
  uint16_t epoch = 0;
  float true_x_m = 0;
  float true_y_m = 0;
  float true_heading_rad = 0;
  float est_x_m = 0;
  float est_y_m = 0;
  float est_heading_rad = 0;

  bool operator==(const RobotFrame& other) const = default;
};

/// What happened. Epoch and membership events are reported by `robot`'s
/// synchronizer; collisions, faults and partitions by the simulator.
enum class EventKind : uint8_t {
  kEpochStart = 0,      ///< `robot` started epoch `epoch` in mode `mode`
  kMemberRemoved = 1,   ///< `robot` removed member `other`
  kMemberJoined = 2,    ///< `robot` admitted joiner `other`
  kBecameJoiner = 3,    ///< `robot` lost the swarm and is joining again
  kCollision = 4,       ///< bodies of `robot` and `other` touched
  kWallContact = 5,     ///< `robot`'s body touched a wall
  kCrash = 6,           ///< fault: `robot` crashed
  kPause = 7,           ///< fault: `robot` paused
  kResume = 8,          ///< fault: `robot` resumed after a pause
  kJoin = 9,            ///< fault: `robot` was switched on
  kPartitionStart = 10, ///< a radio partition began (robot may be kNoRobot)
  kPartitionEnd = 11,   ///< a radio partition ended (robot may be kNoRobot)
  // Since version 2:
  kAppFault = 12,       ///< `robot`'s app call failed in `epoch`; the robot stopped (presence CRASHED)
  kInvalidCommand = 13, ///< `robot`'s first command refused in the run (it held still that epoch)
  kPayloadRefused = 14, ///< `robot`'s first sendMessageData refused in the run
  // Since the next version (accepted in version 2 files until it exists):
  kSafetyIntervention = 15, ///< the safety filter began to limit `robot`'s command, against `other` (kNoRobot: a wall)
  kJoinWait = 16,           ///< joiner `robot` waits to be switched on: a body is on its start disc
};

/// The last EventKind of format `version`; a larger value in a file of that
/// version is an error.
constexpr EventKind LastEventKind(uint16_t version) {
  return version >= 2 ? EventKind::kJoinWait : EventKind::kPartitionEnd;
}

/// The last EventKind of the version the writer writes.
inline constexpr EventKind kLastEventKind = LastEventKind(kFormatVersion);

/// One event of a round.
struct Event {
  EventKind kind = EventKind::kEpochStart;
  uint16_t robot = kNoRobot;  ///< a Header::robots id, or kNoRobot
  uint16_t other = kNoRobot;  ///< removed/joined member, collision partner, else kNoRobot
  uint16_t epoch = 0;         ///< `robot`'s epoch when it happened
  uint8_t mode = 0;           ///< wire::Mode of that epoch; stored as is
  int64_t time_ns = 0;        ///< simulated time of the event

  bool operator==(const Event& other_event) const = default;
};

/// One radio round as the reader returns it.
struct Round {
  uint32_t index = 0;   ///< radio round number; increases through a file
  int64_t time_ns = 0;  ///< simulated time at the end of the round; never decreases
  std::vector<RobotFrame> robots;  ///< ids strictly increasing
  std::vector<Event> events;

  bool operator==(const Round& other) const = default;
};

/// "EPOCH_START", "MEMBER_REMOVED", ...; "?" for a value outside the enum.
const char* ToString(EventKind kind);
/// "ABSENT", "RUNNING", "PAUSED" or "CRASHED"; "?" for a value outside the enum.
const char* ToString(Presence presence);

}  // namespace syrof::lab::replay
