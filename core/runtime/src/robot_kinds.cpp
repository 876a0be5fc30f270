#include "syrof/runtime/robot_kinds.h"

namespace syrof::runtime {

void ConfigureKinds(RobotConfig& config, const motion::SwarmKind& self, std::span<const motion::SwarmKind> swarm) {
  config.kind = self.kind;
  config.motion = motion::ControllerConfigFor(self.kind, self.limits);
  motion::SetOthers(config.safety, swarm);
  if (self.kind == motion::RobotKind::kDrone) {
    // The flow sensor flies with the drone: its metres per pixel are the
    // flight height's, and its UWB antenna ranges from there.
    const auto height = static_cast<float>(self.limits.flight_height_m);
    config.estimator.flow_geometry.height_m = height;
    config.estimator.arena.tag_height_m = height;
  }
}

}  // namespace syrof::runtime
