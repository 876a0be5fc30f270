// Scratch memory for the queries, allocated once by the caller.
#pragma once

#include <cstddef>

#include "syrof/queries/types.h"

namespace syrof::queries {

namespace internal {
struct WorkspaceAccess;
}  // namespace internal

/// The memory every query that needs scratch space works in, sized for
/// kMaxMembers members and kMaxTargets targets, so a query never allocates.
/// Construct one at start-up (a static, or one heap allocation) and pass it
/// to each call; a query leaves nothing in it that the next call reads. One
/// Workspace serves one thread at a time. Most of it is MinWeightedMatching's
/// cost table (4 bytes per robot-target pair): about 4 MB on the host
/// (1024 x 1024), 7 KB on the Teensy (32 x 32).
class Workspace {
 public:
  /// Bytes of scratch storage (an upper bound the implementation checks).
  static constexpr size_t kStorageBytes = 4 * size_t{kMaxMembers} * size_t{kMaxTargets} + 32 * size_t{kMaxMembers} +
                                          56 * (kMaxMembers > kMaxTargets ? size_t{kMaxMembers} : size_t{kMaxTargets}) +
                                          128;

  Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;

 private:
  friend struct internal::WorkspaceAccess;
  alignas(8) unsigned char storage_[kStorageBytes];
};

}  // namespace syrof::queries
