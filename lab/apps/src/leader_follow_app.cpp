// leader_follow: the leader (Leader query: the smallest id in the map)
// drives counter-clockwise around a circular path (MakeLeaderPath), at most
// LeaderStepM per epoch; the other members take the slots trailing it along
// the path (FollowerSlots behind the leader's next position), assigned by
// MinWeightedMatching. Everything follows from the map: the leader's
// position gives its angle on the path, so every robot computes the same
// plan without any payload.
#include <cmath>

#include "target_matching.h"
#include "builtin_apps.h"
#include "formation_app.h"

namespace syrof::lab::apps {
namespace {

class LeaderFollowApp final : public FormationApp {
 public:
  explicit LeaderFollowApp(const LeaderFollowParams& params) : FormationApp(params.margin_m), params_(params) {}
  const char* name() const override { return "leader_follow"; }

 protected:
  bool PlanTargets(const syrof_ldmap& /*ldmap*/, std::span<const syrof_queries_member> members,
                   std::span<Position> targets) override {
    uint16_t leader_id = 0;
    if (syrof_queries_leader(members.data(), members.size(), &leader_id) != SYROF_QUERIES_OK) return false;
    const LeaderPath path = MakeLeaderPath(params_, members.size(), arena(), body_radius_m());
    if (path.radius_m <= 0.0) return false;

    size_t leader_index = 0;
    followers_.clear();
    for (size_t i = 0; i < members.size(); ++i) {
      if (members[i].id == leader_id) {
        leader_index = i;
      } else {
        followers_.push_back(members[i]);
      }
    }
    const double step_m = LeaderStepM(params_, body_radius_m(), maneuver_s());
    const double step_rad = 2.0 * std::asin(std::min(1.0, step_m / (2.0 * path.radius_m)));
    const double next_angle_rad = PathAngleRad(path, MemberPosition(members[leader_index])) + step_rad;
    targets[leader_index] = PathPoint(path, next_angle_rad);

    const std::vector<Position> slots = FollowerSlots(path, next_angle_rad, followers_.size());
    if (!AssignTargets(platform().queries_workspace(), followers_, slots, assignment_)) return false;
    size_t follower = 0;
    for (size_t i = 0; i < members.size(); ++i) {
      if (i == leader_index) continue;
      const uint16_t slot = assignment_.target_of_member[follower++];
      if (slot != SYROF_QUERIES_NO_TARGET) targets[i] = slots[slot];
    }
    return true;
  }

 private:
  LeaderFollowParams params_;
  std::vector<syrof_queries_member> followers_;
  TargetAssignment assignment_;
};

}  // namespace

std::unique_ptr<app::App> MakeLeaderFollowApp(const LeaderFollowParams& params) {
  return std::make_unique<LeaderFollowApp>(params);
}

}  // namespace syrof::lab::apps
