// What a Workspace holds: the scratch arrays of every query, sized for the
// largest input. Nothing survives from one call to the next.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <new>

#include "syrof/queries/types.h"
#include "syrof/queries/workspace.h"

namespace syrof::queries::internal {

/// A member as the algorithms see it.
struct CanonicalMember {
  int16_t x_mm;
  int16_t y_mm;
  uint16_t id;
};

inline constexpr size_t kMaxSide = std::max(size_t{kMaxMembers}, size_t{kMaxTargets});

struct WorkspaceStorage {
  // Shared: members in increasing id order, and the slot table that sorts them.
  std::array<uint16_t, kMaxMembers> slot_of_id;
  std::array<CanonicalMember, kMaxMembers> members;

  // ConvexHull: members sorted by (x, y, id) as packed keys, the first key of
  // each distinct position, and the monotone chain's stack.
  std::array<uint64_t, kMaxMembers> hull_keys;
  std::array<uint16_t, kMaxMembers + 1> hull_position_start;
  std::array<uint16_t, 2 * size_t{kMaxMembers} + 2> hull_chain;

  // ShortestEnclosingCircle: the members in the construction's order.
  std::array<CanonicalMember, kMaxMembers> circle_order;

  // MinWeightedMatching. Rows are the smaller side (robots, or targets when
  // there are fewer targets), columns the larger; every row gets a column.
  std::array<Point, kMaxSide> row_points;
  std::array<Point, kMaxSide> column_points;
  std::array<uint32_t, size_t{kMaxMembers} * size_t{kMaxTargets}> costs;  // row-major
  // Bottleneck search (Hopcroft-Karp): the current and the best matching.
  std::array<uint16_t, kMaxSide> column_of_row;
  std::array<uint16_t, kMaxSide> row_of_column;
  std::array<uint16_t, kMaxSide> best_column_of_row;
  std::array<uint16_t, kMaxSide> layer;
  std::array<uint16_t, kMaxSide> queue;
  std::array<uint16_t, kMaxSide> next_column;
  std::array<uint16_t, kMaxSide> path_rows;
  std::array<uint16_t, kMaxSide> path_columns;
  // Hungarian method, 1-based with index 0 as the virtual start column.
  std::array<int64_t, kMaxSide + 1> row_potential;
  std::array<int64_t, kMaxSide + 1> column_potential;
  std::array<int64_t, kMaxSide + 1> min_slack;
  std::array<uint16_t, kMaxSide + 1> row_of_column_1;
  std::array<uint16_t, kMaxSide + 1> previous_column;
  std::array<uint8_t, kMaxSide + 1> column_visited;
};

static_assert(sizeof(WorkspaceStorage) <= Workspace::kStorageBytes,
              "Workspace::kStorageBytes must cover WorkspaceStorage");
static_assert(alignof(WorkspaceStorage) <= 8, "Workspace storage is 8-byte aligned");

/// The one way into a Workspace's storage.
struct WorkspaceAccess {
  static WorkspaceStorage& Storage(Workspace& workspace) {
    return *std::launder(reinterpret_cast<WorkspaceStorage*>(workspace.storage_));
  }
  static void Construct(Workspace& workspace) {
    // Default-initialized: no 4 MB of zeroing; every query writes before it reads.
    new (workspace.storage_) WorkspaceStorage;
  }
};

}  // namespace syrof::queries::internal
