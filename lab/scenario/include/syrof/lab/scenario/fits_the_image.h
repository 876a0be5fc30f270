// Whether a scenario fits what a robot image has compiled in and cannot be
// told: the radio round (registry::kDefaultRadioRoundNs), the
// synchronizer's timing (runtime::RobotConfig's maneuver_rounds,
// sync::SyncConfig::ForSwarm's K and F), the default
// arena's anchors its estimator ranges against (estimation::DefaultArena)
// the default kinds' limits (motion::DefaultKindLimits; firmware/robot
// takes them from there), the estimator's sensor noise and the safety
// filter (always on). The lab runs any of these a scenario gives; the
// firmware's host tools, the emulated swarm's (syrof-firmware-swarm) and
// the flash-time one (syrof-firmware-config), refuse a scenario that
// changes one through this one check, so both say the same words
// (docs/firmware.md, "The emulated swarm", "Robot kinds" and "The
// configuration block").
#pragma once

#include <optional>

#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::scenario {

/// The first way `scenario` does not fit the robot image, in this order;
/// nothing when it fits.
///  0. More robots than the robots' radio carries a beacon for
///     (wire::LargestRadioSwarm, 16): "17 robots; their beacon would be 32
///     bytes, more than the robots' radio carries (31, one BLE
///     advertisement): the robot image runs swarms of at most 16 robots
///     (docs/beacon.md)".
///  1. Its radio round is not the image's 50 ms: "timing.radio_round_s must
///     be 0.05 (the robot image's radio round)".
///  2. Its synchronizer's timing is not the image's (app_round_s 1 s, i.e.
///     runtime::RobotConfig's 20 rounds of PROGRESS; vote_rounds K = 3;
///     silence_rounds F = 6), by field in that order: "timing.
///     silence_rounds is 8; the robot image has 6 compiled in (its
///     synchronizer's timing, docs/scenarios.md) and would run its epochs
///     on other timing".
///  3. Its arena is not the default one (the image's estimates would be
///     off: 1.3 m RMSE on a 5 m arena), naming the first difference of the
///     size, arena.tag_height_m, the anchor count and an anchor: "the arena
///     is 5 m x 5 m; the robot image has the default arena compiled in (4 m
///     x 4 m, tag_height_m 0.10, the four default anchors;
///     docs/scenarios.md) and its estimates would be off".
///  4. A limit of a kind it has robots of differs from the default, by
///     field in KindLimits' order, kinds in RobotKind's order: "kinds.drone.
///     max_speed_mps is 1; the robot image has 0.8 compiled in (the default
///     kinds, docs/scenarios.md) and would drive its robots with other
///     limits". A kind no robot has may be changed (the image never drives
///     it), and so may a drone's drift_sigma_mps (the world's alone, not
///     the robot's).
///  5. Its sensors' noise that the robot's estimator weighs readings with
///     is not the image's (estimation::EstimatorConfig's defaults, which
///     the default sensors match), UWB then flow: "sensors.uwb.sigma_m is
///     0.2; the robot image's estimator has 0.1 compiled in (the default
///     sensors, docs/scenarios.md) and would weigh its readings otherwise
///     than the lab's robots".
///  6. `safety: off`: "safety is off; the robot image runs its safety
///     filter always (docs/safety.md) and would drive otherwise than the
///     lab's robots".
/// The error's `where` is the scenario's source (its name when read from a
/// string), with no line (the Scenario keeps no places).
std::optional<ScenarioError> CheckScenarioFitsTheImage(const Scenario& scenario);

}  // namespace syrof::lab::scenario
