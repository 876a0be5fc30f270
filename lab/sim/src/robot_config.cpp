#include "syrof/lab/sim/robot_config.h"

#include <algorithm>
#include <cmath>

#include "syrof/lab/world/world.h"
#include "syrof/runtime/robot_kinds.h"
#include "units.h"

namespace syrof::lab::sim {
namespace {

// The estimator's arena: the one the simulated sensors measure against.
estimation::Arena<float> EstimatorArena(const sensors::SensorBankConfig& bank) {
  const estimation::Arena<double>& source = bank.arena;
  estimation::Arena<float> arena{};
  arena.width_m = static_cast<float>(source.width_m);
  arena.depth_m = static_cast<float>(source.depth_m);
  arena.tag_height_m = static_cast<float>(source.tag_height_m);
  arena.anchor_count = source.anchor_count;
  for (int i = 0; i < source.anchor_count; ++i) arena.anchors[i] = source.anchors[i].cast<float>();
  return arena;
}

}  // namespace

uint16_t ManeuverRounds(const scenario::TimingSpec& timing) {
  return static_cast<uint16_t>(std::llround(timing.app_round_s / timing.radio_round_s));
}

wire::MemberSet InitialMembers(const scenario::Scenario& scenario) {
  wire::MemberSet initial;
  for (const scenario::RobotSpec& spec : scenario.robots) {
    if (spec.present_at_start) initial.set(spec.id);
  }
  return initial;
}

motion::ControllerConfig ControllerConfigFor(world::RobotKind kind, const world::KindSpec& spec) {
  return motion::ControllerConfigFor(kind, world::LimitsOf(spec));
}

std::vector<motion::SwarmKind> SwarmKindsOf(const scenario::Scenario& scenario) {
  std::vector<motion::SwarmKind> kinds;
  for (const world::RobotKind kind : {world::RobotKind::kOmni, world::RobotKind::kRover, world::RobotKind::kDrone}) {
    const bool present = std::any_of(scenario.robots.begin(), scenario.robots.end(),
                                     [kind](const scenario::RobotSpec& robot) { return robot.kind == kind; });
    if (present) kinds.push_back(motion::SwarmKind{kind, world::LimitsOf(scenario.kind_spec(kind))});
  }
  return kinds;
}

sensors::SensorBankConfig SensorConfigFor(const scenario::Scenario& scenario, const scenario::RobotSpec& robot) {
  sensors::SensorBankConfig bank = scenario.sensors;
  if (robot.kind == world::RobotKind::kDrone) {
    bank.flow.geometry.height_m = scenario.drone.flight_height_m;
    bank.arena.tag_height_m = scenario.drone.flight_height_m;
  }
  return bank;
}

runtime::RobotConfig RobotConfigFor(const scenario::Scenario& scenario, const scenario::RobotSpec& robot) {
  const sensors::SensorBankConfig bank = SensorConfigFor(scenario, robot);
  runtime::RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(static_cast<uint16_t>(scenario.robots.size()), robot.id);
  config.sync.vote_rounds = static_cast<uint8_t>(scenario.timing.vote_rounds);
  config.sync.silence_rounds = static_cast<uint16_t>(scenario.timing.silence_rounds);
  config.sync.initial_members = InitialMembers(scenario);
  config.radio_round_ns = Nanoseconds(scenario.timing.radio_round_s);
  config.maneuver_rounds = ManeuverRounds(scenario.timing);
  config.estimator.arena = EstimatorArena(bank);
  if (robot.kind == world::RobotKind::kDrone) {
    // The flow sensor flies with the drone: its metres per pixel are the
    // flight height's. (Omni and rover keep the estimator's default
    // geometry, the one the scenario's sensors default to.)
    config.estimator.flow_geometry.viewing_angle_rad = static_cast<float>(bank.flow.geometry.viewing_angle_rad);
    config.estimator.flow_geometry.pixels = static_cast<float>(bank.flow.geometry.pixels);
    config.estimator.flow_geometry.height_m = static_cast<float>(bank.flow.geometry.height_m);
    config.estimator.flow_geometry.mounting_angle_rad = static_cast<float>(bank.flow.geometry.mounting_angle_rad);
  }
  config.estimator.range_sigma_m = static_cast<float>(std::max(kRangeSigmaFloorM, scenario.sensors.uwb.sigma_m));
  config.estimator.flow_sigma_px = static_cast<float>(std::max(kFlowSigmaFloorPx, scenario.sensors.flow.sigma_px));
  config.initial_pose.x_m = static_cast<float>(robot.x_m);
  config.initial_pose.y_m = static_cast<float>(robot.y_m);
  config.initial_pose.heading_rad = static_cast<float>(robot.heading_rad);
  config.initial_pose.position_sigma_m = kInitialPositionSigmaM;
  config.initial_pose.heading_sigma_rad = kInitialHeadingSigmaRad;
  config.arena_width_m = static_cast<float>(scenario.arena.width_m);
  config.arena_height_m = static_cast<float>(scenario.arena.height_m);
  config.safety = SafetyConfigFor(scenario);
  // The kind's controller, the safety filter's view of the swarm's kinds and
  // a drone's estimator at its flight height, as the robot image sets them.
  runtime::ConfigureKinds(config, motion::SwarmKind{robot.kind, world::LimitsOf(scenario.kind_spec(robot.kind))},
                          SwarmKindsOf(scenario));
  config.announce_presence = scenario.safety;
  config.activation = ActivationConfigFor(scenario);
  // With a clocks section the robots align their rounds unless it says
  // alignment: off; without one every robot shares the lab's clock.
  config.align_rounds = scenario.clocks.enabled && scenario.clocks.alignment;
  // The lab's radio sends in the middle of the round (radio_network.h).
  if (scenario.clocks.enabled) config.beacon_delay_ns = std::llround(scenario.timing.radio_round_s * 1e9) / 2;
  return config;
}

sync::ActivationConfig ActivationConfigFor(const scenario::Scenario& scenario) {
  sync::ActivationConfig activation;
  activation.model = scenario.activation.model;
  activation.schedule = scenario.activation.schedule;
  activation.seed = scenario.seed;
  activation.fair_within = scenario.activation.fair_within;
  activation.script = scenario.activation.script;
  activation.max_delay_epochs = scenario.activation.max_delay_epochs;
  activation.min_move_mm = static_cast<uint32_t>(std::lround(scenario.activation.min_move_m * 1000.0));
  activation.cycles = scenario.activation.cycles;
  return activation;
}

motion::SafetyConfig SafetyConfigFor(const scenario::Scenario& scenario) {
  motion::SafetyConfig safety;
  safety.enabled = scenario.safety;
  // A beacon does not say its sender's kind: assume the fastest, largest and
  // slowest-braking kind present.
  motion::SetOthers(safety, SwarmKindsOf(scenario));
  safety.arena_width_m = static_cast<float>(scenario.arena.width_m);
  safety.arena_height_m = static_cast<float>(scenario.arena.height_m);
  return safety;
}

}  // namespace syrof::lab::sim
