// ShortestEnclosingCircle against the brute force over all circles through
// 2 and 3 members, exact containment and minimality checks, and degenerate
// input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "int128.h"
#include "query_test_support.h"
#include "syrof/queries/swarm_queries.h"

namespace syrof::queries {
namespace {

using internal::Int128;
using testing::Orientation;
using testing::RandomMembers;
using testing::Rng;
using testing::Shuffle;

Workspace& SharedWorkspace() {
  static Workspace workspace;
  return workspace;
}

Circle Enclose(const std::vector<Member>& members) {
  const auto circle = ShortestEnclosingCircle(members, SharedWorkspace());
  EXPECT_TRUE(circle.ok()) << ToString(circle.error());
  return circle.ok() ? circle.value() : Circle{};
}

// Exact closed-disc tests, written independently of the library (which uses
// CGAL's predicates translated to the first point; these translate to t).
bool InDiametralDisc(Point a, Point b, Point t) {
  const int64_t dot =
      (int64_t{a.x_mm} - t.x_mm) * (int64_t{b.x_mm} - t.x_mm) + (int64_t{a.y_mm} - t.y_mm) * (int64_t{b.y_mm} - t.y_mm);
  return dot <= 0;
}

bool InCircumdisc(Point a, Point b, Point c, Point t) {
  const auto row = [&t](Point p) {
    const int64_t x = int64_t{p.x_mm} - t.x_mm;
    const int64_t y = int64_t{p.y_mm} - t.y_mm;
    return std::array<int64_t, 3>{x, y, x * x + y * y};
  };
  const auto ra = row(a);
  const auto rb = row(b);
  const auto rc = row(c);
  // det [ra; rb; rc] by the first column; each minor fits int64.
  const Int128 determinant = Int128::Product(ra[0], rb[1] * rc[2] - rb[2] * rc[1]) -
                             Int128::Product(rb[0], ra[1] * rc[2] - ra[2] * rc[1]) +
                             Int128::Product(rc[0], ra[1] * rb[2] - ra[2] * rb[1]);
  return determinant.sign() * Orientation(a, b, c) >= 0;
}

struct Candidate {
  double centre_x_mm = 0;
  double centre_y_mm = 0;
  double radius_mm = std::numeric_limits<double>::infinity();
};

Candidate Circumcircle(Point a, Point b, Point c) {
  const double bx = b.x_mm - a.x_mm, by = b.y_mm - a.y_mm;
  const double cx = c.x_mm - a.x_mm, cy = c.y_mm - a.y_mm;
  const double d = 2 * (bx * cy - by * cx);
  const double ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d;
  const double uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d;
  return {a.x_mm + ux, a.y_mm + uy, std::sqrt(ux * ux + uy * uy)};
}

// The brute force: every circle with two members as a diameter or three
// (not collinear) on it, kept when it holds every member exactly; the
// smallest radius wins.
Candidate BruteForce(const std::vector<Point>& points) {
  Candidate best;
  if (points.size() == 1) return {double(points[0].x_mm), double(points[0].y_mm), 0.0};
  const auto holds_all = [&points](auto&& contains) { return std::all_of(points.begin(), points.end(), contains); };
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      const Point a = points[i], b = points[j];
      if (holds_all([&](Point t) { return InDiametralDisc(a, b, t); })) {
        const double radius = std::sqrt(double(testing::SquaredDistance(a, b))) / 2;
        if (radius < best.radius_mm) best = {(a.x_mm + b.x_mm) / 2.0, (a.y_mm + b.y_mm) / 2.0, radius};
      }
      for (size_t k = j + 1; k < points.size(); ++k) {
        const Point c = points[k];
        if (Orientation(a, b, c) == 0) continue;
        if (holds_all([&](Point t) { return InCircumdisc(a, b, c, t); })) {
          const Candidate candidate = Circumcircle(a, b, c);
          if (candidate.radius_mm < best.radius_mm) best = candidate;
        }
      }
    }
  }
  return best;
}

Point PositionOf(const std::vector<Member>& members, uint16_t id) {
  return std::find_if(members.begin(), members.end(), [id](const Member& m) { return m.id == id; })->position;
}

// Checks the circle exactly through its support: the support's circle holds
// every member and is the smallest such (two ends of a diameter, or three
// points whose triangle has no obtuse angle), and the floats are close to it.
void ExpectExactlyMinimal(const std::vector<Member>& members, const Circle& circle) {
  ASSERT_GE(circle.support_count, 1);
  ASSERT_LE(circle.support_count, 3);
  std::vector<Point> support;
  for (uint8_t index = 0; index < circle.support_count; ++index) {
    if (index > 0) {
      ASSERT_LT(circle.support_ids[index - 1], circle.support_ids[index]);
    }
    support.push_back(PositionOf(members, circle.support_ids[index]));
    // The smallest id at that position stands for it.
    for (const Member& member : members) {
      if (member.position == support.back()) {
        ASSERT_GE(member.id, circle.support_ids[index]);
      }
    }
  }
  for (uint8_t index = circle.support_count; index < 3; ++index) ASSERT_EQ(circle.support_ids[index], kNoRobot);
  Candidate exact;
  switch (circle.support_count) {
    case 1:
      for (const Member& member : members) ASSERT_EQ(member.position, support[0]);
      exact = {double(support[0].x_mm), double(support[0].y_mm), 0.0};
      break;
    case 2:
      for (const Member& member : members) ASSERT_TRUE(InDiametralDisc(support[0], support[1], member.position));
      exact = {(support[0].x_mm + support[1].x_mm) / 2.0, (support[0].y_mm + support[1].y_mm) / 2.0,
               std::sqrt(double(testing::SquaredDistance(support[0], support[1]))) / 2};
      break;
    default: {
      ASSERT_NE(Orientation(support[0], support[1], support[2]), 0);
      for (const Member& member : members) {
        ASSERT_TRUE(InCircumdisc(support[0], support[1], support[2], member.position));
      }
      for (int corner = 0; corner < 3; ++corner) {  // no obtuse angle
        const Point p = support[corner], q = support[(corner + 1) % 3], r = support[(corner + 2) % 3];
        const int64_t dot =
            (int64_t{q.x_mm} - p.x_mm) * (r.x_mm - p.x_mm) + (int64_t{q.y_mm} - p.y_mm) * (r.y_mm - p.y_mm);
        ASSERT_GE(dot, 0);
      }
      exact = Circumcircle(support[0], support[1], support[2]);
    }
  }
  const double tolerance_m = 1e-6 + 1e-6 * exact.radius_mm / 1000;
  EXPECT_NEAR(circle.centre_x_m, exact.centre_x_mm / 1000, tolerance_m);
  EXPECT_NEAR(circle.centre_y_m, exact.centre_y_mm / 1000, tolerance_m);
  EXPECT_NEAR(circle.radius_m, exact.radius_mm / 1000, tolerance_m);
}

TEST(ShortestEnclosingCircleTest, MatchesBruteForceOverAllTwoAndThreePointCircles) {
  Rng rng(31);
  for (const int32_t extent : {2, 10, 1000, 32767}) {
    for (int trial = 0; trial < 120; ++trial) {
      const size_t count = 1 + rng.Below(std::min<uint32_t>(14, kMaxMembers));
      const std::vector<Member> members = RandomMembers(rng, count, extent);
      const Candidate expected = BruteForce(testing::Positions(members));
      const Circle circle = Enclose(members);
      const double tolerance_m = 1e-6 + 1e-6 * expected.radius_mm / 1000;
      ASSERT_NEAR(circle.radius_m, expected.radius_mm / 1000, tolerance_m) << "extent " << extent << " trial " << trial;
      ASSERT_NEAR(circle.centre_x_m, expected.centre_x_mm / 1000, tolerance_m);
      ASSERT_NEAR(circle.centre_y_m, expected.centre_y_mm / 1000, tolerance_m);
      ExpectExactlyMinimal(members, circle);
    }
  }
}

TEST(ShortestEnclosingCircleTest, HoldsEveryMemberAndIsMinimalOnLargeSets) {
  Rng rng(32);
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<Member> members =
        RandomMembers(rng, 1 + rng.Below(kMaxMembers), trial % 4 == 0 ? 3 : (trial % 4 == 1 ? 100 : 32767));
    ExpectExactlyMinimal(members, Enclose(members));
  }
}

TEST(ShortestEnclosingCircleTest, IsIndependentOfMemberOrderToTheBit) {
  Rng rng(33);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Member> members = RandomMembers(rng, 1 + rng.Below(kMaxMembers), trial % 2 == 0 ? 5 : 32767);
    const Circle expected = Enclose(members);
    for (int shuffle = 0; shuffle < 3; ++shuffle) {
      Shuffle(members, rng);
      const Circle circle = Enclose(members);
      ASSERT_EQ(std::bit_cast<uint32_t>(circle.centre_x_m), std::bit_cast<uint32_t>(expected.centre_x_m));
      ASSERT_EQ(std::bit_cast<uint32_t>(circle.centre_y_m), std::bit_cast<uint32_t>(expected.centre_y_m));
      ASSERT_EQ(std::bit_cast<uint32_t>(circle.radius_m), std::bit_cast<uint32_t>(expected.radius_m));
      ASSERT_EQ(circle.support_count, expected.support_count);
      ASSERT_EQ(circle.support_ids, expected.support_ids);
    }
  }
}

TEST(ShortestEnclosingCircleTest, OneMemberAndCoincidentMembers) {
  EXPECT_EQ(ShortestEnclosingCircle({}, SharedWorkspace()).error(), QueryError::kNoMembers);
  Circle circle = Enclose({{4, {1500, -250}}});
  EXPECT_EQ(circle.centre_x_m, 1.5f);
  EXPECT_EQ(circle.centre_y_m, -0.25f);
  EXPECT_EQ(circle.radius_m, 0.0f);
  EXPECT_EQ(circle.support_count, 1);
  EXPECT_EQ(circle.support_ids, (std::array<uint16_t, 3>{4, kNoRobot, kNoRobot}));
  circle = Enclose({{9, {7, 7}}, {2, {7, 7}}, {5, {7, 7}}});
  EXPECT_EQ(circle.radius_m, 0.0f);
  EXPECT_EQ(circle.support_ids, (std::array<uint16_t, 3>{2, kNoRobot, kNoRobot}));
}

TEST(ShortestEnclosingCircleTest, TwoMembersAndCollinearMembers) {
  Circle circle = Enclose({{1, {0, 0}}, {2, {3000, 4000}}});
  EXPECT_EQ(circle.centre_x_m, 1.5f);
  EXPECT_EQ(circle.centre_y_m, 2.0f);
  EXPECT_EQ(circle.radius_m, 2.5f);
  EXPECT_EQ(circle.support_count, 2);
  // Collinear: the two ends, whatever lies between (coincident ends too).
  circle = Enclose({{5, {-1000, 0}}, {6, {0, 0}}, {7, {250, 0}}, {8, {1000, 0}}, {3, {1000, 0}}, {9, {-1000, 0}}});
  EXPECT_EQ(circle.centre_x_m, 0.0f);
  EXPECT_EQ(circle.radius_m, 1.0f);
  EXPECT_EQ(circle.support_ids, (std::array<uint16_t, 3>{3, 5, kNoRobot}));
}

TEST(ShortestEnclosingCircleTest, ObtuseTriangleUsesItsLongestSide) {
  const Circle circle = Enclose({{0, {-2000, 0}}, {1, {2000, 0}}, {2, {0, 500}}});
  EXPECT_EQ(circle.support_count, 2);
  EXPECT_EQ(circle.radius_m, 2.0f);
  EXPECT_EQ(circle.centre_y_m, 0.0f);
}

TEST(ShortestEnclosingCircleTest, AcuteTriangleUsesAllThree) {
  // All three on the circle of radius 2.5 m about (0, 0); the fourth inside.
  const Circle circle = Enclose({{0, {-1500, -2000}}, {1, {1500, -2000}}, {2, {0, 2500}}, {3, {100, 100}}});
  EXPECT_EQ(circle.support_count, 3);
  EXPECT_EQ(circle.support_ids, (std::array<uint16_t, 3>{0, 1, 2}));
  EXPECT_EQ(circle.centre_x_m, 0.0f);
  EXPECT_EQ(circle.centre_y_m, 0.0f);
  EXPECT_EQ(circle.radius_m, 2.5f);
}

TEST(ShortestEnclosingCircleTest, FullRangeCorners) {
  const Circle circle =
      Enclose({{0, {-32768, -32768}}, {1, {32767, 32767}}, {2, {32767, -32768}}, {3, {-32768, 32767}}, {4, {0, 0}}});
  EXPECT_EQ(circle.centre_x_m, -0.0005f);
  EXPECT_EQ(circle.centre_y_m, -0.0005f);
  EXPECT_EQ(circle.radius_m, static_cast<float>(std::sqrt(2.0) * 65.535 / 2));
  ExpectExactlyMinimal(
      {{0, {-32768, -32768}}, {1, {32767, 32767}}, {2, {32767, -32768}}, {3, {-32768, 32767}}, {4, {0, 0}}}, circle);
  // A huge, nearly flat triangle: the circumcentre is far outside, so the
  // diameter of the longest side wins.
  ExpectExactlyMinimal({{0, {-32768, 0}}, {1, {32767, 1}}, {2, {0, 2}}},
                       Enclose({{0, {-32768, 0}}, {1, {32767, 1}}, {2, {0, 2}}}));
}

TEST(ShortestEnclosingCircleTest, RejectsBadInput) {
  EXPECT_EQ(ShortestEnclosingCircle(std::vector<Member>{{3, {0, 0}}, {3, {1, 1}}}, SharedWorkspace()).error(),
            QueryError::kDuplicateId);
  EXPECT_EQ(ShortestEnclosingCircle(std::vector<Member>{{kNoRobot, {0, 0}}}, SharedWorkspace()).error(),
            QueryError::kIdOutOfRange);
}

}  // namespace
}  // namespace syrof::queries
