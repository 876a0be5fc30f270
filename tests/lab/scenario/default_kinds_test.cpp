// CheckDefaultKindLimits (lab/scenario default_kinds.h): a scenario whose
// present kinds keep motion::DefaultKindLimits passes; one that changes a
// present kind's limit is named by its field, its value and the image's,
// the words both firmware host tools print.
#include "syrof/lab/scenario/default_kinds.h"

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

TEST(DefaultKindLimits, TheDefaultKindsPass) {
  EXPECT_FALSE(CheckDefaultKindLimits(LoadOk("robots: { count: 4 }\napp: builtin:idle\n")).has_value());
  EXPECT_FALSE(CheckDefaultKindLimits(LoadOk("robots:\n  kind: omni\n  poses:\n    - { x_m: 1, y_m: 1 }\n"
                                             "    - { x_m: 2, y_m: 2, kind: rover }\n"
                                             "    - { x_m: 3, y_m: 3, kind: drone }\napp: builtin:idle\n"))
                   .has_value());
}

TEST(DefaultKindLimits, APresentKindsChangedLimitIsNamedWithBothValues) {
  const Scenario drones =
      LoadOk("kinds: { drone: { max_speed_mps: 1.0 } }\nrobots: { count: 4, kind: drone }\napp: builtin:idle\n");
  const auto error = CheckDefaultKindLimits(drones);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->ToString(),
            "test: kinds.drone.max_speed_mps is 1; the robot image has 0.8 compiled in (the default kinds, "
            "docs/scenarios.md) and would drive its robots with other limits");
  // A rover among omni robots: the rover's wheel base counts.
  const Scenario rover = LoadOk(
      "kinds: { rover: { wheel_base_m: 0.2 } }\nrobots:\n  kind: omni\n  poses:\n    - { x_m: 1, y_m: 1 }\n"
      "    - { x_m: 2, y_m: 2, kind: rover }\napp: builtin:idle\n");
  const auto wheels = CheckDefaultKindLimits(rover);
  ASSERT_TRUE(wheels.has_value());
  EXPECT_EQ(wheels->message.rfind("kinds.rover.wheel_base_m is 0.2; the robot image has 0.16 ", 0), 0u)
      << wheels->message;
}

TEST(DefaultKindLimits, TheFirstFieldInOrderIsNamed) {
  const Scenario omni = LoadOk(
      "kinds: { omni: { max_accel_mps2: 2.0, body_radius_m: 0.15 } }\nrobots: { count: 2 }\napp: builtin:idle\n");
  const auto error = CheckDefaultKindLimits(omni);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->message.rfind("kinds.omni.body_radius_m is 0.15; the robot image has 0.1 ", 0), 0u)
      << error->message;
}

TEST(DefaultKindLimits, AnAbsentKindAndADronesDriftMayChange) {
  // No drone in the scenario: its limits are never driven.
  EXPECT_FALSE(CheckDefaultKindLimits(LoadOk("kinds: { drone: { max_speed_mps: 1.0 } }\nrobots: { count: 4 }\n"
                                             "app: builtin:idle\n"))
                   .has_value());
  // The drift is the world's alone.
  EXPECT_FALSE(CheckDefaultKindLimits(LoadOk("kinds: { drone: { drift_sigma_mps: 0.02 } }\n"
                                             "robots: { count: 4, kind: drone }\napp: builtin:idle\n"))
                   .has_value());
}

TEST(DefaultKindLimits, WhereIsTheFileThatWasRead) {
  Scenario drones =
      LoadOk("kinds: { drone: { flight_height_m: 0.5 } }\nrobots: { count: 2, kind: drone }\napp: builtin:idle\n");
  drones.source = "lab/scenarios/high_drones.yaml";
  EXPECT_EQ(CheckDefaultKindLimits(drones)->where, "lab/scenarios/high_drones.yaml");
  EXPECT_EQ(CheckDefaultKindLimits(drones)->line, 0);
}

}  // namespace
}  // namespace syrof::lab::scenario
