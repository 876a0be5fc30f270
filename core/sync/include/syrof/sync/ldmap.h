// The local dynamic map (LDMap) handed to the app's newRound: what a robot
// knows of every member at the end of the previous epoch's maneuver. Each
// member's state is a wire::Snapshot, the one the beacons carry.
#pragma once

#include <array>
#include <cstdint>

#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"

namespace syrof::sync {

/// One robot's view of the swarm at the start of an epoch. In COOPERATIVE
/// mode every robot that starts this epoch COOPERATIVE holds an identical
/// LDMap (docs/protocol.md, "Safety"); in AUTONOMOUS mode it is this robot's
/// own best knowledge.
struct LDMap {
  uint16_t epoch = 0;                 // the epoch that starts with this map
  wire::Mode mode = wire::Mode::kAutonomous;
  wire::MemberSet members;            // whose snapshots follow; always includes self
  std::array<wire::Phase, wire::kMaxSwarmSize> phases{};  // each member's phase when last heard
  std::array<wire::Snapshot, wire::kMaxSwarmSize> snapshots{};  // each member's frozen snapshot (wire/beacon.h); valid for ids in `members`

  /// Whether two maps hold the same epoch, mode, members and, for each
  /// member, the same snapshot (phases and unused slots are not compared).
  bool SameKnowledge(const LDMap& other) const;
};

}  // namespace syrof::sync
