// The C API: plain structs in, the C++ queries, plain structs out.
#include <array>
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>

#include "syrof/queries/queries.h"
#include "syrof/queries/swarm_queries.h"

using syrof::queries::Assignment;
using syrof::queries::Circle;
using syrof::queries::kMaxMembers;
using syrof::queries::kMaxTargets;
using syrof::queries::MatchingSummary;
using syrof::queries::Member;
using syrof::queries::Point;
using syrof::queries::QueryError;
using syrof::queries::Workspace;

struct syrof_queries_workspace {
  Workspace workspace;
};

namespace {

#define SYROF_SAME_STATUS(c_name, cpp_name) \
  static_assert(static_cast<int>(c_name) == static_cast<int>(QueryError::cpp_name), #c_name)
SYROF_SAME_STATUS(SYROF_QUERIES_OK, kOk);
SYROF_SAME_STATUS(SYROF_QUERIES_NO_MEMBERS, kNoMembers);
SYROF_SAME_STATUS(SYROF_QUERIES_TOO_MANY_MEMBERS, kTooManyMembers);
SYROF_SAME_STATUS(SYROF_QUERIES_TOO_MANY_TARGETS, kTooManyTargets);
SYROF_SAME_STATUS(SYROF_QUERIES_ID_OUT_OF_RANGE, kIdOutOfRange);
SYROF_SAME_STATUS(SYROF_QUERIES_DUPLICATE_ID, kDuplicateId);
SYROF_SAME_STATUS(SYROF_QUERIES_NON_FINITE_COORDINATE, kNonFiniteCoordinate);
SYROF_SAME_STATUS(SYROF_QUERIES_COORDINATE_OUT_OF_RANGE, kCoordinateOutOfRange);
SYROF_SAME_STATUS(SYROF_QUERIES_OUTPUT_TOO_SMALL, kOutputTooSmall);
SYROF_SAME_STATUS(SYROF_QUERIES_NULL_ARGUMENT, kNullArgument);
SYROF_SAME_STATUS(SYROF_QUERIES_WORKSPACE_TOO_SMALL, kWorkspaceTooSmall);
#undef SYROF_SAME_STATUS
static_assert(SYROF_QUERIES_NO_ROBOT == syrof::queries::kNoRobot);
static_assert(SYROF_QUERIES_NO_TARGET == syrof::queries::kNoTarget);

syrof_queries_status ToStatus(QueryError error) { return static_cast<syrof_queries_status>(error); }

// The C members as C++ members, in a caller-provided array of kMaxMembers.
// count <= kMaxMembers.
std::span<const Member> ToMembers(const syrof_queries_member* members, size_t count,
                                  std::array<Member, kMaxMembers>& storage) {
  for (size_t index = 0; index < count; ++index) {
    storage[index] = Member{members[index].id, Point{members[index].x_mm, members[index].y_mm}};
  }
  return std::span<const Member>(storage.data(), count);
}

// The checks every query makes on its member list before converting it.
syrof_queries_status CheckMembers(const syrof_queries_member* members, size_t count) {
  if (members == nullptr && count != 0) return SYROF_QUERIES_NULL_ARGUMENT;
  if (count > kMaxMembers) return SYROF_QUERIES_TOO_MANY_MEMBERS;
  return SYROF_QUERIES_OK;
}

}  // namespace

extern "C" {

uint32_t syrof_queries_abi_version(void) { return SYROF_QUERIES_ABI_VERSION; }

const char* syrof_queries_status_name(syrof_queries_status status) {
  return syrof::queries::ToString(static_cast<QueryError>(status));
}

uint16_t syrof_queries_max_members(void) { return kMaxMembers; }
uint16_t syrof_queries_max_targets(void) { return kMaxTargets; }

size_t syrof_queries_workspace_size(void) { return sizeof(syrof_queries_workspace); }
size_t syrof_queries_workspace_alignment(void) { return alignof(syrof_queries_workspace); }

syrof_queries_status syrof_queries_workspace_init(void* memory, size_t size, syrof_queries_workspace** workspace) {
  if (memory == nullptr || workspace == nullptr) return SYROF_QUERIES_NULL_ARGUMENT;
  if (size < sizeof(syrof_queries_workspace) ||
      reinterpret_cast<uintptr_t>(memory) % alignof(syrof_queries_workspace) != 0) {
    return SYROF_QUERIES_WORKSPACE_TOO_SMALL;
  }
  *workspace = new (memory) syrof_queries_workspace;
  return SYROF_QUERIES_OK;
}

syrof_queries_status syrof_queries_point_from_metres(float x_m, float y_m, syrof_queries_point* point) {
  if (point == nullptr) return SYROF_QUERIES_NULL_ARGUMENT;
  const auto result = syrof::queries::PointFromMetres(x_m, y_m);
  if (!result.ok()) return ToStatus(result.error());
  *point = syrof_queries_point{result.value().x_mm, result.value().y_mm};
  return SYROF_QUERIES_OK;
}

syrof_queries_status syrof_queries_number_of_members(const syrof_queries_member* members, size_t count,
                                                     uint16_t* number_of_members) {
  if (number_of_members == nullptr) return SYROF_QUERIES_NULL_ARGUMENT;
  if (const syrof_queries_status status = CheckMembers(members, count); status != SYROF_QUERIES_OK) {
    return status;
  }
  std::array<Member, kMaxMembers> staged;
  const auto result = syrof::queries::NumberOfMembers(ToMembers(members, count, staged));
  if (!result.ok()) return ToStatus(result.error());
  *number_of_members = result.value();
  return SYROF_QUERIES_OK;
}

syrof_queries_status syrof_queries_leader(const syrof_queries_member* members, size_t count, uint16_t* leader_id) {
  if (leader_id == nullptr) return SYROF_QUERIES_NULL_ARGUMENT;
  if (const syrof_queries_status status = CheckMembers(members, count); status != SYROF_QUERIES_OK) {
    return status;
  }
  std::array<Member, kMaxMembers> staged;
  const auto result = syrof::queries::Leader(ToMembers(members, count, staged));
  if (!result.ok()) return ToStatus(result.error());
  *leader_id = result.value();
  return SYROF_QUERIES_OK;
}

syrof_queries_status syrof_queries_shortest_enclosing_circle(syrof_queries_workspace* workspace,
                                                             const syrof_queries_member* members, size_t count,
                                                             syrof_queries_circle* circle) {
  if (workspace == nullptr || circle == nullptr) return SYROF_QUERIES_NULL_ARGUMENT;
  if (const syrof_queries_status status = CheckMembers(members, count); status != SYROF_QUERIES_OK) {
    return status;
  }
  std::array<Member, kMaxMembers> staged;
  const auto result = syrof::queries::ShortestEnclosingCircle(ToMembers(members, count, staged), workspace->workspace);
  if (!result.ok()) return ToStatus(result.error());
  const Circle& answer = result.value();
  *circle = syrof_queries_circle{answer.centre_x_m,
                                 answer.centre_y_m,
                                 answer.radius_m,
                                 {answer.support_ids[0], answer.support_ids[1], answer.support_ids[2]},
                                 answer.support_count};
  return SYROF_QUERIES_OK;
}

syrof_queries_status syrof_queries_convex_hull(syrof_queries_workspace* workspace, const syrof_queries_member* members,
                                               size_t count, uint16_t* hull_ids, size_t capacity, size_t* hull_count) {
  if (workspace == nullptr || hull_count == nullptr || (hull_ids == nullptr && capacity != 0)) {
    return SYROF_QUERIES_NULL_ARGUMENT;
  }
  if (const syrof_queries_status status = CheckMembers(members, count); status != SYROF_QUERIES_OK) {
    return status;
  }
  std::array<Member, kMaxMembers> staged;
  const auto result = syrof::queries::ConvexHull(ToMembers(members, count, staged), workspace->workspace,
                                                 std::span<uint16_t>(hull_ids, capacity));
  if (!result.ok()) return ToStatus(result.error());
  *hull_count = result.value();
  return SYROF_QUERIES_OK;
}

syrof_queries_status syrof_queries_min_weighted_matching(syrof_queries_workspace* workspace,
                                                         const syrof_queries_member* members, size_t count,
                                                         const syrof_queries_point* targets, size_t target_count,
                                                         syrof_queries_assignment* by_robot, size_t by_robot_capacity,
                                                         uint16_t* robot_of_target, size_t robot_of_target_capacity,
                                                         syrof_queries_matching_summary* summary) {
  if (workspace == nullptr || (targets == nullptr && target_count != 0) ||
      (by_robot == nullptr && by_robot_capacity != 0) ||
      (robot_of_target == nullptr && robot_of_target_capacity != 0)) {
    return SYROF_QUERIES_NULL_ARGUMENT;
  }
  if (target_count > kMaxTargets) return SYROF_QUERIES_TOO_MANY_TARGETS;
  if (const syrof_queries_status status = CheckMembers(members, count); status != SYROF_QUERIES_OK) {
    return status;
  }
  std::array<Member, kMaxMembers> staged_members;
  std::array<Point, kMaxTargets> staged_targets;
  std::array<Assignment, kMaxMembers> staged_assignments;
  for (size_t index = 0; index < target_count; ++index) {
    staged_targets[index] = Point{targets[index].x_mm, targets[index].y_mm};
  }
  // Output sizes are checked here, before the query writes anything: on an
  // error the caller's buffers stay untouched.
  const auto result = syrof::queries::MinWeightedMatching(
      ToMembers(members, count, staged_members), std::span<const Point>(staged_targets.data(), target_count),
      workspace->workspace,
      std::span<Assignment>(staged_assignments.data(), by_robot_capacity < count ? by_robot_capacity : count),
      std::span<uint16_t>(robot_of_target, robot_of_target_capacity));
  if (!result.ok()) return ToStatus(result.error());
  for (size_t index = 0; index < count; ++index) {
    by_robot[index] =
        syrof_queries_assignment{staged_assignments[index].robot_id, staged_assignments[index].target_index};
  }
  if (summary != nullptr) {
    const MatchingSummary& figures = result.value();
    *summary = syrof_queries_matching_summary{figures.bottleneck_squared_mm2, figures.total_distance_q15_mm,
                                              figures.bottleneck_m, figures.total_m, figures.matched_count};
  }
  return SYROF_QUERIES_OK;
}

}  // extern "C"
