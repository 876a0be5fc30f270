// ConvexHull against gift wrapping, its properties, and degenerate input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "query_test_support.h"
#include "syrof/queries/swarm_queries.h"

namespace syrof::queries {
namespace {

using testing::Orientation;
using testing::RandomMembers;
using testing::Rng;
using testing::Shuffle;
using testing::SquaredDistance;

Workspace& SharedWorkspace() {
  static Workspace workspace;  // large on the host: not on the stack
  return workspace;
}

std::vector<uint16_t> Hull(const std::vector<Member>& members) {
  std::vector<uint16_t> ids(members.size() + 1, 0xBEEF);
  const auto count = ConvexHull(members, SharedWorkspace(), ids);
  EXPECT_TRUE(count.ok()) << ToString(count.error());
  if (!count.ok()) return {};
  EXPECT_EQ(ids[count.value()], 0xBEEF) << "wrote past the count";
  ids.resize(count.value());
  return ids;
}

bool LessXy(Point a, Point b) { return a.x_mm != b.x_mm ? a.x_mm < b.x_mm : a.y_mm < b.y_mm; }

// The hull's corners by gift wrapping (Jarvis march), counter-clockwise from
// the smallest (x, y): from each corner, the next is the point with every
// other point on its left, the farthest one among collinear candidates.
std::vector<Point> GiftWrapCorners(std::vector<Point> points) {
  std::sort(points.begin(), points.end(), LessXy);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() <= 1) return points;
  std::vector<Point> corners = {points[0]};
  Point current = points[0];
  for (size_t step = 0; step <= points.size(); ++step) {
    Point next = current == points[0] ? points[1] : points[0];
    for (const Point& candidate : points) {
      if (candidate == current) continue;
      const int turn = Orientation(current, next, candidate);
      if (turn < 0 || (turn == 0 && SquaredDistance(current, candidate) > SquaredDistance(current, next))) {
        next = candidate;
      }
    }
    if (next == points[0]) return corners;
    corners.push_back(next);
    current = next;
  }
  ADD_FAILURE() << "gift wrapping did not close";
  return corners;
}

// The ids ConvexHull must return: every member at each corner, ids increasing.
std::vector<uint16_t> ExpectedHull(const std::vector<Member>& members) {
  std::vector<uint16_t> ids;
  for (const Point& corner : GiftWrapCorners(testing::Positions(members))) {
    std::vector<uint16_t> here;
    for (const Member& member : members) {
      if (member.position == corner) here.push_back(member.id);
    }
    std::sort(here.begin(), here.end());
    ids.insert(ids.end(), here.begin(), here.end());
  }
  return ids;
}

TEST(ConvexHullTest, MatchesGiftWrappingOnRandomSets) {
  Rng rng(21);
  // Small extents make collinear and coincident points common.
  for (const int32_t extent : {3, 20, 1000, 32767}) {
    for (int trial = 0; trial < 150; ++trial) {
      const size_t count = 1 + rng.Below(std::min<uint32_t>(60, kMaxMembers));
      const std::vector<Member> members = RandomMembers(rng, count, extent);
      ASSERT_EQ(Hull(members), ExpectedHull(members)) << "extent " << extent << " trial " << trial;
    }
  }
}

TEST(ConvexHullTest, IsIndependentOfMemberOrder) {
  Rng rng(22);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Member> members = RandomMembers(rng, 1 + rng.Below(kMaxMembers), trial % 2 == 0 ? 10 : 30000);
    const std::vector<uint16_t> expected = Hull(members);
    for (int shuffle = 0; shuffle < 3; ++shuffle) {
      Shuffle(members, rng);
      ASSERT_EQ(Hull(members), expected);
    }
  }
}

TEST(ConvexHullTest, ContainsEveryMemberAndTurnsLeftAtEveryCorner) {
  Rng rng(23);
  for (int trial = 0; trial < 30; ++trial) {
    const std::vector<Member> members = RandomMembers(rng, kMaxMembers, trial % 3 == 0 ? 50 : 32767);
    const std::vector<uint16_t> ids = Hull(members);
    std::vector<Point> corners;
    for (const uint16_t id : ids) {
      const Point position =
          std::find_if(members.begin(), members.end(), [id](const Member& m) { return m.id == id; })->position;
      if (corners.empty() || !(corners.back() == position)) corners.push_back(position);
    }
    ASSERT_GE(corners.size(), 3u);
    for (size_t index = 0; index < corners.size(); ++index) {
      const Point a = corners[index];
      const Point b = corners[(index + 1) % corners.size()];
      const Point c = corners[(index + 2) % corners.size()];
      ASSERT_EQ(Orientation(a, b, c), 1) << "corner " << index << " is not a strict left turn";
      for (const Member& member : members) ASSERT_GE(Orientation(a, b, member.position), 0);
    }
    // Starts at the smallest (x, y).
    for (const Member& member : members) ASSERT_FALSE(LessXy(member.position, corners[0]));
  }
}

TEST(ConvexHullTest, EmptyAndSingleMember) {
  EXPECT_EQ(Hull({}), std::vector<uint16_t>{});
  EXPECT_EQ(Hull({{7, {100, -100}}}), std::vector<uint16_t>{7});
}

TEST(ConvexHullTest, AllAtOnePositionListsEveryMember) {
  EXPECT_EQ(Hull({{5, {3, 3}}, {1, {3, 3}}, {9, {3, 3}}}), (std::vector<uint16_t>{1, 5, 9}));
}

TEST(ConvexHullTest, CollinearMembersGiveTheTwoEnds) {
  // On a diagonal line, with coincident members at one end.
  EXPECT_EQ(Hull({{1, {2, 2}}, {2, {0, 0}}, {3, {4, 4}}, {4, {1, 1}}, {0, {4, 4}}}), (std::vector<uint16_t>{2, 0, 3}));
  // Vertical: the lower end comes first.
  EXPECT_EQ(Hull({{1, {0, 5}}, {2, {0, -5}}, {3, {0, 0}}}), (std::vector<uint16_t>{2, 1}));
  EXPECT_EQ(Hull({{1, {8, 1}}, {2, {-3, 1}}}), (std::vector<uint16_t>{2, 1}));
}

TEST(ConvexHullTest, PointsOnEdgesAndInsideAreLeftOut) {
  // A square with a member in the middle of each edge and one inside;
  // counter-clockwise from (0, 0).
  const std::vector<Member> members = {{0, {0, 0}},  {1, {10, 0}}, {2, {10, 10}}, {3, {0, 10}}, {4, {5, 0}},
                                       {5, {10, 5}}, {6, {5, 10}}, {7, {0, 5}},   {8, {5, 5}}};
  EXPECT_EQ(Hull(members), (std::vector<uint16_t>{0, 1, 2, 3}));
}

TEST(ConvexHullTest, CoincidentMembersAtCornersAreAllListed) {
  const std::vector<Member> members = {{10, {0, 0}}, {3, {0, 0}}, {4, {6, 0}}, {8, {0, 6}}, {2, {0, 6}}, {1, {1, 1}}};
  EXPECT_EQ(Hull(members), (std::vector<uint16_t>{3, 10, 4, 2, 8}));
}

TEST(ConvexHullTest, ExtremeCoordinates) {
  const std::vector<Member> members = {{0, {-32768, -32768}}, {1, {32767, -32768}}, {2, {32767, 32767}},
                                       {3, {-32768, 32767}},  {4, {0, 0}},          {5, {32767, 0}},
                                       {6, {-32767, 32767}}};
  EXPECT_EQ(Hull(members), (std::vector<uint16_t>{0, 1, 2, 3}));
  // A nearly flat triangle at full range: the middle point is 1 mm off the line.
  EXPECT_EQ(Hull({{0, {-32768, -32768}}, {1, {32767, 32766}}, {2, {0, -1}}}), (std::vector<uint16_t>{0, 2, 1}));
  EXPECT_EQ(Hull({{0, {-32768, -32768}}, {1, {32767, 32767}}, {2, {0, 0}}}), (std::vector<uint16_t>{0, 1}));
}

TEST(ConvexHullTest, RejectsBadInputAndShortOutput) {
  Workspace& workspace = SharedWorkspace();
  std::vector<uint16_t> ids(4);
  const std::vector<Member> members = {{1, {0, 0}}, {2, {1, 0}}, {3, {0, 1}}};
  EXPECT_EQ(ConvexHull(members, workspace, std::span<uint16_t>(ids.data(), 2)).error(), QueryError::kOutputTooSmall);
  EXPECT_EQ(ConvexHull(std::vector<Member>{{1, {0, 0}}, {1, {1, 1}}}, workspace, ids).error(),
            QueryError::kDuplicateId);
  EXPECT_EQ(ConvexHull(std::vector<Member>{{kMaxMembers, {0, 0}}}, workspace, ids).error(), QueryError::kIdOutOfRange);
  // The same workspace still works after errors.
  EXPECT_EQ(ConvexHull(members, workspace, ids).value(), 3);
}

}  // namespace
}  // namespace syrof::queries
