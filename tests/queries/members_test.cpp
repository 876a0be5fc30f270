// NumberOfMembers, Leader, input validation and the metre conversions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "query_test_support.h"
#include "syrof/queries/swarm_queries.h"
#include "syrof/wire/fixed_point.h"
#include "syrof/wire/member_set.h"

namespace syrof::queries {
namespace {

using testing::RandomMembers;
using testing::Rng;
using testing::Shuffle;

static_assert(kMaxMembers == wire::kMaxSwarmSize, "queries accept exactly the swarm sizes beacons carry");

TEST(NumberOfMembersTest, CountsMembers) {
  EXPECT_EQ(NumberOfMembers({}).value(), 0);
  const std::vector<Member> members = {{3, {0, 0}}, {0, {5, 5}}, {1, {-5, 2}}};
  EXPECT_EQ(NumberOfMembers(members).value(), 3);
}

TEST(NumberOfMembersTest, FullSwarmIsAccepted) {
  std::vector<Member> members;
  for (uint16_t id = 0; id < kMaxMembers; ++id) members.push_back({id, {0, 0}});
  EXPECT_EQ(NumberOfMembers(members).value(), kMaxMembers);
}

TEST(ValidationTest, RejectsDuplicateIdsOutOfRangeIdsAndTooManyMembers) {
  EXPECT_EQ(NumberOfMembers(std::vector<Member>{{1, {0, 0}}, {1, {9, 9}}}).error(), QueryError::kDuplicateId);
  // Same id at the same position is still a duplicate.
  EXPECT_EQ(Leader(std::vector<Member>{{4, {2, 2}}, {4, {2, 2}}}).error(), QueryError::kDuplicateId);
  EXPECT_EQ(NumberOfMembers(std::vector<Member>{{kMaxMembers, {0, 0}}}).error(), QueryError::kIdOutOfRange);
  EXPECT_EQ(Leader(std::vector<Member>{{0, {0, 0}}, {kNoRobot, {0, 0}}}).error(), QueryError::kIdOutOfRange);
  std::vector<Member> too_many;
  for (uint32_t index = 0; index <= kMaxMembers; ++index) too_many.push_back({0, {0, 0}});
  EXPECT_EQ(NumberOfMembers(too_many).error(), QueryError::kTooManyMembers);
}

TEST(ValidationTest, ErrorDoesNotDependOnOrder) {
  // A list with both a duplicate and an out-of-range id reports the
  // out-of-range id whichever comes first.
  std::vector<Member> members = {{2, {0, 0}}, {2, {1, 1}}, {kMaxMembers, {0, 0}}, {5, {3, 3}}};
  Rng rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    Shuffle(members, rng);
    EXPECT_EQ(NumberOfMembers(members).error(), QueryError::kIdOutOfRange);
  }
}

TEST(ValidationTest, SamePositionForTwoIdsIsFine) {
  EXPECT_EQ(NumberOfMembers(std::vector<Member>{{1, {7, 7}}, {2, {7, 7}}}).value(), 2);
}

TEST(LeaderTest, IsTheSmallestId) {
  EXPECT_EQ(Leader({}).error(), QueryError::kNoMembers);
  EXPECT_EQ(Leader(std::vector<Member>{{9, {1, 1}}}).value(), 9);
  EXPECT_EQ(Leader(std::vector<Member>{{9, {1, 1}}, {0, {-1, -1}}, {4, {0, 0}}}).value(), 0);
  Rng rng(12);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Member> members = RandomMembers(rng, 1 + rng.Below(kMaxMembers), 1000);
    uint16_t smallest = kNoRobot;
    for (const Member& member : members) smallest = std::min(smallest, member.id);
    EXPECT_EQ(Leader(members).value(), smallest);
    Shuffle(members, rng);
    EXPECT_EQ(Leader(members).value(), smallest);
  }
}

// Random input, valid or not (ids anywhere in uint16, repeats, sizes around
// the limit): every query gives an answer or one of its errors, never a crash.
TEST(ValidationTest, AnyInputGivesAnAnswerOrAnError) {
  static Workspace workspace;
  Rng rng(14);
  for (int trial = 0; trial < 300; ++trial) {
    const size_t count = rng.Below(uint32_t{kMaxMembers} + 3);
    const uint32_t id_range = trial % 3 == 0 ? 65536 : (trial % 3 == 1 ? kMaxMembers : count + 1);
    std::vector<Member> members(count);
    for (Member& member : members) {
      member = {static_cast<uint16_t>(rng.Below(id_range)),
                {static_cast<int16_t>(rng.Between(-32768, 32767)), static_cast<int16_t>(rng.Between(-32768, 32767))}};
    }
    std::vector<Point> targets(rng.Below(uint32_t{kMaxTargets} + 3));
    for (Point& target : targets) target = {static_cast<int16_t>(rng.Between(-5, 5)), static_cast<int16_t>(rng.Next())};
    const QueryError validity = NumberOfMembers(members).error();
    EXPECT_EQ(Leader(members).error(),
              members.empty() && validity == QueryError::kOk ? QueryError::kNoMembers : validity);
    std::vector<uint16_t> hull(members.size());
    EXPECT_EQ(ConvexHull(members, workspace, hull).error(), validity);
    const QueryError circle = ShortestEnclosingCircle(members, workspace).error();
    EXPECT_EQ(circle, members.empty() && validity == QueryError::kOk ? QueryError::kNoMembers : validity);
    std::vector<Assignment> by_robot(members.size());
    std::vector<uint16_t> robot_of_target(targets.size());
    const QueryError matching = MinWeightedMatching(members, targets, workspace, by_robot, robot_of_target).error();
    EXPECT_EQ(matching, targets.size() > kMaxTargets ? QueryError::kTooManyTargets : validity);
  }
}

TEST(PointFromMetresTest, RoundsLikeTheBeaconEncoderInRange) {
  // Every millimetre value survives metres and back, as a map built from
  // beacons needs.
  for (int32_t mm = -32768; mm <= 32767; ++mm) {
    const float metres = wire::ToMetres(static_cast<int16_t>(mm));
    const auto point = PointFromMetres(metres, metres);
    ASSERT_TRUE(point.ok()) << mm;
    ASSERT_EQ(point.value().x_mm, mm);
    ASSERT_EQ(point.value().y_mm, wire::ToMillimetres(metres));
  }
  Rng rng(13);
  for (int trial = 0; trial < 100000; ++trial) {
    const float metres = static_cast<float>(rng.Between(-32'767'000, 32'767'000)) / 1'000'000.0f;
    ASSERT_EQ(PointFromMetres(metres, 0.0f).value().x_mm, wire::ToMillimetres(metres)) << metres;
  }
  // Ties round away from zero.
  EXPECT_EQ(PointFromMetres(0.0005f, -0.0025f).value(), (Point{1, -3}));
  EXPECT_EQ(PointFromMetres(-0.0f, 0.0f).value(), (Point{0, 0}));
  EXPECT_EQ(PointFromMetres(32.767f, -32.768f).value(), (Point{32767, -32768}));
}

TEST(PointFromMetresTest, RejectsNonFiniteAndOutOfRange) {
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(PointFromMetres(nan, 0.0f).error(), QueryError::kNonFiniteCoordinate);
  EXPECT_EQ(PointFromMetres(0.0f, -kInfinity).error(), QueryError::kNonFiniteCoordinate);
  EXPECT_EQ(PointFromMetres(40.0f, nan).error(), QueryError::kNonFiniteCoordinate);  // non-finite outranks range
  EXPECT_EQ(PointFromMetres(32.7675f, 0.0f).error(), QueryError::kCoordinateOutOfRange);
  EXPECT_EQ(PointFromMetres(0.0f, -32.7685f).error(), QueryError::kCoordinateOutOfRange);
  EXPECT_EQ(PointFromMetres(3.0e38f, 0.0f).error(), QueryError::kCoordinateOutOfRange);
  EXPECT_EQ(PointFromMetres(-1.0e9f, 0.0f).error(), QueryError::kCoordinateOutOfRange);
}

TEST(ToMetresTest, IsTheNearestFloat) {
  EXPECT_EQ(ToMetres(1000), 1.0f);
  EXPECT_EQ(ToMetres(-32768), -32.768f);
  EXPECT_EQ(ToMetres(1), 0.001f);
}

TEST(QueryErrorTest, EveryErrorHasAName) {
  EXPECT_STREQ(ToString(QueryError::kOk), "Ok");
  EXPECT_STREQ(ToString(QueryError::kDuplicateId), "DuplicateId");
  EXPECT_STREQ(ToString(QueryError::kWorkspaceTooSmall), "WorkspaceTooSmall");
  EXPECT_STREQ(ToString(static_cast<QueryError>(200)), "?");
  for (uint8_t value = 0; value <= static_cast<uint8_t>(QueryError::kWorkspaceTooSmall); ++value) {
    EXPECT_STRNE(ToString(static_cast<QueryError>(value)), "?") << int{value};
  }
}

}  // namespace
}  // namespace syrof::queries
