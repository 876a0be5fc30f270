// Robot-to-target assignment through the queries' C API (the API an app
// reaches through its Platform), shared by the apps and the goal checks.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "syrof/lab/apps/formation.h"
#include "syrof/queries/queries.h"

namespace syrof::lab::apps {

/// A queries workspace of its own, for code that has no Platform (the goal
/// checks). About 4 MB on the host.
class OwnedWorkspace {
 public:
  OwnedWorkspace();
  syrof_queries_workspace* get() const { return workspace_; }

 private:
  struct Free {
    void operator()(unsigned char* memory) const;
  };
  std::unique_ptr<unsigned char, Free> memory_;
  syrof_queries_workspace* workspace_ = nullptr;
};

/// What AssignTargets found.
struct TargetAssignment {
  /// Per member, in the members' order: the index of its target, or
  /// SYROF_QUERIES_NO_TARGET.
  std::vector<uint16_t> target_of_member;
  double bottleneck_m = 0;  ///< the longest robot-to-target distance
};

/// MinWeightedMatching of `members` (increasing id) to `targets` (metres,
/// quantized to millimetres like a beacon). False when a query refuses the
/// input (a target outside the int16 millimetre range, too many members).
bool AssignTargets(syrof_queries_workspace* workspace, std::span<const syrof_queries_member> members,
                   std::span<const Position> targets, TargetAssignment& out);

/// A member's position in metres.
Position MemberPosition(const syrof_queries_member& member);

}  // namespace syrof::lab::apps
