#include "syrof/sync/ldmap.h"

namespace syrof::sync {

Snapshot SnapshotOf(const wire::Beacon& beacon) {
  Snapshot snapshot;
  snapshot.x_mm = beacon.x_mm;
  snapshot.y_mm = beacon.y_mm;
  snapshot.heading_mrad = beacon.heading_mrad;
  snapshot.vx_mm_s = beacon.vx_mm_s;
  snapshot.vy_mm_s = beacon.vy_mm_s;
  snapshot.payload_length = beacon.payload_length;
  snapshot.payload = beacon.payload;
  return snapshot;
}

void WriteSnapshot(const Snapshot& snapshot, wire::Beacon& beacon) {
  beacon.x_mm = snapshot.x_mm;
  beacon.y_mm = snapshot.y_mm;
  beacon.heading_mrad = snapshot.heading_mrad;
  beacon.vx_mm_s = snapshot.vx_mm_s;
  beacon.vy_mm_s = snapshot.vy_mm_s;
  beacon.payload_length = snapshot.payload_length;
  beacon.payload = snapshot.payload;
}

bool LDMap::SameKnowledge(const LDMap& other) const {
  if (epoch != other.epoch || mode != other.mode || members != other.members) return false;
  for (const uint16_t id : members) {
    if (snapshots[id] != other.snapshots[id]) return false;
  }
  return true;
}

}  // namespace syrof::sync
