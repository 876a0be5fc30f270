// circle: n points evenly spaced on a circle (CircleTargets for the map's
// member count), robots assigned by MinWeightedMatching, recomputed in every
// COOPERATIVE epoch so crashes and joins re-space the circle.
#include "target_matching.h"
#include "builtin_apps.h"
#include "formation_app.h"

namespace syrof::lab::apps {
namespace {

class CircleApp final : public FormationApp {
 public:
  explicit CircleApp(const CircleParams& params) : FormationApp(params.margin_m), params_(params) {}
  const char* name() const override { return "circle"; }

 protected:
  bool PlanTargets(const syrof_ldmap& /*ldmap*/, std::span<const syrof_queries_member> members,
                   std::span<Position> targets) override {
    const std::vector<Position> points = CircleTargets(params_, members.size(), arena(), body_radius_m());
    if (!AssignTargets(platform().queries_workspace(), members, points, assignment_)) return false;
    for (size_t i = 0; i < members.size(); ++i) {
      const uint16_t point = assignment_.target_of_member[i];
      if (point != SYROF_QUERIES_NO_TARGET) targets[i] = points[point];
    }
    return true;
  }

 private:
  CircleParams params_;
  TargetAssignment assignment_;
};

}  // namespace

std::unique_ptr<app::App> MakeCircleApp(const CircleParams& params) { return std::make_unique<CircleApp>(params); }

}  // namespace syrof::lab::apps
