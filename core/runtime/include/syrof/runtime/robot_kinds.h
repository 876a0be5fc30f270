// A robot's kind in its start-up config: what the lab (lab/sim
// robot_config.h) and the robot image (firmware/robot) both call, so a robot
// of a kind runs the same motion layer wherever it runs (motion/robot_kind.h
// for the controller and the safety filter's view of the swarm).
#pragma once

#include <span>

#include "syrof/motion/robot_kind.h"
#include "syrof/runtime/robot.h"

namespace syrof::runtime {

/// Sets what `config` needs of robot kinds for a robot of kind `self` in a
/// swarm of the kinds `swarm` (each present kind once, `self`'s among them):
///   - kind: self's (what the app reads as syrof_app_info::kind);
///   - motion: motion::ControllerConfigFor(self);
///   - safety: the others' speed, radius, braking and lag
///     (motion::SetOthers(swarm)); own_sigmas (motion::kOwnSigmas for every
///     kind), enabled and the walls are left as they are;
///   - estimator: a drone's flow sensor and UWB antenna at its flight height
///     (flow_geometry.height_m, arena.tag_height_m; docs/estimation.md
///     "Drones"); the other kinds keep theirs.
void ConfigureKinds(RobotConfig& config, const motion::SwarmKind& self, std::span<const motion::SwarmKind> swarm);

}  // namespace syrof::runtime
