// The C API: the same answers as the C++ API, status codes, NULL arguments,
// workspace placement, outputs untouched on error.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "query_test_support.h"
#include "syrof/queries/queries.h"
#include "syrof/queries/swarm_queries.h"

extern "C" int syrof_queries_c_caller_leader(void);

namespace syrof::queries {
namespace {

using testing::RandomMembers;
using testing::RandomPoints;
using testing::Rng;

std::vector<syrof_queries_member> ToC(const std::vector<Member>& members) {
  std::vector<syrof_queries_member> result;
  for (const Member& member : members) result.push_back({member.id, member.position.x_mm, member.position.y_mm});
  return result;
}

std::vector<syrof_queries_point> ToC(const std::vector<Point>& points) {
  std::vector<syrof_queries_point> result;
  for (const Point& point : points) result.push_back({point.x_mm, point.y_mm});
  return result;
}

// Workspace memory owned by the test, as an app's start-up code would.
class CApiTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    memory_ = new unsigned char[syrof_queries_workspace_size() + syrof_queries_workspace_alignment()];
  }
  static void TearDownTestSuite() { delete[] memory_; }

  void SetUp() override {
    void* aligned = memory_;
    size_t space = syrof_queries_workspace_size() + syrof_queries_workspace_alignment();
    ASSERT_NE(std::align(syrof_queries_workspace_alignment(), syrof_queries_workspace_size(), aligned, space), nullptr);
    ASSERT_EQ(syrof_queries_workspace_init(aligned, space, &workspace_), SYROF_QUERIES_OK);
  }

  static unsigned char* memory_;
  syrof_queries_workspace* workspace_ = nullptr;
};
unsigned char* CApiTest::memory_ = nullptr;

Workspace& CxxWorkspace() {
  static Workspace workspace;
  return workspace;
}

TEST_F(CApiTest, VersionLimitsAndNames) {
  EXPECT_EQ(syrof_queries_abi_version(), SYROF_QUERIES_ABI_VERSION);
  EXPECT_EQ(syrof_queries_max_members(), kMaxMembers);
  EXPECT_EQ(syrof_queries_max_targets(), kMaxTargets);
  EXPECT_STREQ(syrof_queries_status_name(SYROF_QUERIES_DUPLICATE_ID), "DuplicateId");
  EXPECT_STREQ(syrof_queries_status_name(static_cast<syrof_queries_status>(99)), "?");
  EXPECT_GE(syrof_queries_workspace_size(), sizeof(Workspace));
}

TEST_F(CApiTest, CallableFromC) { EXPECT_EQ(syrof_queries_c_caller_leader(), 4); }

TEST_F(CApiTest, WorkspaceInitChecksMemory) {
  syrof_queries_workspace* workspace = nullptr;
  EXPECT_EQ(syrof_queries_workspace_init(nullptr, 1 << 20, &workspace), SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(syrof_queries_workspace_init(memory_, syrof_queries_workspace_size(), nullptr),
            SYROF_QUERIES_NULL_ARGUMENT);
  void* aligned = memory_;
  size_t space = syrof_queries_workspace_size() + syrof_queries_workspace_alignment();
  std::align(syrof_queries_workspace_alignment(), syrof_queries_workspace_size(), aligned, space);
  EXPECT_EQ(syrof_queries_workspace_init(aligned, syrof_queries_workspace_size() - 1, &workspace),
            SYROF_QUERIES_WORKSPACE_TOO_SMALL);
  EXPECT_EQ(syrof_queries_workspace_init(static_cast<unsigned char*>(aligned) + 1, space - 1, &workspace),
            SYROF_QUERIES_WORKSPACE_TOO_SMALL);
  EXPECT_EQ(workspace, nullptr);
}

TEST_F(CApiTest, PointFromMetres) {
  syrof_queries_point point{99, 99};
  EXPECT_EQ(syrof_queries_point_from_metres(1.2345f, -0.0004f, &point), SYROF_QUERIES_OK);
  EXPECT_EQ(point.x_mm, 1235);  // 1234.5 rounds away from zero
  EXPECT_EQ(point.y_mm, 0);
  EXPECT_EQ(syrof_queries_point_from_metres(40.0f, 0.0f, &point), SYROF_QUERIES_COORDINATE_OUT_OF_RANGE);
  EXPECT_EQ(point.x_mm, 1235);
  EXPECT_EQ(syrof_queries_point_from_metres(0.0f, 0.0f, nullptr), SYROF_QUERIES_NULL_ARGUMENT);
}

TEST_F(CApiTest, SameAnswersAsTheCxxApi) {
  Rng rng(51);
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Member> members = RandomMembers(rng, 1 + rng.Below(std::min<uint32_t>(30, kMaxMembers)), 5000);
    const std::vector<Point> targets = RandomPoints(rng, rng.Below(30), 5000);
    const std::vector<syrof_queries_member> c_members = ToC(members);
    const std::vector<syrof_queries_point> c_targets = ToC(targets);

    uint16_t value = 0;
    ASSERT_EQ(syrof_queries_number_of_members(c_members.data(), c_members.size(), &value), SYROF_QUERIES_OK);
    EXPECT_EQ(value, members.size());
    ASSERT_EQ(syrof_queries_leader(c_members.data(), c_members.size(), &value), SYROF_QUERIES_OK);
    EXPECT_EQ(value, Leader(members).value());

    syrof_queries_circle circle{};
    ASSERT_EQ(syrof_queries_shortest_enclosing_circle(workspace_, c_members.data(), c_members.size(), &circle),
              SYROF_QUERIES_OK);
    const Circle expected_circle = ShortestEnclosingCircle(members, CxxWorkspace()).value();
    EXPECT_EQ(circle.centre_x_m, expected_circle.centre_x_m);
    EXPECT_EQ(circle.centre_y_m, expected_circle.centre_y_m);
    EXPECT_EQ(circle.radius_m, expected_circle.radius_m);
    EXPECT_EQ(circle.support_count, expected_circle.support_count);
    for (int index = 0; index < 3; ++index) EXPECT_EQ(circle.support_ids[index], expected_circle.support_ids[index]);

    std::vector<uint16_t> hull(members.size());
    size_t hull_count = 0;
    ASSERT_EQ(syrof_queries_convex_hull(workspace_, c_members.data(), c_members.size(), hull.data(), hull.size(),
                                        &hull_count),
              SYROF_QUERIES_OK);
    std::vector<uint16_t> expected_hull(members.size());
    expected_hull.resize(ConvexHull(members, CxxWorkspace(), expected_hull).value());
    hull.resize(hull_count);
    EXPECT_EQ(hull, expected_hull);

    std::vector<syrof_queries_assignment> by_robot(members.size());
    std::vector<uint16_t> robot_of_target(targets.size());
    syrof_queries_matching_summary summary{};
    ASSERT_EQ(syrof_queries_min_weighted_matching(workspace_, c_members.data(), c_members.size(), c_targets.data(),
                                                  c_targets.size(), by_robot.data(), by_robot.size(),
                                                  robot_of_target.data(), robot_of_target.size(), &summary),
              SYROF_QUERIES_OK);
    std::vector<Assignment> expected_by_robot(members.size());
    std::vector<uint16_t> expected_robot_of_target(targets.size());
    const MatchingSummary expected_summary =
        MinWeightedMatching(members, targets, CxxWorkspace(), expected_by_robot, expected_robot_of_target).value();
    for (size_t index = 0; index < members.size(); ++index) {
      EXPECT_EQ(by_robot[index].robot_id, expected_by_robot[index].robot_id);
      EXPECT_EQ(by_robot[index].target_index, expected_by_robot[index].target_index);
    }
    EXPECT_EQ(robot_of_target, expected_robot_of_target);
    EXPECT_EQ(summary.matched_count, expected_summary.matched_count);
    EXPECT_EQ(summary.bottleneck_squared_mm2, expected_summary.bottleneck_squared_mm2);
    EXPECT_EQ(summary.total_distance_q15_mm, expected_summary.total_distance_q15_mm);
    EXPECT_EQ(summary.bottleneck_m, expected_summary.bottleneck_m);
    EXPECT_EQ(summary.total_m, expected_summary.total_m);
  }
}

TEST_F(CApiTest, NullArgumentsAndErrorsLeaveOutputsUntouched) {
  const syrof_queries_member members[] = {{3, 0, 0}, {3, 10, 10}};
  uint16_t value = 77;
  EXPECT_EQ(syrof_queries_number_of_members(nullptr, 0, &value), SYROF_QUERIES_OK);
  EXPECT_EQ(value, 0);
  value = 77;
  EXPECT_EQ(syrof_queries_number_of_members(nullptr, 2, &value), SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(syrof_queries_number_of_members(members, 2, nullptr), SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(syrof_queries_leader(members, 2, &value), SYROF_QUERIES_DUPLICATE_ID);
  EXPECT_EQ(syrof_queries_leader(nullptr, 0, &value), SYROF_QUERIES_NO_MEMBERS);
  EXPECT_EQ(value, 77);
  EXPECT_EQ(syrof_queries_number_of_members(members, size_t{kMaxMembers} + 1, &value), SYROF_QUERIES_TOO_MANY_MEMBERS);

  syrof_queries_circle circle{};
  circle.radius_m = 5.0f;
  EXPECT_EQ(syrof_queries_shortest_enclosing_circle(nullptr, members, 1, &circle), SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(syrof_queries_shortest_enclosing_circle(workspace_, members, 1, nullptr), SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(syrof_queries_shortest_enclosing_circle(workspace_, members, 2, &circle), SYROF_QUERIES_DUPLICATE_ID);
  EXPECT_EQ(syrof_queries_shortest_enclosing_circle(workspace_, nullptr, 0, &circle), SYROF_QUERIES_NO_MEMBERS);
  EXPECT_EQ(circle.radius_m, 5.0f);

  uint16_t hull[2] = {77, 77};
  size_t hull_count = 77;
  EXPECT_EQ(syrof_queries_convex_hull(workspace_, members, 1, nullptr, 1, &hull_count), SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(syrof_queries_convex_hull(workspace_, members, 1, hull, 1, nullptr), SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(syrof_queries_convex_hull(workspace_, members, 2, hull, 1, &hull_count), SYROF_QUERIES_DUPLICATE_ID);
  EXPECT_EQ(syrof_queries_convex_hull(workspace_, members, 1, hull, 0, &hull_count), SYROF_QUERIES_OUTPUT_TOO_SMALL);
  EXPECT_EQ(hull_count, 77u);
  EXPECT_EQ(hull[0], 77);
  EXPECT_EQ(syrof_queries_convex_hull(workspace_, nullptr, 0, nullptr, 0, &hull_count), SYROF_QUERIES_OK);
  EXPECT_EQ(hull_count, 0u);

  const syrof_queries_point targets[] = {{0, 0}, {5, 5}};
  syrof_queries_assignment by_robot[2] = {{77, 77}, {77, 77}};
  uint16_t robot_of_target[2] = {77, 77};
  EXPECT_EQ(
      syrof_queries_min_weighted_matching(workspace_, members, 1, nullptr, 2, by_robot, 2, robot_of_target, 2, nullptr),
      SYROF_QUERIES_NULL_ARGUMENT);
  EXPECT_EQ(
      syrof_queries_min_weighted_matching(workspace_, members, 1, targets, 2, by_robot, 0, robot_of_target, 2, nullptr),
      SYROF_QUERIES_OUTPUT_TOO_SMALL);
  EXPECT_EQ(
      syrof_queries_min_weighted_matching(workspace_, members, 1, targets, 2, by_robot, 2, robot_of_target, 1, nullptr),
      SYROF_QUERIES_OUTPUT_TOO_SMALL);
  EXPECT_EQ(
      syrof_queries_min_weighted_matching(workspace_, members, 2, targets, 2, by_robot, 2, robot_of_target, 2, nullptr),
      SYROF_QUERIES_DUPLICATE_ID);
  EXPECT_EQ(syrof_queries_min_weighted_matching(workspace_, members, 1, targets, size_t{kMaxTargets} + 1, by_robot, 2,
                                                robot_of_target, 2, nullptr),
            SYROF_QUERIES_TOO_MANY_TARGETS);
  EXPECT_EQ(by_robot[0].robot_id, 77);
  EXPECT_EQ(robot_of_target[0], 77);
  // The summary is optional.
  EXPECT_EQ(
      syrof_queries_min_weighted_matching(workspace_, members, 1, targets, 2, by_robot, 2, robot_of_target, 2, nullptr),
      SYROF_QUERIES_OK);
  EXPECT_EQ(by_robot[0].robot_id, 3);
  EXPECT_EQ(by_robot[0].target_index, 0);
  EXPECT_EQ(robot_of_target[1], SYROF_QUERIES_NO_ROBOT);
}

}  // namespace
}  // namespace syrof::queries
