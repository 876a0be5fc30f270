// Whether a scenario's robots run on the default kinds' limits: the ones a
// robot image has compiled in (motion::DefaultKindLimits; firmware/robot
// takes them from there and cannot be told others). The lab runs any
// limits a scenario gives; the firmware's host tools, the emulated swarm's
// (syrof-firmware-swarm) and the flash-time one (syrof-firmware-config),
// refuse a scenario with other limits through this one check, so both say
// the same words (docs/firmware.md, "Robot kinds" and "The configuration
// block").
#pragma once

#include <optional>

#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::scenario {

/// The first limit of a kind that `scenario` has robots of which differs
/// from motion::DefaultKindLimits of that kind, by field in KindLimits'
/// order, kinds in RobotKind's order; nothing when every present kind's
/// limits are the defaults. A kind no robot has may be changed (the image
/// never drives it), and so may a drone's drift_sigma_mps (the world's
/// alone, not the robot's). The error's `where` is the scenario's source
/// (its name when read from a string), with no line (the Scenario keeps no
/// places), and its message names the field, the value found and the
/// image's: "kinds.drone.max_speed_mps is 1; the robot image has 0.8
/// compiled in (the default kinds, docs/scenarios.md) and would drive its
/// robots with other limits".
std::optional<ScenarioError> CheckDefaultKindLimits(const Scenario& scenario);

}  // namespace syrof::lab::scenario
