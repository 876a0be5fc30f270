// The local dynamic map (LDMap) handed to the app's newRound: what a robot
// knows of every member at the end of the previous epoch's maneuver.
#pragma once

#include <array>
#include <cstdint>

#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"

namespace syrof::sync {

/// A member's frozen end-of-maneuver state, in the beacon's fixed-point units
/// so every robot holds exactly the same bytes. Frozen once per epoch when
/// the member's maneuver ends; every WAIT and VOTE beacon of that epoch
/// carries it unchanged.
struct Snapshot {
  int16_t x_mm = 0;           // position in the arena frame, millimetres
  int16_t y_mm = 0;           // position in the arena frame, millimetres
  int16_t heading_mrad = 0;   // milliradians counter-clockwise from +x, -3142 .. 3142
  int16_t vx_mm_s = 0;        // velocity, millimetres per second
  int16_t vy_mm_s = 0;        // velocity, millimetres per second
  uint8_t payload_length = 0; // bytes of payload in use, 0 .. 9
  std::array<uint8_t, wire::kMaxPayloadBytes> payload{};  // the app's sendMessageData bytes

  bool operator==(const Snapshot&) const = default;
};

/// The snapshot fields of `beacon`.
Snapshot SnapshotOf(const wire::Beacon& beacon);

/// Copies `snapshot` into the snapshot fields of `beacon`.
void WriteSnapshot(const Snapshot& snapshot, wire::Beacon& beacon);

/// One robot's view of the swarm at the start of an epoch. In COOPERATIVE
/// mode every robot that starts this epoch COOPERATIVE holds an identical
/// LDMap (docs/protocol.md, "Safety"); in AUTONOMOUS mode it is this robot's
/// own best knowledge.
struct LDMap {
  uint16_t epoch = 0;                 // the epoch that starts with this map
  wire::Mode mode = wire::Mode::kAutonomous;
  wire::MemberSet members;            // whose snapshots follow; always includes self
  std::array<wire::Phase, wire::kMaxSwarmSize> phases{};  // each member's phase when last heard
  std::array<Snapshot, wire::kMaxSwarmSize> snapshots{};  // valid for ids in `members`

  /// Whether two maps hold the same epoch, mode, members and, for each
  /// member, the same snapshot (phases and unused slots are not compared).
  bool SameKnowledge(const LDMap& other) const;
};

}  // namespace syrof::sync
