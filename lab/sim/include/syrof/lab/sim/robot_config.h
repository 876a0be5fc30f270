// What one simulated robot's software is told at start-up, derived from the
// scenario alone: the lab's side of runtime::RobotConfig.
//
// Pure functions: the same scenario and robot give the same config, with no
// engine state. The simulation (simulation.cpp) calls RobotConfigFor once per
// robot and adds the one thing a scenario cannot say, the shared queries
// workspace.
#pragma once

#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/motion/robot_kind.h"
#include "syrof/motion/controller.h"
#include "syrof/motion/safety_filter.h"
#include "syrof/runtime/robot.h"
#include "syrof/wire/member_set.h"

namespace syrof::lab::sim {

/// Where the robot's estimator starts: the placement is known (the scenario
/// places every robot), but a robot set down by hand sits within a few
/// centimetres and degrees of its mark. 0.05 m and 0.05 rad (about 3
/// degrees) say so, keep the filter's covariance positive definite, and let
/// the first UWB sweeps correct the start rather than be gated out against an
/// over-confident prior.
inline constexpr float kInitialPositionSigmaM = 0.05f;
inline constexpr float kInitialHeadingSigmaRad = 0.05f;

/// A drone's position gain: the motion layer's (motion/robot_kind.h), which
/// the robot image uses too.
using motion::kDronePositionGainPerS;

/// Floors on the noise the estimator assumes, whatever the scenario's
/// simulated sensors do. A scenario may set a sensor's noise to 0 (perfect
/// sensors, for teaching); a filter told "0" would have a singular
/// innovation covariance and gate out every reading off by rounding.
///   - ranges: 0.02 m, the order of what the range model leaves out
///     (float rounding of the anchors' and tag's positions, the tag height);
///   - flow: 0.5 px, the quantisation of a flow sensor that counts whole
///     pixels (a reading is off by up to half a pixel even without noise).
inline constexpr double kRangeSigmaFloorM = 0.02;
inline constexpr double kFlowSigmaFloorPx = 0.5;

/// The radio rounds the maneuver (PROGRESS) lasts: app_round_s /
/// radio_round_s rounded to the nearest whole round. The scenario gives both
/// in decimal seconds, whose ratio is not exact in binary (1.0 / 0.05 is
/// 19.999...): truncating would lose a round. The loader has checked that the
/// ratio is a whole number >= K.
uint16_t ManeuverRounds(const scenario::TimingSpec& timing);

/// The robots present at the start: every robot's initial membership.
wire::MemberSet InitialMembers(const scenario::Scenario& scenario);

/// A motion controller configuration with `spec`'s limits (converted to
/// float) and the default gains and tolerances; the drive kind follows the
/// robot kind (omni and drone: velocity, rover: wheels). A drone's response
/// lag is its tilt time constant, and its position gain
/// kDronePositionGainPerS. motion::ControllerConfigFor, the robot image's.
motion::ControllerConfig ControllerConfigFor(world::RobotKind kind, const world::KindSpec& spec);

/// The kinds present among `scenario`'s robots, each once, in RobotKind's
/// order, with the scenario's limits of each (what motion::SetOthers and
/// runtime::ConfigureKinds take).
std::vector<motion::SwarmKind> SwarmKindsOf(const scenario::Scenario& scenario);

/// Robot `robot`'s simulated sensors: the scenario's, except that a drone's
/// flow sensor and UWB antenna sit at its kind's flight height (a fixed
/// height: the flow sensor's metres per pixel grow with it, docs/estimation.md
/// "Drones"). The estimator of RobotConfigFor is given the same geometry.
sensors::SensorBankConfig SensorConfigFor(const scenario::Scenario& scenario, const scenario::RobotSpec& robot);

/// The safety filter's view of `scenario`'s swarm (docs/safety.md): on or off
/// as the scenario says; the fastest speed limit, largest body and weakest
/// braking among the kinds present (a beacon does not carry its sender's
/// kind); the arena's walls.
motion::SafetyConfig SafetyConfigFor(const scenario::Scenario& scenario);

/// Every robot's activation schedule (docs/activation.md): the scenario's
/// `activation` with its seed. The script is a view into `scenario`, which
/// must outlive the config.
sync::ActivationConfig ActivationConfigFor(const scenario::Scenario& scenario);

/// Robot `robot`'s start-up config in `scenario` (a resolved, validated
/// scenario; `robot` one of its robots): the synchronizer's swarm, K, F and
/// initial members; the radio round and maneuver length; the estimator's
/// arena and noise (with the floors above); the known start pose (with the
/// sigmas above); its kind's motion limits; the arena size; the activation
/// schedule (a view into `scenario`, which must outlive it). The queries
/// workspace is left null: the caller owns one and sets it.
runtime::RobotConfig RobotConfigFor(const scenario::Scenario& scenario, const scenario::RobotSpec& robot);

}  // namespace syrof::lab::sim
