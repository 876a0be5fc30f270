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
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/message/message_format.h"

namespace syrof::lab::replay {

/// Version of the byte layout (format.h) the writer writes. Any change to the
/// layout bumps it; a reader reads every version from kOldestFormatVersion on
/// and refuses a newer one (docs/replay.md, "Versions").
///   1: the first layout.
///   2: event kinds APP_FAULT, INVALID_COMMAND and PAYLOAD_REFUSED.
///   3: per-epoch map records in each round, an event's own `partition`
///      field, event kinds SAFETY_INTERVENTION and JOIN_WAIT, the arena's
///      UWB anchors in the header.
///   4: each robot's private inputs and the run's message format (when one
///      was declared) in the header.
///   5: event kind BEACON_LOST (a scripted channel's lost beacons).
inline constexpr uint16_t kFormatVersion = 5;
inline constexpr uint16_t kOldestFormatVersion = 1;

/// Robot id meaning "no robot" in Event::robot and Event::other; no robot of
/// a replay may have it.
inline constexpr uint16_t kNoRobot = 0xFFFF;

/// Event::partition of an event that is not about a partition.
inline constexpr uint16_t kNoPartition = 0xFFFF;

/// Limits a reader enforces on an untrusted file, and a writer on its input.
inline constexpr size_t kMaxNameBytes = 256;              ///< scenario_name, app_name
inline constexpr uint32_t kMaxRobots = 65535;             ///< ids 0 .. 65534 (kNoRobot excluded)
inline constexpr uint32_t kMaxEventsPerRound = 1u << 20;  ///< far above any real round
inline constexpr size_t kMaxAnchors = 256;                ///< UWB anchors of the arena
inline constexpr size_t kMaxInputsPerRobot = 16;          ///< SYROF_APP_MAX_INPUTS (lab/sim checks the two agree)
/// A map member's payload: the beacon's (wire::kMaxPayloadBytes; lab/sim
/// checks the two agree).
inline constexpr size_t kMaxPayloadBytes = 9;

/// One private input of a robot (syrofAppInput; since version 4).
struct InputValue {
  std::string name;  ///< a name's rules (Header), not empty
  double value = 0;  ///< finite

  bool operator==(const InputValue& other) const = default;
};

/// One robot of the run.
struct RobotInfo {
  uint16_t id = 0;            ///< any value but kNoRobot; ids increase along Header::robots
  uint8_t kind = 0;           ///< world::RobotKind value (0 omni, 1 rover, 2 drone), stored as is
  float body_radius_m = 0;    ///< disc radius, finite and >= 0
  /// Its private inputs (the scenario's `inputs:` resolved for it), at most
  /// kMaxInputsPerRobot, names unique; empty in files before version 4.
  std::vector<InputValue> inputs;

  bool operator==(const RobotInfo& other) const = default;
};

/// A UWB anchor of the arena (since version 3), metres, arena frame.
struct AnchorInfo {
  float x_m = 0;  ///< finite
  float y_m = 0;  ///< finite

  bool operator==(const AnchorInfo& other) const = default;
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
  std::vector<AnchorInfo> anchors;  ///< at most kMaxAnchors; empty in version 1 and 2 files
  /// The robots' message format, when the run had one (the scenario's or
  /// the assignment's `message:`); absent in files before version 4.
  std::optional<message::MessageFormat> message;

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
  // Since version 3:
  kSafetyIntervention = 15, ///< the safety filter limited `robot`'s command to keep it from `other` (kNoRobot: a wall)
  kJoinWait = 16,       ///< joiner `robot` waits for its start disc to clear before it is switched on
  // Since version 5:
  kBeaconLost = 17,     ///< `robot`'s beacon of this round did not reach `other`: a scripted channel lost it
};

/// The last EventKind of format `version`; a larger value in a file of that
/// version is an error.
constexpr EventKind LastEventKind(uint16_t version) {
  if (version >= 5) return EventKind::kBeaconLost;
  if (version >= 3) return EventKind::kJoinWait;
  return version >= 2 ? EventKind::kPayloadRefused : EventKind::kPartitionEnd;
}

/// Whether `kind` is PARTITION_START or PARTITION_END, the events that name a
/// partition instead of a robot.
constexpr bool IsPartitionEvent(EventKind kind) {
  return kind == EventKind::kPartitionStart || kind == EventKind::kPartitionEnd;
}

/// The last EventKind of the version the writer writes.
inline constexpr EventKind kLastEventKind = LastEventKind(kFormatVersion);

/// One event of a round.
struct Event {
  EventKind kind = EventKind::kEpochStart;
  uint16_t robot = kNoRobot;  ///< a Header::robots id, or kNoRobot (always for partition events)
  uint16_t other = kNoRobot;  ///< removed/joined member, collision partner, robot kept away from, else kNoRobot
  uint16_t epoch = 0;         ///< `robot`'s epoch when it happened
  uint8_t mode = 0;           ///< wire::Mode of that epoch; stored as is
  int64_t time_ns = 0;        ///< simulated time of the event
  /// PARTITION_START and PARTITION_END: the partition's index in the
  /// scenario's channel.partitions (0 is the first); every other kind
  /// kNoPartition. A version 1 or 2 file kept the index in `robot`; the
  /// reader moves it here.
  uint16_t partition = kNoPartition;

  bool operator==(const Event& other_event) const = default;
};

/// One member of an epoch map: what the map's holder knows of it, the
/// synchronizer's frozen snapshot (wire::Snapshot, in its units) and the
/// member's phase when last heard.
struct MapMember {
  uint16_t id = 0;          ///< a Header::robots id
  uint8_t phase = 0;        ///< wire::Phase value, 0 .. 2
  int16_t x_mm = 0;         ///< position, millimetres, arena frame
  int16_t y_mm = 0;
  int16_t heading_mrad = 0; ///< milliradians counter-clockwise from +x
  int16_t vx_mm_s = 0;      ///< velocity, millimetres per second
  int16_t vy_mm_s = 0;
  std::vector<uint8_t> payload;  ///< the app's sendMessageData bytes, at most kMaxPayloadBytes

  bool operator==(const MapMember& other) const = default;
};

/// The LDMap a robot started an epoch with (sync::LDMap, what the app's
/// newRound received): in a COOPERATIVE epoch every robot that started it
/// holds the same one.
struct EpochMap {
  uint16_t epoch = 0;
  uint8_t mode = 0;                 ///< wire::Mode value, 0 .. 1
  std::vector<MapMember> members;   ///< ids strictly increasing; at most the header's robots

  bool operator==(const EpochMap& other) const = default;
};

/// Robot `robot` started an epoch in this round with `map`. Maps are shared
/// and immutable: the reader hands the same object to every robot whose map
/// the file stores once (docs/replay.md, "Map record").
struct RobotMap {
  uint16_t robot = 0;                    ///< a Header::robots id
  std::shared_ptr<const EpochMap> map;   ///< never null

  /// Compares the maps' contents, not their addresses.
  bool operator==(const RobotMap& other) const {
    if (robot != other.robot) return false;
    if (map == nullptr || other.map == nullptr) return map == other.map;
    return *map == *other.map;
  }
};

/// One radio round as the reader returns it.
struct Round {
  uint32_t index = 0;   ///< radio round number; increases through a file
  int64_t time_ns = 0;  ///< simulated time at the end of the round; never decreases
  std::vector<RobotFrame> robots;  ///< ids strictly increasing
  std::vector<Event> events;
  std::vector<RobotMap> maps;      ///< robots that started an epoch this round, ids strictly increasing (version 3 on)

  bool operator==(const Round& other) const = default;
};

/// "EPOCH_START", "MEMBER_REMOVED", ...; "?" for a value outside the enum.
const char* ToString(EventKind kind);
/// "ABSENT", "RUNNING", "PAUSED" or "CRASHED"; "?" for a value outside the enum.
const char* ToString(Presence presence);

}  // namespace syrof::lab::replay
