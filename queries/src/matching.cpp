// MinWeightedMatching: bottleneck assignment, then minimum total distance
// among the bottleneck-optimal assignments. Integer arithmetic only: squared
// distances in mm^2 are exact (below 2^33), and the total is a sum of
// distances in units of 2^-15 mm rounded down, computed by an integer square
// root, so every robot makes the same decisions. No geometric predicate is
// needed, so this file does not use CGAL.
//
// Shape: rows are the smaller side (robots, or targets when there are fewer
// targets than robots) and columns the larger, so every row is matched.
//   1. Bottleneck: the smallest T such that a matching saturating the rows
//      exists using only pairs with squared distance <= T. Binary search over
//      T, each probe a Hopcroft-Karp maximum matching (phases of shortest
//      augmenting paths) restricted to pairs <= T, warm-started from the
//      best matching so far; probes snap to actual squared distances, so T
//      is one of them.
//   2. Min-sum: the Hungarian method (shortest augmenting paths with
//      potentials) on the integer costs of the pairs <= T; the other pairs
//      are forbidden. It adds rows in order and, among equal candidates,
//      takes the lowest column, which fixes the remaining ties.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>

#include "canonical.h"
#include "exact_rounding.h"
#include "int128.h"
#include "syrof/base/check.h"
#include "syrof/queries/swarm_queries.h"
#include "workspace_storage.h"

namespace syrof::queries {
namespace {

using internal::WorkspaceStorage;

constexpr uint16_t kNone = 0xFFFF;
constexpr uint16_t kUnreached = 0xFFFF;
constexpr uint32_t kForbidden = std::numeric_limits<uint32_t>::max();
constexpr int64_t kInfinity = std::numeric_limits<int64_t>::max() / 4;
// One distance unit of the total: 2^-15 mm. The largest distance in range,
// sqrt(2) * 65535 mm, is then below 2^32 - 1 = kForbidden.
constexpr int kDistanceFractionBits = 15;

uint64_t SquaredDistance(Point a, Point b) {
  const int64_t dx = int64_t{a.x_mm} - b.x_mm;
  const int64_t dy = int64_t{a.y_mm} - b.y_mm;
  return static_cast<uint64_t>(dx * dx + dy * dy);
}

// floor(distance * 2^15) for a squared distance below 2^33.
uint32_t FixedPointDistance(uint64_t squared_mm2) {
  return static_cast<uint32_t>(internal::IntegerSqrt(squared_mm2 << (2 * kDistanceFractionBits)));
}

class Matcher {
 public:
  Matcher(WorkspaceStorage& storage, uint16_t rows, uint16_t columns) : s_(storage), rows_(rows), columns_(columns) {}

  uint64_t Distance2(uint16_t row, uint16_t column) const {
    return SquaredDistance(s_.row_points[row], s_.column_points[column]);
  }

  // Stage 1: the bottleneck value (a matching achieving it is left in
  // best_column_of_row).
  uint64_t Bottleneck() {
    // Every row needs a column, so no threshold below the largest of the
    // rows' nearest distances works (nor, with equal sides, the columns').
    uint64_t low = 0;
    for (uint16_t row = 0; row < rows_; ++row) {
      uint64_t nearest = std::numeric_limits<uint64_t>::max();
      for (uint16_t column = 0; column < columns_; ++column) nearest = std::min(nearest, Distance2(row, column));
      low = std::max(low, nearest);
    }
    if (rows_ == columns_) {
      for (uint16_t column = 0; column < columns_; ++column) {
        uint64_t nearest = std::numeric_limits<uint64_t>::max();
        for (uint16_t row = 0; row < rows_; ++row) nearest = std::min(nearest, Distance2(row, column));
        low = std::max(low, nearest);
      }
    }
    // Row i with column i is a matching, feasible at its own longest pair.
    uint64_t high = 0;
    for (uint16_t row = 0; row < rows_; ++row) {
      s_.best_column_of_row[row] = row;
      high = std::max(high, Distance2(row, row));
    }
    // Invariant: the answer lies in [low, high]; high is feasible with `best`.
    while (low < high) {
      const uint64_t middle = low + (high - low) / 2;
      if (SaturateRows(middle)) {
        high = 0;
        for (uint16_t row = 0; row < rows_; ++row) high = std::max(high, Distance2(row, s_.column_of_row[row]));
        std::copy_n(s_.column_of_row.begin(), rows_, s_.best_column_of_row.begin());
      } else {
        // Feasibility only changes at an actual squared distance.
        uint64_t next = std::numeric_limits<uint64_t>::max();
        for (uint16_t row = 0; row < rows_; ++row) {
          for (uint16_t column = 0; column < columns_; ++column) {
            const uint64_t distance2 = Distance2(row, column);
            if (distance2 > middle && distance2 < next) next = distance2;
          }
        }
        low = next;
      }
    }
    return high;
  }

  // Stage 2: minimum total fixed-point distance over pairs within the
  // bottleneck. Writes row_of_column_1 (1-based rows, 0 = free) and returns
  // the total.
  uint64_t MinimumTotal(uint64_t bottleneck_mm2) {
    uint32_t* costs = s_.costs.data();
    for (uint16_t row = 0; row < rows_; ++row) {
      for (uint16_t column = 0; column < columns_; ++column) {
        const uint64_t distance2 = Distance2(row, column);
        costs[size_t{row} * columns_ + column] =
            distance2 <= bottleneck_mm2 ? FixedPointDistance(distance2) : kForbidden;
      }
    }
    auto& row_potential = s_.row_potential;
    auto& column_potential = s_.column_potential;
    auto& min_slack = s_.min_slack;
    auto& row_of_column = s_.row_of_column_1;
    auto& previous = s_.previous_column;
    auto& visited = s_.column_visited;
    std::fill(row_potential.begin(), row_potential.begin() + rows_ + 1, 0);
    std::fill(column_potential.begin(), column_potential.begin() + columns_ + 1, 0);
    std::fill(row_of_column.begin(), row_of_column.begin() + columns_ + 1, 0);
    for (uint32_t row = 1; row <= rows_; ++row) {
      // Grow a shortest alternating path from `row` (Dijkstra on reduced
      // costs) until it reaches a free column, then flip it.
      row_of_column[0] = static_cast<uint16_t>(row);
      uint16_t column = 0;
      std::fill(min_slack.begin(), min_slack.begin() + columns_ + 1, kInfinity);
      std::fill(visited.begin(), visited.begin() + columns_ + 1, 0);
      do {
        visited[column] = 1;
        const uint16_t current_row = row_of_column[column];
        const uint32_t* row_costs = costs + (size_t{current_row} - 1) * columns_;
        int64_t delta = kInfinity;
        uint16_t next_column = 0;
        for (uint32_t candidate = 1; candidate <= columns_; ++candidate) {
          if (visited[candidate] != 0) continue;
          const uint32_t cost = row_costs[candidate - 1];
          if (cost != kForbidden) {
            const int64_t slack = int64_t{cost} - row_potential[current_row] - column_potential[candidate];
            if (slack < min_slack[candidate]) {
              min_slack[candidate] = slack;
              previous[candidate] = column;
            }
          }
          if (min_slack[candidate] < delta) {  // strict: the lowest column wins ties
            delta = min_slack[candidate];
            next_column = static_cast<uint16_t>(candidate);
          }
        }
        // Stage 1 left a matching within the bottleneck, so by Hall's
        // theorem a free column is always reachable.
        SYROF_CHECK(delta < kInfinity);
        for (uint32_t other = 0; other <= columns_; ++other) {
          if (visited[other] != 0) {
            row_potential[row_of_column[other]] += delta;
            column_potential[other] -= delta;
          } else if (min_slack[other] < kInfinity) {
            min_slack[other] -= delta;
          }
        }
        column = next_column;
      } while (row_of_column[column] != 0);
      do {
        const uint16_t before = previous[column];
        row_of_column[column] = row_of_column[before];
        column = before;
      } while (column != 0);
    }
    uint64_t total = 0;
    for (uint32_t column = 1; column <= columns_; ++column) {
      if (row_of_column[column] != 0) total += costs[(size_t{row_of_column[column]} - 1) * columns_ + column - 1];
    }
    return total;
  }

 private:
  // Hopcroft-Karp from the best matching so far, without its pairs beyond
  // `threshold`: whether every row can be matched using pairs <= threshold.
  // Leaves the matching in column_of_row / row_of_column.
  bool SaturateRows(uint64_t threshold) {
    uint16_t matched = 0;
    std::fill(s_.row_of_column.begin(), s_.row_of_column.begin() + columns_, kNone);
    for (uint16_t row = 0; row < rows_; ++row) {
      const uint16_t column = s_.best_column_of_row[row];
      if (Distance2(row, column) <= threshold) {
        s_.column_of_row[row] = column;
        s_.row_of_column[column] = row;
        ++matched;
      } else {
        s_.column_of_row[row] = kNone;
      }
    }
    while (matched < rows_) {
      if (!BuildLayers(threshold)) return false;
      std::fill(s_.next_column.begin(), s_.next_column.begin() + rows_, 0);
      uint16_t augmented = 0;
      for (uint16_t row = 0; row < rows_; ++row) {
        if (s_.column_of_row[row] == kNone && Augment(row, threshold)) ++augmented;
      }
      // A phase whose layers reach a free column augments at least once.
      SYROF_CHECK(augmented > 0);
      matched = static_cast<uint16_t>(matched + augmented);
    }
    return true;
  }

  // Breadth-first layers of rows from the free rows along alternating paths,
  // up to the first layer with a row next to a free column (the length of
  // the shortest augmenting paths, kept in free_layer_); whether there is one.
  bool BuildLayers(uint64_t threshold) {
    uint16_t head = 0;
    uint16_t tail = 0;
    for (uint16_t row = 0; row < rows_; ++row) {
      if (s_.column_of_row[row] == kNone) {
        s_.layer[row] = 0;
        s_.queue[tail++] = row;
      } else {
        s_.layer[row] = kUnreached;
      }
    }
    free_layer_ = kUnreached;
    while (head < tail) {
      const uint16_t row = s_.queue[head++];
      if (s_.layer[row] > free_layer_) break;  // only longer paths from here on
      for (uint16_t column = 0; column < columns_; ++column) {
        if (Distance2(row, column) > threshold) continue;
        const uint16_t next_row = s_.row_of_column[column];
        if (next_row == kNone) {
          free_layer_ = s_.layer[row];
        } else if (s_.layer[next_row] == kUnreached) {
          s_.layer[next_row] = static_cast<uint16_t>(s_.layer[row] + 1);
          s_.queue[tail++] = next_row;
        }
      }
    }
    return free_layer_ != kUnreached;
  }

  // Depth-first search along increasing layers from a free row to a free
  // column at free_layer_, i.e. a shortest augmenting path (iterative:
  // bounded stack); flips the path if one is found.
  bool Augment(uint16_t start, uint64_t threshold) {
    size_t depth = 0;
    s_.path_rows[0] = start;
    for (;;) {
      const uint16_t row = s_.path_rows[depth];
      bool advanced = false;
      while (s_.next_column[row] < columns_) {
        const uint16_t column = s_.next_column[row]++;
        if (Distance2(row, column) > threshold) continue;
        const uint16_t next_row = s_.row_of_column[column];
        if (next_row == kNone) {
          if (s_.layer[row] != free_layer_) continue;
          s_.path_columns[depth] = column;
          for (size_t step = 0; step <= depth; ++step) {
            s_.column_of_row[s_.path_rows[step]] = s_.path_columns[step];
            s_.row_of_column[s_.path_columns[step]] = s_.path_rows[step];
          }
          return true;
        }
        if (s_.layer[row] < free_layer_ && s_.layer[next_row] == s_.layer[row] + 1) {
          s_.path_columns[depth] = column;
          s_.path_rows[++depth] = next_row;
          advanced = true;
          break;
        }
      }
      if (advanced) continue;
      s_.layer[row] = kUnreached;  // a dead end for the rest of this phase
      if (depth == 0) return false;
      --depth;
    }
  }

  WorkspaceStorage& s_;
  const uint16_t rows_;
  const uint16_t columns_;
  uint16_t free_layer_ = kUnreached;  // set by BuildLayers
};

}  // namespace

base::Result<MatchingSummary, QueryError> MinWeightedMatching(std::span<const Member> members,
                                                              std::span<const Point> targets, Workspace& workspace,
                                                              std::span<Assignment> by_robot,
                                                              std::span<uint16_t> robot_of_target) {
  if (targets.size() > kMaxTargets) return QueryError::kTooManyTargets;
  WorkspaceStorage& storage = internal::WorkspaceAccess::Storage(workspace);
  const base::Result<uint16_t, QueryError> count = internal::CanonicalMembers(members, storage);
  if (!count.ok()) return count.error();
  if (by_robot.size() < members.size() || robot_of_target.size() < targets.size()) {
    return QueryError::kOutputTooSmall;
  }
  const uint16_t robots = count.value();
  const auto target_count = static_cast<uint16_t>(targets.size());
  const bool rows_are_robots = robots <= target_count;
  const uint16_t rows = rows_are_robots ? robots : target_count;
  const uint16_t columns = rows_are_robots ? target_count : robots;

  for (uint16_t robot = 0; robot < robots; ++robot) {
    const Point position{storage.members[robot].x_mm, storage.members[robot].y_mm};
    (rows_are_robots ? storage.row_points : storage.column_points)[robot] = position;
  }
  for (uint16_t target = 0; target < target_count; ++target) {
    (rows_are_robots ? storage.column_points : storage.row_points)[target] = targets[target];
  }

  MatchingSummary summary;
  for (uint16_t robot = 0; robot < robots; ++robot) by_robot[robot] = {storage.members[robot].id, kNoTarget};
  for (uint16_t target = 0; target < target_count; ++target) robot_of_target[target] = kNoRobot;
  if (rows == 0) return summary;

  Matcher matcher(storage, rows, columns);
  const uint64_t bottleneck_mm2 = matcher.Bottleneck();
  summary.total_distance_q15_mm = matcher.MinimumTotal(bottleneck_mm2);
  summary.matched_count = rows;
  for (uint32_t column = 1; column <= columns; ++column) {
    const uint16_t row_1 = storage.row_of_column_1[column];
    if (row_1 == 0) continue;
    const uint16_t robot = rows_are_robots ? static_cast<uint16_t>(row_1 - 1) : static_cast<uint16_t>(column - 1);
    const uint16_t target = rows_are_robots ? static_cast<uint16_t>(column - 1) : static_cast<uint16_t>(row_1 - 1);
    by_robot[robot].target_index = target;
    robot_of_target[target] = storage.members[robot].id;
    summary.bottleneck_squared_mm2 =
        std::max(summary.bottleneck_squared_mm2,
                 matcher.Distance2(static_cast<uint16_t>(row_1 - 1), static_cast<uint16_t>(column - 1)));
  }
  // The min-sum stage only used pairs within the bottleneck, and no
  // matching does better, so its longest pair is the bottleneck.
  SYROF_CHECK(summary.bottleneck_squared_mm2 == bottleneck_mm2);
  summary.bottleneck_m = internal::NearestFloatOfSqrtQuotient(internal::Int128(static_cast<int64_t>(bottleneck_mm2)),
                                                              internal::Int128(1'000'000));
  summary.total_m =
      internal::NearestFloatOfQuotient(internal::Int128(static_cast<int64_t>(summary.total_distance_q15_mm)),
                                       internal::Int128(int64_t{1000} << kDistanceFractionBits));
  return summary;
}

}  // namespace syrof::queries
