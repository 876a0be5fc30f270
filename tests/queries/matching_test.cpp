// MinWeightedMatching against the brute force over all assignments (up to 8
// robots and 8 targets), optimality certificates on larger sets, order
// independence and degenerate input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "query_test_support.h"
#include "syrof/queries/swarm_queries.h"

namespace syrof::queries {
namespace {

using testing::RandomMembers;
using testing::RandomPoints;
using testing::ReferenceFixedDistance;
using testing::Rng;
using testing::Shuffle;
using testing::SquaredDistance;

Workspace& SharedWorkspace() {
  static Workspace workspace;
  return workspace;
}

struct Outcome {
  std::vector<Assignment> by_robot;
  std::vector<uint16_t> robot_of_target;
  MatchingSummary summary;
};

Outcome Match(const std::vector<Member>& members, const std::vector<Point>& targets) {
  Outcome outcome;
  outcome.by_robot.assign(members.size(), Assignment{0xBEEF, 0xBEEF});
  outcome.robot_of_target.assign(targets.size(), 0xBEEF);
  const auto summary =
      MinWeightedMatching(members, targets, SharedWorkspace(), outcome.by_robot, outcome.robot_of_target);
  EXPECT_TRUE(summary.ok()) << ToString(summary.error());
  if (summary.ok()) outcome.summary = summary.value();
  return outcome;
}

// The problem as rows (the smaller side, every one matched) and columns.
struct Sides {
  std::vector<Point> rows;
  std::vector<Point> columns;
};

Sides ToSides(std::vector<Member> members, const std::vector<Point>& targets) {
  std::sort(members.begin(), members.end(), [](const Member& a, const Member& b) { return a.id < b.id; });
  const std::vector<Point> robots = testing::Positions(members);
  return robots.size() <= targets.size() ? Sides{robots, targets} : Sides{targets, robots};
}

// Each row's column in the outcome (rows and columns as in ToSides).
std::vector<size_t> ColumnOfRow(const std::vector<Member>& members, const std::vector<Point>& targets,
                                const Outcome& outcome) {
  std::vector<size_t> columns;
  if (members.size() <= targets.size()) {
    for (const Assignment& assignment : outcome.by_robot) columns.push_back(assignment.target_index);
  } else {
    for (const uint16_t robot_id : outcome.robot_of_target) {
      const auto robot = std::find_if(outcome.by_robot.begin(), outcome.by_robot.end(),
                                      [robot_id](const Assignment& a) { return a.robot_id == robot_id; });
      columns.push_back(static_cast<size_t>(robot - outcome.by_robot.begin()));
    }
  }
  return columns;
}

struct Objective {
  uint64_t bottleneck_mm2 = 0;
  uint64_t total_q15_mm = 0;
  friend bool operator==(const Objective&, const Objective&) = default;
  bool operator<(const Objective& other) const {
    return bottleneck_mm2 != other.bottleneck_mm2 ? bottleneck_mm2 < other.bottleneck_mm2
                                                  : total_q15_mm < other.total_q15_mm;
  }
};

Objective Evaluate(const Sides& sides, const std::vector<size_t>& column_of_row) {
  Objective objective;
  for (size_t row = 0; row < sides.rows.size(); ++row) {
    const uint64_t distance2 = SquaredDistance(sides.rows[row], sides.columns[column_of_row[row]]);
    objective.bottleneck_mm2 = std::max(objective.bottleneck_mm2, distance2);
    objective.total_q15_mm += ReferenceFixedDistance(distance2);
  }
  return objective;
}

// Every way to give each row its own column; the best objective.
Objective BruteForce(const Sides& sides) {
  const size_t rows = sides.rows.size();
  const size_t columns = sides.columns.size();
  // Each pair's squared distance and fixed-point distance, computed once.
  std::vector<Objective> pair(rows * columns);
  for (size_t row = 0; row < rows; ++row) {
    for (size_t column = 0; column < columns; ++column) {
      const uint64_t distance2 = SquaredDistance(sides.rows[row], sides.columns[column]);
      pair[row * columns + column] = {distance2, ReferenceFixedDistance(distance2)};
    }
  }
  Objective best{std::numeric_limits<uint64_t>::max(), std::numeric_limits<uint64_t>::max()};
  std::vector<bool> used(columns, false);
  const auto recurse = [&](auto&& self, size_t row, Objective so_far) -> void {
    if (row == rows) {
      best = std::min(best, so_far);
      return;
    }
    for (size_t column = 0; column < columns; ++column) {
      if (used[column]) continue;
      used[column] = true;
      const Objective& here = pair[row * columns + column];
      self(self, row + 1,
           Objective{std::max(so_far.bottleneck_mm2, here.bottleneck_mm2), so_far.total_q15_mm + here.total_q15_mm});
      used[column] = false;
    }
  };
  recurse(recurse, 0, Objective{});
  return best;
}

// The outcome is a matching of min(robots, targets) pairs, reported
// consistently both ways, with the summary it claims.
void ExpectConsistent(const std::vector<Member>& members, const std::vector<Point>& targets, const Outcome& outcome) {
  std::vector<Member> sorted = members;
  std::sort(sorted.begin(), sorted.end(), [](const Member& a, const Member& b) { return a.id < b.id; });
  ASSERT_EQ(outcome.by_robot.size(), sorted.size());
  size_t matched = 0;
  for (size_t index = 0; index < sorted.size(); ++index) {
    const Assignment& assignment = outcome.by_robot[index];
    ASSERT_EQ(assignment.robot_id, sorted[index].id);
    if (assignment.target_index == kNoTarget) continue;
    ASSERT_LT(assignment.target_index, targets.size());
    ASSERT_EQ(outcome.robot_of_target[assignment.target_index], assignment.robot_id);
    ++matched;
  }
  size_t targets_taken = 0;
  for (const uint16_t robot : outcome.robot_of_target) targets_taken += robot != kNoRobot ? 1 : 0;
  ASSERT_EQ(matched, std::min(members.size(), targets.size()));
  ASSERT_EQ(targets_taken, matched);
  ASSERT_EQ(outcome.summary.matched_count, matched);
  const Sides sides = ToSides(members, targets);
  const Objective claimed{outcome.summary.bottleneck_squared_mm2, outcome.summary.total_distance_q15_mm};
  ASSERT_EQ(Evaluate(sides, ColumnOfRow(members, targets, outcome)), claimed);
  // Nearest floats: within half an ulp (2^-24 relative) of the exact values.
  const double bottleneck_m = std::sqrt(double(claimed.bottleneck_mm2)) / 1000;
  const double total_m = double(claimed.total_q15_mm) / 32768 / 1000;
  EXPECT_NEAR(outcome.summary.bottleneck_m, bottleneck_m, 6e-8 * bottleneck_m);
  EXPECT_NEAR(outcome.summary.total_m, total_m, 6e-8 * total_m);
}

TEST(MinWeightedMatchingTest, MatchesBruteForceOverAllAssignments) {
  Rng rng(41);
  for (const int32_t extent : {2, 30, 32767}) {
    for (int trial = 0; trial < 120; ++trial) {
      const size_t robots = std::min<size_t>(rng.Below(9), kMaxMembers);
      const size_t target_count = rng.Below(9);
      const std::vector<Member> members = RandomMembers(rng, robots, extent);
      const std::vector<Point> targets = RandomPoints(rng, target_count, extent);
      const Outcome outcome = Match(members, targets);
      ExpectConsistent(members, targets, outcome);
      const Objective claimed{outcome.summary.bottleneck_squared_mm2, outcome.summary.total_distance_q15_mm};
      ASSERT_EQ(claimed, BruteForce(ToSides(members, targets)))
          << "extent " << extent << " trial " << trial << ": " << robots << " robots, " << target_count << " targets";
    }
  }
}

// Whether every row can get its own column within `threshold` (Kuhn's
// augmenting paths, independent of the library's Hopcroft-Karp).
bool SaturatesRows(const Sides& sides, uint64_t threshold) {
  std::vector<int> row_of_column(sides.columns.size(), -1);
  for (size_t row = 0; row < sides.rows.size(); ++row) {
    std::vector<bool> seen(sides.columns.size(), false);
    const auto augment = [&](auto&& self, size_t r) -> bool {
      for (size_t column = 0; column < sides.columns.size(); ++column) {
        if (seen[column] || SquaredDistance(sides.rows[r], sides.columns[column]) > threshold) continue;
        seen[column] = true;
        if (row_of_column[column] < 0 || self(self, static_cast<size_t>(row_of_column[column]))) {
          row_of_column[column] = static_cast<int>(r);
          return true;
        }
      }
      return false;
    };
    if (!augment(augment, row)) return false;
  }
  return true;
}

// Whether no assignment within the bottleneck has a smaller total: no
// negative cycle in the residual graph (Bellman-Ford), with dummy rows of
// cost 0 holding the free columns.
bool IsMinimumTotal(const Sides& sides, const std::vector<size_t>& column_of_row, uint64_t bottleneck_mm2) {
  const size_t n = sides.columns.size();  // rows padded to n; nodes: rows 0..n-1, columns n..2n-1
  std::vector<size_t> column(column_of_row);
  std::vector<bool> taken(n, false);
  for (const size_t c : column) taken[c] = true;
  for (size_t c = 0; c < n; ++c) {
    if (!taken[c]) column.push_back(c);
  }
  struct Edge {
    size_t from, to;
    int64_t weight;
  };
  std::vector<Edge> edges;
  for (size_t row = 0; row < n; ++row) {
    for (size_t c = 0; c < n; ++c) {
      int64_t weight = 0;
      if (row < sides.rows.size()) {
        const uint64_t distance2 = SquaredDistance(sides.rows[row], sides.columns[c]);
        if (distance2 > bottleneck_mm2) continue;
        weight = static_cast<int64_t>(ReferenceFixedDistance(distance2));
      }
      if (column[row] == c) {
        edges.push_back({n + c, row, -weight});
      } else {
        edges.push_back({row, n + c, weight});
      }
    }
  }
  std::vector<int64_t> distance(2 * n, 0);
  for (size_t round = 0; round < 2 * n; ++round) {
    bool changed = false;
    for (const Edge& edge : edges) {
      if (distance[edge.from] + edge.weight < distance[edge.to]) {
        distance[edge.to] = distance[edge.from] + edge.weight;
        changed = true;
      }
    }
    if (!changed) return true;
  }
  return false;
}

TEST(MinWeightedMatchingTest, LargerSetsPassOptimalityCertificates) {
  Rng rng(42);
  for (int trial = 0; trial < 30; ++trial) {
    const size_t robots = 1 + rng.Below(std::min<uint32_t>(40, kMaxMembers));
    const size_t target_count = 1 + rng.Below(std::min<uint32_t>(40, kMaxTargets));
    const int32_t extent = trial % 3 == 0 ? 4 : 32767;
    const std::vector<Member> members = RandomMembers(rng, robots, extent);
    const std::vector<Point> targets = RandomPoints(rng, target_count, extent);
    const Outcome outcome = Match(members, targets);
    ExpectConsistent(members, targets, outcome);
    const Sides sides = ToSides(members, targets);
    const uint64_t bottleneck = outcome.summary.bottleneck_squared_mm2;
    ASSERT_TRUE(SaturatesRows(sides, bottleneck));
    if (bottleneck > 0) {
      ASSERT_FALSE(SaturatesRows(sides, bottleneck - 1)) << "bottleneck not minimal";
    }
    ASSERT_TRUE(IsMinimumTotal(sides, ColumnOfRow(members, targets, outcome), bottleneck)) << "trial " << trial;
  }
}

TEST(MinWeightedMatchingTest, CertificatesRejectWorseAssignments) {
  // The checks above must be able to fail: crossing two robots over is worse.
  const Sides sides{{{0, 0}, {1000, 0}}, {{0, 0}, {1000, 0}, {5000, 0}}};
  EXPECT_TRUE(IsMinimumTotal(sides, {0, 1}, 25'000'000));
  EXPECT_FALSE(IsMinimumTotal(sides, {1, 0}, 25'000'000));
  EXPECT_FALSE(IsMinimumTotal(sides, {2, 1}, 25'000'000));  // a free column is better
  EXPECT_TRUE(SaturatesRows(sides, 0));
  EXPECT_FALSE(SaturatesRows(Sides{{{0, 0}, {1, 0}}, {{0, 0}, {9, 0}}}, 63));
}

TEST(MinWeightedMatchingTest, IsIndependentOfMemberOrder) {
  Rng rng(43);
  for (int trial = 0; trial < 30; ++trial) {
    // Small extents: many equally good assignments, so the tie rule shows.
    std::vector<Member> members = RandomMembers(rng, 1 + rng.Below(std::min<uint32_t>(24, kMaxMembers)), 3);
    const std::vector<Point> targets = RandomPoints(rng, 1 + rng.Below(24), 3);
    const Outcome expected = Match(members, targets);
    for (int shuffle = 0; shuffle < 3; ++shuffle) {
      Shuffle(members, rng);
      const Outcome outcome = Match(members, targets);
      ASSERT_EQ(outcome.by_robot, expected.by_robot);
      ASSERT_EQ(outcome.robot_of_target, expected.robot_of_target);
      ASSERT_EQ(outcome.summary.total_distance_q15_mm, expected.summary.total_distance_q15_mm);
    }
  }
}

TEST(MinWeightedMatchingTest, BottleneckComesBeforeTotal) {
  // Robots at 0, 1, 2 m and targets at 1, 2, 3 m on a line: shifting every
  // robot by 1 m and sending the first robot 3 m both total 3 m; the
  // bottleneck picks the shift.
  const std::vector<Member> members = {{0, {0, 0}}, {1, {1000, 0}}, {2, {2000, 0}}};
  const std::vector<Point> targets = {{1000, 0}, {2000, 0}, {3000, 0}};
  const Outcome outcome = Match(members, targets);
  EXPECT_EQ(outcome.by_robot, (std::vector<Assignment>{{0, 0}, {1, 1}, {2, 2}}));
  EXPECT_EQ(outcome.summary.bottleneck_squared_mm2, 1'000'000u);
  EXPECT_EQ(outcome.summary.bottleneck_m, 1.0f);
  EXPECT_EQ(outcome.summary.total_m, 3.0f);
}

TEST(MinWeightedMatchingTest, MoreTargetsThanRobotsLeavesTargetsFree) {
  const std::vector<Member> members = {{7, {0, 0}}, {3, {1000, 0}}};
  const std::vector<Point> targets = {{5000, 5000}, {1000, 100}, {0, -100}, {-3000, 0}};
  const Outcome outcome = Match(members, targets);
  EXPECT_EQ(outcome.by_robot, (std::vector<Assignment>{{3, 1}, {7, 2}}));
  EXPECT_EQ(outcome.robot_of_target, (std::vector<uint16_t>{kNoRobot, 3, 7, kNoRobot}));
  EXPECT_EQ(outcome.summary.matched_count, 2);
}

TEST(MinWeightedMatchingTest, FewerTargetsThanRobotsLeavesRobotsWithout) {
  const std::vector<Member> members = {{0, {0, 0}}, {1, {1000, 0}}, {2, {2000, 0}}, {3, {9000, 0}}};
  const std::vector<Point> targets = {{8000, 0}, {1500, 0}};
  const Outcome outcome = Match(members, targets);
  ExpectConsistent(members, targets, outcome);
  EXPECT_EQ(outcome.robot_of_target[0], 3);
  EXPECT_EQ(outcome.by_robot[0].target_index, kNoTarget);
  EXPECT_EQ(outcome.summary.bottleneck_squared_mm2, 1000u * 1000u);  // robot 3 to the first target
}

TEST(MinWeightedMatchingTest, EmptySidesAndCoincidentPoints) {
  Outcome outcome = Match({}, {{0, 0}, {5, 5}});
  EXPECT_EQ(outcome.robot_of_target, (std::vector<uint16_t>{kNoRobot, kNoRobot}));
  EXPECT_EQ(outcome.summary.matched_count, 0);
  outcome = Match({{4, {1, 1}}, {2, {2, 2}}}, {});
  EXPECT_EQ(outcome.by_robot, (std::vector<Assignment>{{2, kNoTarget}, {4, kNoTarget}}));
  EXPECT_EQ(outcome.summary.bottleneck_m, 0.0f);
  outcome = Match({}, {});
  EXPECT_EQ(outcome.summary.matched_count, 0);
  // Robots already on their targets: nothing to travel.
  outcome = Match({{1, {10, 10}}, {2, {-10, 4}}}, {{-10, 4}, {10, 10}});
  EXPECT_EQ(outcome.by_robot, (std::vector<Assignment>{{1, 1}, {2, 0}}));
  EXPECT_EQ(outcome.summary.total_distance_q15_mm, 0u);
  // Every robot and target at one point.
  outcome = Match({{1, {5, 5}}, {2, {5, 5}}, {3, {5, 5}}}, {{5, 5}, {5, 5}});
  ExpectConsistent({{1, {5, 5}}, {2, {5, 5}}, {3, {5, 5}}}, {{5, 5}, {5, 5}}, outcome);
  EXPECT_EQ(outcome.summary.bottleneck_squared_mm2, 0u);
}

TEST(MinWeightedMatchingTest, FullRangeDistances) {
  const std::vector<Member> members = {{0, {-32768, -32768}}, {1, {32767, 32767}}};
  const std::vector<Point> targets = {{32767, 32767}, {-32768, -32768}};
  const Outcome outcome = Match(members, targets);
  EXPECT_EQ(outcome.summary.bottleneck_squared_mm2, 0u);
  const Outcome swapped = Match(members, {{-32768, 32767}, {32767, -32768}});
  EXPECT_EQ(swapped.summary.bottleneck_squared_mm2, 65535ull * 65535ull);
  const Outcome far = Match({{0, {-32768, -32768}}}, {{32767, 32767}});
  EXPECT_EQ(far.summary.bottleneck_squared_mm2, 2 * 65535ull * 65535ull);
  EXPECT_EQ(far.summary.total_distance_q15_mm, ReferenceFixedDistance(2 * 65535ull * 65535ull));
  EXPECT_EQ(far.summary.bottleneck_m, static_cast<float>(std::sqrt(2.0) * 65.535));
}

TEST(MinWeightedMatchingTest, RejectsBadInputWithoutTouchingOutputs) {
  Workspace& workspace = SharedWorkspace();
  std::vector<Assignment> by_robot(2, Assignment{0xBEEF, 0xBEEF});
  std::vector<uint16_t> robot_of_target(2, 0xBEEF);
  const std::vector<Member> members = {{1, {0, 0}}, {2, {1, 1}}};
  const std::vector<Point> targets = {{0, 0}, {1, 1}};
  EXPECT_EQ(MinWeightedMatching(members, targets, workspace, std::span<Assignment>(by_robot.data(), 1), robot_of_target)
                .error(),
            QueryError::kOutputTooSmall);
  EXPECT_EQ(MinWeightedMatching(members, targets, workspace, by_robot, std::span<uint16_t>(robot_of_target.data(), 1))
                .error(),
            QueryError::kOutputTooSmall);
  EXPECT_EQ(
      MinWeightedMatching(std::vector<Member>{{1, {0, 0}}, {1, {0, 0}}}, targets, workspace, by_robot, robot_of_target)
          .error(),
      QueryError::kDuplicateId);
  const std::vector<Point> too_many(size_t{kMaxTargets} + 1);
  std::vector<uint16_t> large_output(too_many.size());
  EXPECT_EQ(MinWeightedMatching(members, too_many, workspace, by_robot, large_output).error(),
            QueryError::kTooManyTargets);
  EXPECT_EQ(by_robot[0].robot_id, 0xBEEF);
  EXPECT_EQ(robot_of_target[0], 0xBEEF);
}

}  // namespace
}  // namespace syrof::queries
