#include "target_matching.h"

#include <new>

#include "syrof/base/check.h"

namespace syrof::lab::apps {

OwnedWorkspace::OwnedWorkspace() {
  const size_t alignment = syrof_queries_workspace_alignment();
  const size_t size = syrof_queries_workspace_size();
  memory_.reset(static_cast<unsigned char*>(::operator new(size, std::align_val_t{alignment})));
  SYROF_CHECK(syrof_queries_workspace_init(memory_.get(), size, &workspace_) == SYROF_QUERIES_OK);
}

void OwnedWorkspace::Free::operator()(unsigned char* memory) const {
  ::operator delete(memory, std::align_val_t{syrof_queries_workspace_alignment()});
}

bool AssignTargets(syrof_queries_workspace* workspace, std::span<const syrof_queries_member> members,
                   std::span<const Position> targets, TargetAssignment& out) {
  std::vector<syrof_queries_point> points(targets.size());
  for (size_t k = 0; k < targets.size(); ++k) {
    if (syrof_queries_point_from_metres(static_cast<float>(targets[k].x_m), static_cast<float>(targets[k].y_m),
                                        &points[k]) != SYROF_QUERIES_OK) {
      return false;
    }
  }
  std::vector<syrof_queries_assignment> by_robot(members.size());
  std::vector<uint16_t> robot_of_target(targets.size());
  syrof_queries_matching_summary summary{};
  if (syrof_queries_min_weighted_matching(workspace, members.data(), members.size(), points.data(), points.size(),
                                          by_robot.data(), by_robot.size(), robot_of_target.data(),
                                          robot_of_target.size(), &summary) != SYROF_QUERIES_OK) {
    return false;
  }
  out.target_of_member.resize(members.size());
  for (size_t i = 0; i < members.size(); ++i) out.target_of_member[i] = by_robot[i].target_index;
  out.bottleneck_m = summary.bottleneck_m;
  return true;
}

Position MemberPosition(const syrof_queries_member& member) {
  return {static_cast<double>(member.x_mm) / 1000.0, static_cast<double>(member.y_mm) / 1000.0};
}

}  // namespace syrof::lab::apps
