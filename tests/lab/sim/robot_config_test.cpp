// RobotConfigFor: what a simulated robot is told, from the scenario alone.
#include "syrof/lab/sim/robot_config.h"

#include <gtest/gtest.h>

#include <string>

namespace syrof::lab::sim {
namespace {

scenario::Scenario Load(const std::string& text) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// Two omni robots and a rover, the rover switched on late.
const char* const kMixed = R"(seed: 5
kinds:
  rover: { body_radius_m: 0.12, max_speed_mps: 0.4, max_accel_mps2: 0.8, wheel_base_m: 0.16 }
robots:
  kind: omni
  poses:
    - { x_m: 1.0, y_m: 1.0 }
    - { x_m: 2.0, y_m: 1.5, heading_rad: 0.5 }
    - { x_m: 3.0, y_m: 3.0, heading_rad: -1.5708, kind: rover }
timing: { radio_round_s: 0.05, app_round_s: 1.0, vote_rounds: 4, silence_rounds: 8 }
faults: [{join: 2, at_s: 2}]
app: builtin:idle
)";

TEST(RobotConfigForTest, SynchronizerKnowsTheSwarmAndWhoIsThereAtStart) {
  const scenario::Scenario scenario = Load(kMixed);

  const runtime::RobotConfig config = RobotConfigFor(scenario, scenario.robots[1]);

  EXPECT_EQ(config.sync.swarm_size, 3);
  EXPECT_EQ(config.sync.self_id, 1);
  EXPECT_EQ(config.sync.vote_rounds, 4);
  EXPECT_EQ(config.sync.silence_rounds, 8);
  EXPECT_TRUE(config.sync.initial_members.test(0));
  EXPECT_TRUE(config.sync.initial_members.test(1));
  EXPECT_FALSE(config.sync.initial_members.test(2));  // joins at 2 s
  EXPECT_EQ(config.radio_round_ns, 50'000'000);
  EXPECT_EQ(config.queries_workspace, nullptr);  // the caller's
}

TEST(RobotConfigForTest, ADronesFlowSensorAndAntennaFlyAtItsHeight) {
  const scenario::Scenario scenario = Load(R"(kinds: { drone: { flight_height_m: 0.4 } }
robots:
  kind: drone
  poses: [ { x_m: 1.0, y_m: 1.0 }, { x_m: 3.0, y_m: 3.0, kind: omni } ]
app: builtin:idle
)");
  const sensors::SensorBankConfig drone_bank = SensorConfigFor(scenario, scenario.robots[0]);
  const sensors::SensorBankConfig omni_bank = SensorConfigFor(scenario, scenario.robots[1]);
  EXPECT_DOUBLE_EQ(drone_bank.flow.geometry.height_m, 0.4);
  EXPECT_DOUBLE_EQ(drone_bank.arena.tag_height_m, 0.4);
  EXPECT_DOUBLE_EQ(omni_bank.flow.geometry.height_m, scenario.sensors.flow.geometry.height_m);
  EXPECT_DOUBLE_EQ(omni_bank.arena.tag_height_m, scenario.sensors.arena.tag_height_m);
  // Four times as high: four times the metres per pixel.
  EXPECT_NEAR(estimation::FlowMetresPerPixel(drone_bank.flow.geometry) /
                  estimation::FlowMetresPerPixel(omni_bank.flow.geometry),
              4.0, 1e-9);

  // The estimator is told the same geometry as the sensors.
  const runtime::RobotConfig drone = RobotConfigFor(scenario, scenario.robots[0]);
  const runtime::RobotConfig omni = RobotConfigFor(scenario, scenario.robots[1]);
  EXPECT_FLOAT_EQ(drone.estimator.flow_geometry.height_m, 0.4f);
  EXPECT_FLOAT_EQ(drone.estimator.arena.tag_height_m, 0.4f);
  EXPECT_FLOAT_EQ(omni.estimator.flow_geometry.height_m, static_cast<float>(omni_bank.flow.geometry.height_m));
  EXPECT_FLOAT_EQ(omni.estimator.arena.tag_height_m, static_cast<float>(omni_bank.arena.tag_height_m));
  EXPECT_EQ(drone.motion.kind, motion::DriveKind::kOmni);
}

TEST(RobotConfigForTest, ManeuverRoundsRoundToTheNearestWholeRound) {
  scenario::TimingSpec timing;
  timing.radio_round_s = 0.05;
  timing.app_round_s = 1.0;  // 1.0 / 0.05 is 19.999... in binary
  EXPECT_EQ(ManeuverRounds(timing), 20);
  timing.radio_round_s = 0.1;
  timing.app_round_s = 0.7;  // 6.999...
  EXPECT_EQ(ManeuverRounds(timing), 7);
  timing.radio_round_s = 0.03;
  timing.app_round_s = 0.3;
  EXPECT_EQ(ManeuverRounds(timing), 10);
}

TEST(RobotConfigForTest, StartPoseIsThePlacementWithTheHandPlacementSigmas) {
  const scenario::Scenario scenario = Load(kMixed);

  const runtime::RobotConfig config = RobotConfigFor(scenario, scenario.robots[1]);

  EXPECT_FLOAT_EQ(config.initial_pose.x_m, 2.0f);
  EXPECT_FLOAT_EQ(config.initial_pose.y_m, 1.5f);
  EXPECT_FLOAT_EQ(config.initial_pose.heading_rad, 0.5f);
  EXPECT_FLOAT_EQ(config.initial_pose.position_sigma_m, 0.05f);
  EXPECT_FLOAT_EQ(config.initial_pose.heading_sigma_rad, 0.05f);
}

TEST(RobotConfigForTest, EstimatorNoiseIsTheSensorsButNeverBelowTheFloors) {
  scenario::Scenario scenario = Load(kMixed);

  const runtime::RobotConfig noisy = RobotConfigFor(scenario, scenario.robots[0]);
  scenario.sensors.uwb.sigma_m = 0;
  scenario.sensors.flow.sigma_px = 0;
  const runtime::RobotConfig perfect = RobotConfigFor(scenario, scenario.robots[0]);

  EXPECT_FLOAT_EQ(noisy.estimator.range_sigma_m, static_cast<float>(scenario::Scenario{}.sensors.uwb.sigma_m));
  EXPECT_FLOAT_EQ(noisy.estimator.flow_sigma_px, static_cast<float>(scenario::Scenario{}.sensors.flow.sigma_px));
  EXPECT_FLOAT_EQ(perfect.estimator.range_sigma_m, 0.02f);
  EXPECT_FLOAT_EQ(perfect.estimator.flow_sigma_px, 0.5f);
}

TEST(RobotConfigForTest, EstimatorArenaIsTheSensorsArena) {
  const scenario::Scenario scenario = Load(kMixed);

  const runtime::RobotConfig config = RobotConfigFor(scenario, scenario.robots[0]);

  EXPECT_EQ(config.estimator.arena.anchor_count, scenario.sensors.arena.anchor_count);
  EXPECT_FLOAT_EQ(config.estimator.arena.width_m, static_cast<float>(scenario.sensors.arena.width_m));
  for (int i = 0; i < config.estimator.arena.anchor_count; ++i) {
    EXPECT_FLOAT_EQ(config.estimator.arena.anchors[i].x(), static_cast<float>(scenario.sensors.arena.anchors[i].x()));
  }
  EXPECT_FLOAT_EQ(config.arena_width_m, static_cast<float>(scenario.arena.width_m));
  EXPECT_FLOAT_EQ(config.arena_height_m, static_cast<float>(scenario.arena.height_m));
}

TEST(RobotConfigForTest, MotionLimitsAreTheRobotsKinds) {
  const scenario::Scenario scenario = Load(kMixed);

  const runtime::RobotConfig omni = RobotConfigFor(scenario, scenario.robots[0]);
  const runtime::RobotConfig rover = RobotConfigFor(scenario, scenario.robots[2]);

  EXPECT_EQ(omni.motion.kind, motion::DriveKind::kOmni);
  EXPECT_FLOAT_EQ(omni.motion.limits.body_radius_m, static_cast<float>(scenario.omni.body_radius_m));
  EXPECT_EQ(rover.motion.kind, motion::DriveKind::kWheels);
  EXPECT_FLOAT_EQ(rover.motion.limits.body_radius_m, 0.12f);
}

TEST(ControllerConfigForTest, CarriesTheKindsLimits) {
  const world::KindSpec rover{0.12, 0.4, 0.8, 3.0, 0.16};

  const motion::ControllerConfig config = ControllerConfigFor(world::RobotKind::kRover, rover);

  EXPECT_EQ(config.kind, motion::DriveKind::kWheels);
  EXPECT_FLOAT_EQ(config.limits.max_speed_mps, 0.4f);
  EXPECT_FLOAT_EQ(config.limits.max_accel_mps2, 0.8f);
  EXPECT_FLOAT_EQ(config.limits.max_turn_rate_radps, 3.0f);
  EXPECT_FLOAT_EQ(config.limits.wheel_base_m, 0.16f);
  EXPECT_FLOAT_EQ(config.limits.body_radius_m, 0.12f);
  EXPECT_EQ(ControllerConfigFor(world::RobotKind::kOmni, rover).kind, motion::DriveKind::kOmni);
}

}  // namespace
}  // namespace syrof::lab::sim
