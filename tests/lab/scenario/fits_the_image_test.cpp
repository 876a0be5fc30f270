// CheckScenarioFitsTheImage (lab/scenario fits_the_image.h): a scenario on
// the image's radio round, the default arena and the default kinds' limits
// passes; one that changes any of them is named by what differs, in the
// words both firmware host tools print, the radio round first, then the
// synchronizer's timing (app_round_s, K, F), then the arena, then the kinds.
#include "syrof/lab/scenario/fits_the_image.h"

#include <gtest/gtest.h>

#include <string>

#include "scenario_test_util.h"

namespace syrof::lab::scenario {
namespace {

using testing::Load;

Scenario LoadOk(const std::string& text) {
  const LoadResult loaded = Load(text);
  EXPECT_TRUE(loaded.ok()) << loaded.error->ToString();
  return *loaded.scenario;
}

constexpr const char* kArenaTail =
    "; the robot image has the default arena compiled in (4 m x 4 m, tag_height_m 0.10, the four default anchors; "
    "docs/scenarios.md) and its estimates would be off";

// The message for `text` loaded, or "fits".
std::string Verdict(const std::string& text) {
  const auto error = CheckScenarioFitsTheImage(LoadOk(text));
  return error ? error->message : "fits";
}

TEST(ScenarioFitsTheImage, TheDefaultsPass) {
  EXPECT_EQ(Verdict("robots: { count: 4 }\napp: builtin:idle\n"), "fits");
  EXPECT_EQ(Verdict("robots:\n  kind: omni\n  poses:\n    - { x_m: 1, y_m: 1 }\n"
                    "    - { x_m: 2, y_m: 2, kind: rover }\n"
                    "    - { x_m: 3, y_m: 3, kind: drone }\napp: builtin:idle\n"),
            "fits");
  // The defaults written out.
  EXPECT_EQ(Verdict("arena:\n  width_m: 4\n  height_m: 4\n  tag_height_m: 0.10\n  anchors:\n"
                    "    - { x_m: 0, y_m: 0, z_m: 0 }\n    - { x_m: 4, y_m: 4, z_m: 0 }\n"
                    "    - { x_m: 0, y_m: 4, z_m: 2 }\n    - { x_m: 4, y_m: 0, z_m: 2 }\n"
                    "timing: { radio_round_s: 0.05 }\nrobots: { count: 4 }\napp: builtin:idle\n"),
            "fits");
}

// The robots' radio carries one BLE advertisement (31 bytes): 16 robots'
// beacon fits, 17 robots' does not, and the firmware's link would drop
// every one of their beacons silently. Checked before anything else.
TEST(ScenarioFitsTheImage, ASwarmWhoseBeaconTheRadioCannotCarryIsRefusedFirst) {
  EXPECT_EQ(Verdict("arena: { width_m: 4, height_m: 4 }\nrobots: { count: 16, placement: grid, spacing_m: 0.6 }\n"
                    "app: builtin:idle\n"),
            "fits");
  EXPECT_EQ(Verdict("timing: { radio_round_s: 0.1, app_round_s: 1.0 }\n"
                    "robots: { count: 17, placement: grid, spacing_m: 0.6 }\napp: builtin:idle\n"),
            "17 robots; their beacon would be 32 bytes, more than the robots' radio carries (31, one BLE "
            "advertisement): the robot image runs swarms of at most 16 robots (docs/beacon.md)");
}

TEST(ScenarioFitsTheImage, ARadioRoundOtherThanTheImagesIsRefused) {
  const auto error = CheckScenarioFitsTheImage(
      LoadOk("timing: { radio_round_s: 0.1, app_round_s: 1.0 }\nrobots: { count: 4 }\napp: builtin:idle\n"));
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->ToString(), "test: timing.radio_round_s must be 0.05 (the robot image's radio round)");
}

TEST(ScenarioFitsTheImage, AnotherArenaIsNamedByItsFirstDifference) {
  // The size (strongest_6.yaml's 5 m arena: 1.3 m RMSE on the image).
  const auto error = CheckScenarioFitsTheImage(
      LoadOk("arena: { width_m: 5, height_m: 5 }\nrobots: { count: 4 }\napp: builtin:idle\n"));
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->ToString(), std::string("test: the arena is 5 m x 5 m") + kArenaTail);
  EXPECT_EQ(Verdict("arena: { width_m: 4, height_m: 5 }\nrobots: { count: 4 }\napp: builtin:idle\n"),
            std::string("the arena is 4 m x 5 m") + kArenaTail);
  // The antennas' height.
  EXPECT_EQ(Verdict("arena: { tag_height_m: 0.2 }\nrobots: { count: 4 }\napp: builtin:idle\n"),
            std::string("arena.tag_height_m is 0.2 m") + kArenaTail);
  // The anchors: how many, then which one moved.
  EXPECT_EQ(Verdict("arena:\n  anchors:\n    - { x_m: 0, y_m: 0, z_m: 0 }\n    - { x_m: 4, y_m: 4, z_m: 0 }\n"
                    "    - { x_m: 0, y_m: 4, z_m: 2 }\nrobots: { count: 4 }\napp: builtin:idle\n"),
            std::string("arena.anchors lists 3 anchors") + kArenaTail);
  EXPECT_EQ(Verdict("arena:\n  anchors:\n    - { x_m: 0, y_m: 0, z_m: 0 }\n    - { x_m: 4, y_m: 4, z_m: 0 }\n"
                    "    - { x_m: 0, y_m: 4, z_m: 2.5 }\n    - { x_m: 4, y_m: 0, z_m: 2 }\n"
                    "robots: { count: 4 }\napp: builtin:idle\n"),
            std::string("arena.anchors[2] is elsewhere") + kArenaTail);
}

constexpr const char* kTimingTail =
    " compiled in (its synchronizer's timing, docs/scenarios.md) and would run its epochs on other timing";

TEST(ScenarioFitsTheImage, TheImagesTimingWrittenOutFits) {
  EXPECT_EQ(Verdict("timing: { radio_round_s: 0.05, app_round_s: 1.0, vote_rounds: 3, silence_rounds: 6, "
                    "duration_s: 20 }\nrobots: { count: 4 }\napp: builtin:idle\n"),
            "fits");
}

// Before, the image ran its own 20 rounds of PROGRESS, K = 3 and F = 6
// whatever the scenario said, while the lab ran the scenario's.
TEST(ScenarioFitsTheImage, AnotherSynchronizerTimingIsNamedByFieldWithBothValues) {
  const std::string robots = "robots: { count: 4 }\napp: builtin:idle\n";
  EXPECT_EQ(Verdict("timing: { app_round_s: 2.0 }\n" + robots),
            std::string("timing.app_round_s is 2; the robot image has 1") + kTimingTail);
  EXPECT_EQ(Verdict("timing: { vote_rounds: 4, silence_rounds: 6 }\n" + robots),
            std::string("timing.vote_rounds is 4; the robot image has 3") + kTimingTail);
  EXPECT_EQ(Verdict("timing: { silence_rounds: 8 }\n" + robots),
            std::string("timing.silence_rounds is 8; the robot image has 6") + kTimingTail);
  // In the fields' order: app_round_s before K before F.
  EXPECT_EQ(Verdict("timing: { app_round_s: 0.5, vote_rounds: 2, silence_rounds: 5 }\n" + robots),
            std::string("timing.app_round_s is 0.5; the robot image has 1") + kTimingTail);
  EXPECT_EQ(Verdict("timing: { vote_rounds: 2, silence_rounds: 5 }\n" + robots),
            std::string("timing.vote_rounds is 2; the robot image has 3") + kTimingTail);
}

TEST(ScenarioFitsTheImage, TheRadioRoundComesFirstThenTheTimingThenTheArenaThenTheKinds) {
  const std::string kinds = "kinds: { omni: { body_radius_m: 0.15 } }\nrobots: { count: 4 }\napp: builtin:idle\n";
  const std::string arena = "arena: { width_m: 5, height_m: 5 }\n";
  const std::string round = "timing: { radio_round_s: 0.1, app_round_s: 1.0, silence_rounds: 8 }\n";
  EXPECT_EQ(Verdict(round + arena + kinds), "timing.radio_round_s must be 0.05 (the robot image's radio round)");
  const std::string timing = "timing: { silence_rounds: 8 }\n";
  EXPECT_EQ(Verdict(timing + arena + kinds), std::string("timing.silence_rounds is 8; the robot image has 6") + kTimingTail);
  EXPECT_EQ(Verdict(arena + kinds), std::string("the arena is 5 m x 5 m") + kArenaTail);
  EXPECT_EQ(Verdict(kinds).rfind("kinds.omni.body_radius_m is 0.15; ", 0), 0u) << Verdict(kinds);
}

TEST(ScenarioFitsTheImage, APresentKindsChangedLimitIsNamedWithBothValues) {
  const Scenario drones =
      LoadOk("kinds: { drone: { max_speed_mps: 1.0 } }\nrobots: { count: 4, kind: drone }\napp: builtin:idle\n");
  const auto error = CheckScenarioFitsTheImage(drones);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->ToString(),
            "test: kinds.drone.max_speed_mps is 1; the robot image has 0.8 compiled in (the default kinds, "
            "docs/scenarios.md) and would drive its robots with other limits");
  // A rover among omni robots: the rover's wheel base counts.
  const Scenario rover = LoadOk(
      "kinds: { rover: { wheel_base_m: 0.2 } }\nrobots:\n  kind: omni\n  poses:\n    - { x_m: 1, y_m: 1 }\n"
      "    - { x_m: 2, y_m: 2, kind: rover }\napp: builtin:idle\n");
  const auto wheels = CheckScenarioFitsTheImage(rover);
  ASSERT_TRUE(wheels.has_value());
  EXPECT_EQ(wheels->message.rfind("kinds.rover.wheel_base_m is 0.2; the robot image has 0.16 ", 0), 0u)
      << wheels->message;
}

TEST(ScenarioFitsTheImage, TheFirstKindFieldInOrderIsNamed) {
  const Scenario omni = LoadOk(
      "kinds: { omni: { max_accel_mps2: 2.0, body_radius_m: 0.15 } }\nrobots: { count: 2 }\napp: builtin:idle\n");
  const auto error = CheckScenarioFitsTheImage(omni);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->message.rfind("kinds.omni.body_radius_m is 0.15; the robot image has 0.1 ", 0), 0u)
      << error->message;
}

TEST(ScenarioFitsTheImage, AnAbsentKindAndADronesDriftMayChange) {
  // No drone in the scenario: its limits are never driven.
  EXPECT_EQ(Verdict("kinds: { drone: { max_speed_mps: 1.0 } }\nrobots: { count: 4 }\napp: builtin:idle\n"), "fits");
  // The drift is the world's alone.
  EXPECT_EQ(Verdict("kinds: { drone: { drift_sigma_mps: 0.02 } }\nrobots: { count: 4, kind: drone }\n"
                    "app: builtin:idle\n"),
            "fits");
}

// The lab's robot weighs its readings with the scenario's sensor noise
// (lab/sim robot_config.cpp), the image with its estimator's defaults: a
// scenario with other noise would estimate otherwise on the image than in
// the lab, and one with safety off would drive otherwise (the image's
// filter is always on). Both are refused by name, UWB before flow, after
// the kinds.
TEST(ScenarioFitsTheImage, OtherSensorNoiseOrSafetyOffIsNamed) {
  EXPECT_EQ(Verdict("sensors: { uwb: { sigma_m: 0.2 } }\nrobots: { count: 4 }\napp: builtin:idle\n"),
            "sensors.uwb.sigma_m is 0.2; the robot image's estimator has 0.1 compiled in (the default sensors, "
            "docs/scenarios.md) and would weigh its readings otherwise than the lab's robots");
  EXPECT_EQ(Verdict("sensors: { flow: { sigma_px: 1 }, uwb: { sigma_m: 0.05 } }\nrobots: { count: 4 }\n"
                    "app: builtin:idle\n")
                .rfind("sensors.uwb.sigma_m is 0.05; ", 0),
            0u);
  EXPECT_EQ(Verdict("sensors: { flow: { sigma_px: 1 } }\nrobots: { count: 4 }\napp: builtin:idle\n")
                .rfind("sensors.flow.sigma_px is 1; the robot image's estimator has 2 compiled in", 0),
            0u);
  // The defaults written out, and noise the estimator does not weigh.
  EXPECT_EQ(Verdict("sensors: { uwb: { sigma_m: 0.10, outlier_probability: 0.05 }, flow: { sigma_px: 2 } }\n"
                    "robots: { count: 4 }\napp: builtin:idle\n"),
            "fits");
  EXPECT_EQ(Verdict("safety: off\nrobots: { count: 4 }\napp: builtin:idle\n"),
            "safety is off; the robot image runs its safety filter always (docs/safety.md) and would drive otherwise "
            "than the lab's robots");
  EXPECT_EQ(Verdict("kinds: { omni: { body_radius_m: 0.15 } }\nsafety: off\nsensors: { uwb: { sigma_m: 0.2 } }\n"
                    "robots: { count: 4 }\napp: builtin:idle\n")
                .rfind("kinds.omni.body_radius_m", 0),
            0u);
}

TEST(ScenarioFitsTheImage, WhereIsTheFileThatWasRead) {
  Scenario drones =
      LoadOk("kinds: { drone: { flight_height_m: 0.5 } }\nrobots: { count: 2, kind: drone }\napp: builtin:idle\n");
  drones.source = "lab/scenarios/high_drones.yaml";
  EXPECT_EQ(CheckScenarioFitsTheImage(drones)->where, "lab/scenarios/high_drones.yaml");
  EXPECT_EQ(CheckScenarioFitsTheImage(drones)->line, 0);
  Scenario wide = LoadOk("arena: { width_m: 5, height_m: 5 }\nrobots: { count: 4 }\napp: builtin:idle\n");
  wide.source = "lab/scenarios/wide.yaml";
  EXPECT_EQ(CheckScenarioFitsTheImage(wide)->where, "lab/scenarios/wide.yaml");
}

}  // namespace
}  // namespace syrof::lab::scenario
