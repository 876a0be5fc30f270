#include "canonical.h"

#include <array>
#include <cstddef>

namespace syrof::queries::internal {
namespace {

QueryError CheckSizeAndIds(std::span<const Member> members) {
  if (members.size() > kMaxMembers) return QueryError::kTooManyMembers;
  for (const Member& member : members) {
    if (member.id >= kMaxMembers) return QueryError::kIdOutOfRange;
  }
  return QueryError::kOk;
}

}  // namespace

QueryError ValidateMembers(std::span<const Member> members) {
  if (const QueryError error = CheckSizeAndIds(members); error != QueryError::kOk) return error;
  // One bit per possible id: 128 bytes on the host, 4 on the Teensy.
  std::array<uint32_t, (size_t{kMaxMembers} + 31) / 32> seen{};
  for (const Member& member : members) {
    uint32_t& word = seen[member.id / 32];
    const uint32_t bit = uint32_t{1} << (member.id % 32);
    if ((word & bit) != 0) return QueryError::kDuplicateId;
    word |= bit;
  }
  return QueryError::kOk;
}

base::Result<uint16_t, QueryError> CanonicalMembers(std::span<const Member> members, WorkspaceStorage& storage) {
  if (const QueryError error = CheckSizeAndIds(members); error != QueryError::kOk) return error;
  // Counting sort on the id: a slot per possible id, then one pass in id order.
  storage.slot_of_id.fill(kNoRobot);
  for (size_t index = 0; index < members.size(); ++index) {
    uint16_t& slot = storage.slot_of_id[members[index].id];
    if (slot != kNoRobot) return QueryError::kDuplicateId;
    slot = static_cast<uint16_t>(index);
  }
  uint16_t count = 0;
  for (uint16_t id = 0; id < kMaxMembers; ++id) {
    const uint16_t slot = storage.slot_of_id[id];
    if (slot == kNoRobot) continue;
    const Point position = members[slot].position;
    storage.members[count++] = CanonicalMember{position.x_mm, position.y_mm, id};
  }
  return count;
}

}  // namespace syrof::queries::internal
