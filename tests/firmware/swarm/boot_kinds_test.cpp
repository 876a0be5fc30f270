// Each robot's boot line (qemu_launcher.h, ImageAppend) names its kind and,
// in a swarm of mixed kinds, the swarm's (boot_words.h): the robot image runs
// the motion layer of that kind (docs/firmware.md, "Robot kinds").
#include <gtest/gtest.h>

#include <string>

#include "syrof/firmware/swarm/qemu_launcher.h"
#include "syrof/firmware/swarm/swarm_options.h"

namespace syrof::firmware::swarm {
namespace {

lab::scenario::Scenario KindsScenario(const std::string& text) {
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

TEST(BootKindsTest, EachRobotIsToldItsKindAndAMixedSwarmItsKinds) {
  const lab::scenario::Scenario mixed = KindsScenario(R"(robots:
  kind: omni
  poses:
    - { x_m: 1.0, y_m: 1.0 }
    - { x_m: 2.0, y_m: 1.0, kind: rover }
    - { x_m: 3.0, y_m: 1.0, kind: drone }
app: builtin:circle
)");
  const Options options;
  EXPECT_NE(ImageAppend(options, mixed, 0).find(" kind omni swarm_kinds omni,rover,drone"), std::string::npos)
      << ImageAppend(options, mixed, 0);
  EXPECT_NE(ImageAppend(options, mixed, 1).find(" kind rover swarm_kinds omni,rover,drone"), std::string::npos);
  EXPECT_NE(ImageAppend(options, mixed, 2).find(" kind drone swarm_kinds omni,rover,drone"), std::string::npos);

  const lab::scenario::Scenario drones =
      KindsScenario("robots: { count: 2, kind: drone, placement: grid, spacing_m: 0.6 }\napp: builtin:circle\n");
  const std::string drone = ImageAppend(options, drones, 1);
  EXPECT_NE(drone.find(" kind drone"), std::string::npos) << drone;
  EXPECT_EQ(drone.find("swarm_kinds"), std::string::npos) << drone;  // its own kind alone

  // Omni robots among omni robots: the line every image had before.
  const lab::scenario::Scenario omni =
      KindsScenario("robots: { count: 2, placement: grid, spacing_m: 0.6 }\napp: builtin:circle\n");
  EXPECT_EQ(ImageAppend(options, omni, 0).find("kind"), std::string::npos) << ImageAppend(options, omni, 0);
}

}  // namespace
}  // namespace syrof::firmware::swarm
