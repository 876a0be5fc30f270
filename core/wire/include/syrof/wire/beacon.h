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
///   4: a relay at the end: a silent robot's last known position
///      (docs/beacon.md, "Relays").
inline constexpr uint8_t kBeaconVersion = 4;

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

/// A relayed position: where a robot the sender has not heard from for a
/// while (crashed, paused, out of reach) was when the sender last heard of
/// it, so that robots which never heard it (a joiner switched on after it
/// fell silent) keep off its body too (docs/safety.md, "A robot that was
/// never told"). Positions travel in units of kRelayUnitMm, 12 bits each.
struct Relay {
  uint16_t slot = 0;   // 0: nothing relayed; else 1 + the relayed robot's id
  int16_t x_16mm = 0;  // position x in units of 16 mm, -2048 .. 2047; 0 when slot is 0
  int16_t y_16mm = 0;  // position y in units of 16 mm, -2048 .. 2047; 0 when slot is 0

  bool relays() const { return slot != 0; }
  uint16_t robot_id() const { return static_cast<uint16_t>(slot - 1); }

  bool operator==(const Relay& other) const = default;
};

/// Millimetres per unit of a relayed position, and the farthest a relayed
/// position is from the millimetres it was made of: rounding to the unit
/// moves an axis by at most 8 mm, and clamping 32753 .. 32767 mm to the
/// 12 bits' 32752 by at most 15, so 15 * sqrt(2) = 21.2 mm, rounded up.
inline constexpr int32_t kRelayUnitMm = 16;
inline constexpr int32_t kRelayAxisErrorMm = 15;
inline constexpr uint16_t kRelayRoundingMm = 22;
inline constexpr int16_t kMinRelayUnits = -2048;
inline constexpr int16_t kMaxRelayUnits = 2047;

/// A millimetre coordinate in relay units, rounded to nearest (ties away
/// from zero) and clamped to the 12 bits; back to millimetres.
constexpr int16_t ToRelayUnits(int16_t mm) {
  const int32_t half = kRelayUnitMm / 2;
  const int32_t units = mm >= 0 ? (int32_t{mm} + half) / kRelayUnitMm : -((half - int32_t{mm}) / kRelayUnitMm);
  return static_cast<int16_t>(units > kMaxRelayUnits ? kMaxRelayUnits : units < kMinRelayUnits ? kMinRelayUnits : units);
}
constexpr int16_t FromRelayUnits(int16_t units) {
  const int32_t mm = int32_t{units} * kRelayUnitMm;
  return static_cast<int16_t>(mm > 32767 ? 32767 : mm);
}

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
  Relay relay;                 // a silent robot's last known position, or nothing

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
  digest.AddValue(beacon.relay.slot);
  digest.AddValue(beacon.relay.x_16mm);
  digest.AddValue(beacon.relay.y_16mm);
}

}  // namespace syrof::wire
