// Every scenario shipped in lab/scenarios/ loads, and what it loads into
// builds a world and a channel (the loader's promise to lab/world).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/world/channel.h"
#include "syrof/lab/world/world.h"

namespace syrof::lab::scenario {
namespace {

std::vector<std::filesystem::path> ExampleFiles() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(SYROF_SCENARIOS_DIR)) {
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  }
  return files;
}

TEST(ExampleScenarios, EveryFileLoads) {
  const std::vector<std::filesystem::path> files = ExampleFiles();

  ASSERT_GE(files.size(), 12u);
  for (const std::filesystem::path& file : files) {
    const LoadResult result = LoadScenarioFile(file.string());

    EXPECT_TRUE(result.ok()) << result.error->ToString();
    if (result.ok()) {
      EXPECT_EQ(result.scenario->name, file.stem().string());
    }
  }
}

// World and Channel stop the program on a spec that fails their checks;
// the loader must never hand one over.
TEST(ExampleScenarios, EveryLoadedScenarioPassesTheWorldsAndChannelsChecks) {
  for (const std::filesystem::path& file : ExampleFiles()) {
    const LoadResult result = LoadScenarioFile(file.string());
    ASSERT_TRUE(result.ok()) << result.error->ToString();
    const Scenario& scenario = *result.scenario;
    std::vector<world::BodySpec> bodies;
    for (const RobotSpec& robot : scenario.robots) {
      bodies.push_back(world::BodySpec{robot.id, robot.kind, scenario.kind_spec(robot.kind), robot.x_m, robot.y_m,
                                       robot.heading_rad, world::BodyPresence::kActive});
    }
    const auto robots = static_cast<uint16_t>(scenario.robots.size());

    const std::optional<Error> world_problem = world::CheckWorldSpec(scenario.arena, bodies);
    const std::optional<Error> channel_problem = world::CheckChannelSpec(scenario.channel, robots);

    EXPECT_FALSE(world_problem.has_value()) << file << ": " << world_problem->ToString();
    EXPECT_FALSE(channel_problem.has_value()) << file << ": " << channel_problem->ToString();
  }
}

TEST(ExampleScenarios, DemoCircleIsTenOmniRobotsInTheDefaultArena) {
  const LoadResult result = LoadScenarioFile(std::string(SYROF_SCENARIOS_DIR) + "/demo_circle.yaml");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const Scenario& scenario = *result.scenario;
  EXPECT_EQ(scenario.robots.size(), 10u);
  EXPECT_EQ(scenario.app.name, "builtin:circle");
  EXPECT_EQ(scenario.arena.width_m, 4);
  EXPECT_EQ(scenario.channel.model, world::ChannelModel::kIid);
  EXPECT_EQ(scenario.channel.loss, 0.1);
  EXPECT_EQ(scenario.timing.duration_s, 60);
}

TEST(ExampleScenarios, BenchStandardScalesToFourHundredRobots) {
  const std::string path = std::string(SYROF_SCENARIOS_DIR) + "/bench_standard.yaml";
  Overrides overrides;
  overrides.robots = 400;

  const LoadResult standard = LoadScenarioFile(path);
  const LoadResult scaled = LoadScenarioFile(path, overrides);

  ASSERT_TRUE(standard.ok()) << standard.error->ToString();
  EXPECT_EQ(standard.scenario->robots.size(), 100u);
  EXPECT_EQ(standard.scenario->arena.width_m, 20);
  EXPECT_EQ(standard.scenario->sensors.arena.anchor_count, 4);
  EXPECT_EQ(standard.scenario->timing.duration_s, 10);
  ASSERT_TRUE(scaled.ok()) << scaled.error->ToString();
  EXPECT_EQ(scaled.scenario->robots.size(), 400u);
}

}  // namespace
}  // namespace syrof::lab::scenario
