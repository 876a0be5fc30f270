// The robot image's motion layer for each kind (boot_words.h,
// ConfigureImageKinds, what RobotImage::Prepare sets) against the lab's
// robot of the same kind in the same swarm (lab::sim::RobotConfigFor): the
// same controller, the same safety filter's view of the swarm and walls,
// and a drone's estimator at the same flight height.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "syrof/firmware/robot/boot_words.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/run_parts.h"

namespace syrof::firmware::robot {
namespace {

lab::scenario::Scenario Load(const std::string& text) {
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

void ExpectSameMotionLayer(const runtime::RobotConfig& lab, const runtime::RobotConfig& image, const std::string& who) {
  const motion::ControllerConfig& a = lab.motion;
  const motion::ControllerConfig& b = image.motion;
  EXPECT_EQ(a.kind, b.kind) << who;
  EXPECT_EQ(a.limits.max_speed_mps, b.limits.max_speed_mps) << who;
  EXPECT_EQ(a.limits.max_accel_mps2, b.limits.max_accel_mps2) << who;
  EXPECT_EQ(a.limits.max_turn_rate_radps, b.limits.max_turn_rate_radps) << who;
  EXPECT_EQ(a.limits.wheel_base_m, b.limits.wheel_base_m) << who;
  EXPECT_EQ(a.limits.body_radius_m, b.limits.body_radius_m) << who;
  EXPECT_EQ(a.limits.response_lag_s, b.limits.response_lag_s) << who;
  EXPECT_EQ(a.position_gain_per_s, b.position_gain_per_s) << who;
  EXPECT_EQ(a.braking_fraction, b.braking_fraction) << who;
  EXPECT_EQ(a.hold_position, b.hold_position) << who;

  EXPECT_EQ(lab.safety.enabled, image.safety.enabled) << who;
  EXPECT_EQ(lab.safety.others_max_speed_mps, image.safety.others_max_speed_mps) << who;
  EXPECT_EQ(lab.safety.others_radius_m, image.safety.others_radius_m) << who;
  EXPECT_EQ(lab.safety.others_braking_mps2, image.safety.others_braking_mps2) << who;
  EXPECT_EQ(lab.safety.others_lag_s, image.safety.others_lag_s) << who;
  EXPECT_EQ(lab.safety.own_sigmas, image.safety.own_sigmas) << who;
  EXPECT_EQ(lab.safety.arena_width_m, image.safety.arena_width_m) << who;
  EXPECT_EQ(lab.safety.arena_height_m, image.safety.arena_height_m) << who;

  EXPECT_EQ(lab.estimator.flow_geometry.height_m, image.estimator.flow_geometry.height_m) << who;
  EXPECT_EQ(lab.estimator.flow_geometry.pixels, image.estimator.flow_geometry.pixels) << who;
  EXPECT_EQ(lab.estimator.flow_geometry.mounting_angle_rad, image.estimator.flow_geometry.mounting_angle_rad) << who;
  // The lab's drone takes its viewing angle from the scenario's sensors
  // (25 degrees in double, then float); the image keeps the estimator's
  // float default: the same angle, rounded once or twice.
  EXPECT_FLOAT_EQ(lab.estimator.flow_geometry.viewing_angle_rad, image.estimator.flow_geometry.viewing_angle_rad) << who;
  EXPECT_EQ(lab.estimator.arena.tag_height_m, image.estimator.arena.tag_height_m) << who;
}

void ExpectTheImageRunsTheLabsMotionLayer(const lab::scenario::Scenario& scenario) {
  KindSet swarm = 0;
  for (const lab::scenario::RobotSpec& robot : scenario.robots) swarm |= KindBit(robot.kind);
  // What the image's boot words carry: every robot's kind (member_kinds).
  const std::vector<motion::RobotKind> members = lab::sim::MemberKindsOf(scenario);
  const bool one_kind = (swarm & (swarm - 1)) == 0;
  for (const lab::scenario::RobotSpec& robot : scenario.robots) {
    const runtime::RobotConfig lab = lab::sim::RobotConfigFor(scenario, robot);
    runtime::RobotConfig image;
    image.sync = sync::SyncConfig::ForSwarm(static_cast<uint16_t>(scenario.robots.size()), robot.id);
    std::array<motion::RobotKind, 8> storage{};
    ASSERT_EQ(ConfigureImageKinds(image, robot.kind, swarm, one_kind ? std::span<const motion::RobotKind>() : members,
                                  storage),
              nullptr);
    const std::string who = std::string(motion::ToString(robot.kind)) + " robot " + std::to_string(robot.id);
    ExpectSameMotionLayer(lab, image, who);
    // The app's view of the kinds: its own and its members', as in the lab.
    EXPECT_EQ(image.kind, lab.kind) << who;
    EXPECT_EQ(std::vector<motion::RobotKind>(image.member_kinds.begin(), image.member_kinds.end()), members) << who;
  }
}

TEST(ImageKindsTest, EachKindInAMixedSwarmRunsTheLabsMotionLayer) {
  ExpectTheImageRunsTheLabsMotionLayer(Load(R"(robots:
  kind: omni
  poses:
    - { x_m: 0.6, y_m: 0.6 }
    - { x_m: 2.0, y_m: 0.6, kind: rover, heading_rad: 1.5708 }
    - { x_m: 3.4, y_m: 0.6, kind: drone }
app: builtin:gather
)"));
}

TEST(ImageKindsTest, ADroneSwarmAndAnOmniSwarmRunTheLabsMotionLayer) {
  ExpectTheImageRunsTheLabsMotionLayer(Load("robots: { count: 4, kind: drone, placement: circle, radius_m: 1.0 }\n"
                                            "app: builtin:gather\n"));
  ExpectTheImageRunsTheLabsMotionLayer(Load("robots: { count: 4, kind: omni, placement: circle, radius_m: 1.0 }\n"
                                            "app: builtin:gather\n"));
  // An image without kind words is an omni robot among omni robots.
  BootKind none;
  runtime::RobotConfig image;
  std::array<motion::RobotKind, 4> storage{};
  ASSERT_EQ(ConfigureImageKinds(image, none.self(), none.swarm(), none.members(), storage), nullptr);
  EXPECT_EQ(image.motion.kind, motion::DriveKind::kOmni);
  EXPECT_EQ(image.motion.limits.response_lag_s, 0.0f);
}

}  // namespace
}  // namespace syrof::firmware::robot
