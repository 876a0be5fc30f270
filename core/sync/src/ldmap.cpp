#include "syrof/sync/ldmap.h"

namespace syrof::sync {

bool LDMap::SameKnowledge(const LDMap& other) const {
  if (epoch != other.epoch || mode != other.mode || members != other.members) return false;
  for (const uint16_t id : members) {
    if (snapshots[id] != other.snapshots[id]) return false;
  }
  return true;
}

}  // namespace syrof::sync
