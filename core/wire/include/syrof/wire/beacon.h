// The beacon each robot broadcasts every radio round, in memory.
//
// Fields are in wire units (integers with the unit in the name), so a Beacon
// holds exactly what travels: for any Beacon that Encode() accepts,
// Decode(Encode(b)) == b. Fill the snapshot from estimated poses with the
// conversions in fixed_point.h. The byte layout is defined once in
// beacon_layout.h; beacon_codec.h encodes and decodes it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/wire/member_set.h"
#include "syrof/wire/wire_error.h"
#include "syrof/base/state_digest.h"

namespace syrof::wire {

/// Version of the layout in beacon_layout.h; a decoder rejects any other.
///   1: the first layout.
///   2: the mode takes one bit; the freed bit is `presence_only`.
///   3: the same bytes; a PROGRESS beacon's set is its sender's heard set
///      (docs/protocol.md, "Connectivity"), no longer its waiting set.
inline constexpr uint8_t kBeaconVersion = 3;

/// Most bytes an application may send per round (sendMessageData).
inline constexpr size_t kMaxPayloadBytes = 9;

/// Heading bounds in milliradians: round(1000 * pi).
inline constexpr int16_t kMaxHeadingMilliradians = 3142;
inline constexpr int16_t kMinHeadingMilliradians = -kMaxHeadingMilliradians;

/// The synchronizer's phase (docs/protocol.md).
enum class Phase : uint8_t {
  kProgress = 0,  // the maneuver runs
  kWait = 1,      // snapshot frozen, waiting for every member
  kVote = 2,      // counting rounds to the next epoch
};

/// Operation mode from stream consensus.
enum class Mode : uint8_t {
  kCooperative = 0,
  kAutonomous = 1,
};

/// Upper-case protocol names ("PROGRESS", ...); "?" for a value outside the enum.
const char* ToString(Phase phase);
/// "COOPERATIVE" or "AUTONOMOUS"; "?" for a value outside the enum.
const char* ToString(Mode mode);

/// A robot's state as the swarm sees it: pose, velocity and the app's
/// payload, in the beacon's fixed-point units so every robot holds exactly the
/// same bytes. Defined once, here: the beacon carries it (Beacon::snapshot),
/// the synchronizer freezes one per member and epoch and hands them to the
/// app in the LDMap (sync/ldmap.h). Frozen when the member's maneuver ends;
/// every WAIT and VOTE beacon of that epoch carries it unchanged. Fill it from
/// an estimate with the conversions in fixed_point.h.
struct Snapshot {
  int16_t x_mm = 0;            // position in the arena frame, millimetres
  int16_t y_mm = 0;            // position in the arena frame, millimetres
  int16_t heading_mrad = 0;    // milliradians counter-clockwise from +x, -3142 .. 3142
  int16_t vx_mm_s = 0;         // velocity, millimetres per second
  int16_t vy_mm_s = 0;         // velocity, millimetres per second
  uint8_t payload_length = 0;  // bytes of payload in use, 0 .. kMaxPayloadBytes
  std::array<uint8_t, kMaxPayloadBytes> payload{};  // the app's sendMessageData bytes; the unused tail is zero

  /// Copies `bytes` into the payload, zeroes the rest and sets payload_length.
  /// Returns kPayloadTooLong (and changes nothing) for more than 9 bytes.
  WireError SetPayload(std::span<const uint8_t> bytes);

  /// The bytes in use: payload[0 .. payload_length), clamped to the array.
  std::span<const uint8_t> payload_bytes() const;

  bool operator==(const Snapshot& other) const = default;
};

/// One robot's beacon for one radio round. The snapshot is the sender's
/// frozen estimate for this epoch (its live one in PROGRESS).
///
/// A presence-only beacon (presence_only set) is a robot that is not a
/// member yet (a joiner) saying where it is, so that every robot's safety
/// filter sees it (docs/safety.md). Only robot_id and the snapshot's pose and
/// velocity mean anything; every other field is zero. The runtime hands it to
/// the safety filter only, never to the synchronizer, so membership and
/// common knowledge are what they would be without it.
struct Beacon {
  uint16_t robot_id = 0;  // sender, 0 .. swarm size - 1
  uint16_t epoch = 0;     // maneuver number; wraps from 65535 to 0
  Phase phase = Phase::kProgress;
  Mode mode = Mode::kCooperative;
  bool presence_only = false;  // a joiner's position report; not for the synchronizer
  uint8_t vote_counter = 0;    // rounds counted in VOTE (docs/protocol.md)
  MemberSet waiting;           // WAIT: members known to be waiting; VOTE: the view; PROGRESS: the heard set; ids < swarm size
  Snapshot snapshot;           // pose, velocity and payload (the wire order is beacon_layout.h's)

  bool operator==(const Beacon& other) const = default;
};

/// A beacon's fields into `digest` (base/state_digest.h), one by one: the
/// struct has padding, which equal beacons need not share.
inline void AddToDigest(base::StateDigest& digest, const Beacon& beacon) {
  digest.AddValue(beacon.robot_id);
  digest.AddValue(beacon.epoch);
  digest.AddValue(beacon.phase);
  digest.AddValue(beacon.mode);
  digest.AddValue(beacon.presence_only);
  digest.AddValue(beacon.vote_counter);
  AddToDigest(digest, beacon.waiting);
  static_assert(sizeof(Snapshot) == 5 * 2 + 1 + kMaxPayloadBytes, "Snapshot has no padding");
  digest.AddValue(beacon.snapshot);
}

}  // namespace syrof::wire
