#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scenario_test_util.h"
#include "syrof/estimation/arena.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::kMinimal;
using testing::Load;

std::string WriteTempFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(LoadScenarioText, FillsEveryDefault) {
  const LoadResult result = Load(kMinimal);

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const Scenario& scenario = *result.scenario;
  EXPECT_EQ(scenario.name, "test");
  EXPECT_EQ(scenario.source, "");
  EXPECT_EQ(scenario.seed, 1u);
  EXPECT_EQ(scenario.arena.width_m, 4);
  EXPECT_EQ(scenario.arena.height_m, 4);
  EXPECT_EQ(scenario.placement, Placement::kGrid);
  EXPECT_EQ(scenario.robots.size(), 4u);
  EXPECT_EQ(scenario.omni.body_radius_m, world::DefaultKindSpec(world::RobotKind::kOmni).body_radius_m);
  EXPECT_EQ(scenario.rover.body_radius_m, 0.12);
  EXPECT_EQ(scenario.timing.radio_round_s, 0.05);
  EXPECT_EQ(scenario.timing.vote_rounds, 3);
  EXPECT_EQ(scenario.timing.silence_rounds, 6);
  EXPECT_EQ(scenario.timing.duration_s, 60);
  EXPECT_EQ(scenario.channel.model, world::ChannelModel::kIid);
  EXPECT_EQ(scenario.channel.loss, 0);
  EXPECT_TRUE(scenario.faults.empty());
  EXPECT_EQ(scenario.app.name, "builtin:idle");
  EXPECT_EQ(scenario.sensors.uwb.sigma_m, sensors::UwbModel{}.sigma_m);
}

TEST(LoadScenarioText, DefaultAnchorsAreTheDefaultArenaOnFourMetres) {
  const LoadResult result = Load(kMinimal);
  const estimation::Arena<double> expected = estimation::DefaultArena<double>();

  ASSERT_TRUE(result.ok());
  const estimation::Arena<double>& arena = result.scenario->sensors.arena;
  EXPECT_EQ(arena.width_m, expected.width_m);
  EXPECT_EQ(arena.depth_m, expected.depth_m);
  EXPECT_EQ(arena.tag_height_m, expected.tag_height_m);
  ASSERT_EQ(arena.anchor_count, expected.anchor_count);
  for (int i = 0; i < arena.anchor_count; ++i) EXPECT_EQ(arena.anchors[i], expected.anchors[i]) << i;
}

TEST(LoadScenarioText, DefaultAnchorsStretchOverALargerArena) {
  const LoadResult result = Load(std::string(kMinimal) + "arena: { width_m: 10, height_m: 6 }\n");

  ASSERT_TRUE(result.ok());
  const std::vector<world::AnchorSpec>& anchors = result.scenario->arena.anchors;
  ASSERT_EQ(anchors.size(), 4u);
  EXPECT_EQ(anchors[1].x_m, 10);
  EXPECT_EQ(anchors[1].y_m, 6);
  EXPECT_EQ(anchors[2].z_m, 2);
  EXPECT_EQ(result.scenario->sensors.arena.anchors[3].x(), 10);
}

TEST(LoadScenarioText, ReadsEverySection) {
  const LoadResult result = Load(
      "name: full\n"
      "seed: 9\n"
      "arena:\n"
      "  width_m: 6\n"
      "  height_m: 5\n"
      "  tag_height_m: 0.2\n"
      "  anchors: [ {x_m: 0, y_m: 0, z_m: 0}, {x_m: 6, y_m: 5}, {x_m: 0, y_m: 5, z_m: 2} ]\n"
      "kinds:\n"
      "  omni: { body_radius_m: 0.15, max_speed_mps: 0.3, max_accel_mps2: 0.5, max_turn_rate_radps: 2 }\n"
      "  rover: { wheel_base_m: 0.2 }\n"
      "robots: { count: 3, kind: rover, placement: circle, radius_m: 1.5, centre: { x_m: 3, y_m: 2.5 } }\n"
      "timing: { radio_round_s: 0.1, app_round_s: 2, vote_rounds: 4, silence_rounds: 9, duration_s: 30,\n"
      "          physics_step_s: 0.02 }\n"
      "sensors:\n"
      "  imu: { accel_sigma_mps2: 0.03, gyro_bias_walk_radps_per_sqrt_s: 1e-4 }\n"
      "  flow: { sigma_px: 1.5 }\n"
      "  uwb: { sigma_m: 0.05, outlier_probability: 0, outlier_min_m: 1, outlier_max_m: 3 }\n"
      "channel:\n"
      "  model: gilbert_elliott\n"
      "  good_to_bad: 0.1\n"
      "  bad_to_good: 0.4\n"
      "  loss_good: 0.01\n"
      "  loss_bad: 0.8\n"
      "  links: [ {from: 0, to: 2, loss: 0.3} ]\n"
      "  partitions: [ {start_s: 5, end_s: 10, groups: [[0], [1, 2]]} ]\n"
      "faults: [ {crash: 1, at_s: 20} ]\n"
      "app: { name: 'builtin:gather' }\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const Scenario& scenario = *result.scenario;
  EXPECT_EQ(scenario.name, "full");
  EXPECT_EQ(scenario.seed, 9u);
  EXPECT_EQ(scenario.arena.anchors.size(), 3u);
  EXPECT_EQ(scenario.sensors.arena.tag_height_m, 0.2);
  EXPECT_EQ(scenario.sensors.arena.anchor_count, 3);
  EXPECT_EQ(scenario.omni.max_turn_rate_radps, 2);
  EXPECT_EQ(scenario.rover.wheel_base_m, 0.2);
  EXPECT_EQ(scenario.rover.body_radius_m, 0.12);
  EXPECT_EQ(scenario.robots[2].kind, world::RobotKind::kRover);
  EXPECT_EQ(scenario.placement, Placement::kCircle);
  EXPECT_EQ(scenario.timing.silence_rounds, 9);
  EXPECT_EQ(scenario.timing.physics_step_s, 0.02);
  EXPECT_EQ(scenario.sensors.imu.accel_sigma_mps2, 0.03);
  EXPECT_EQ(scenario.sensors.imu.gyro_bias_walk_radps_per_sqrt_s, 1e-4);
  EXPECT_EQ(scenario.sensors.flow.sigma_px, 1.5);
  EXPECT_EQ(scenario.sensors.uwb.outlier_max_m, 3);
  EXPECT_EQ(scenario.channel.model, world::ChannelModel::kGilbertElliott);
  EXPECT_EQ(scenario.channel.loss_bad, 0.8);
  ASSERT_EQ(scenario.channel.links.size(), 1u);
  EXPECT_EQ(scenario.channel.links[0].to, 2);
  ASSERT_EQ(scenario.channel.partitions.size(), 1u);
  EXPECT_EQ(scenario.channel.partitions[0].groups[1].size(), 2u);
  ASSERT_EQ(scenario.faults.size(), 1u);
  EXPECT_EQ(scenario.app.name, "builtin:gather");
}

TEST(LoadScenarioText, NameDefaultsToScenarioForNonPathFiles) {
  const LoadResult result = LoadScenarioText(kMinimal, "<string>");

  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.scenario->name, "scenario");
}

TEST(ScenarioError, FormatsFileLineColumnAndMessage) {
  const ScenarioError placed{"a.yaml", 3, 7, "bad"};
  const ScenarioError unplaced{"a.yaml", 0, 0, "missing"};

  EXPECT_EQ(placed.ToString(), "a.yaml:3:7: bad");
  EXPECT_EQ(unplaced.ToString(), "a.yaml: missing");
}

TEST(EnumNames, NameEveryValue) {
  EXPECT_STREQ(ToString(world::RobotKind::kRover), "rover");
  EXPECT_STREQ(ToString(static_cast<world::RobotKind>(9)), "?");
  EXPECT_STREQ(ToString(Placement::kRandom), "random");
  EXPECT_STREQ(ToString(world::ChannelModel::kGilbertElliott), "gilbert_elliott");
  EXPECT_STREQ(ToString(FaultKind::kPause), "pause");
}

TEST(MaxRobots, IsTheSwarmCapacity) { EXPECT_EQ(MaxRobots(), 1024); }

// --- overrides --------------------------------------------------------------

TEST(Overrides, ReplaceSeedCountDurationAndApp) {
  Overrides overrides;
  overrides.seed = 77;
  overrides.robots = 9;
  overrides.duration_s = 5;
  overrides.app = "builtin:gather";

  const LoadResult result = Load(kMinimal, overrides);

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->seed, 77u);
  EXPECT_EQ(result.scenario->robots.size(), 9u);
  EXPECT_EQ(result.scenario->timing.duration_s, 5);
  EXPECT_EQ(result.scenario->app.name, "builtin:gather");
}

TEST(Overrides, SmallerCountTakesTheFirstPoses) {
  Overrides overrides;
  overrides.robots = 1;

  const LoadResult result =
      Load("robots: { poses: [ {x_m: 1, y_m: 1}, {x_m: 2, y_m: 2} ] }\napp: builtin:idle\n", overrides);

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  ASSERT_EQ(result.scenario->robots.size(), 1u);
  EXPECT_EQ(result.scenario->robots[0].x_m, 1);
}

TEST(Overrides, LargerCountThanThePosesIsAnError) {
  Overrides overrides;
  overrides.robots = 3;

  const LoadResult result =
      Load("robots: { poses: [ {x_m: 1, y_m: 1}, {x_m: 2, y_m: 2} ] }\napp: builtin:idle\n", overrides);

  EXPECT_TRUE(FailsAt(result, 0, 0, {"robots override 3", "only 2 poses"}));
}

TEST(Overrides, CountOutOfRangeIsAnError) {
  Overrides overrides;
  overrides.robots = 0;

  EXPECT_TRUE(FailsAt(Load(kMinimal, overrides), 0, 0, {"robots override must be in [1, 1024], got 0"}));
}

TEST(Overrides, CountIsCheckedAgainstFaultIds) {
  Overrides overrides;
  overrides.robots = 2;

  const LoadResult result = Load(std::string(kMinimal) + "faults: [ {crash: 3, at_s: 1} ]\n", overrides);

  EXPECT_TRUE(FailsAt(result, 3, 19, {"faults[0].crash: robot id 3 is out of range: the scenario has 2 robots"}));
}

TEST(Overrides, ShorterDurationIsCheckedAgainstFaults) {
  Overrides overrides;
  overrides.duration_s = 2;

  const LoadResult result = Load(std::string(kMinimal) + "faults: [ {crash: 1, at_s: 3} ]\n", overrides);

  EXPECT_TRUE(FailsAt(result, 3, 28, {"faults[0].at_s", "duration_s = 2"}));
}

TEST(Overrides, InvalidDurationIsAnError) {
  Overrides overrides;
  overrides.duration_s = -1;

  EXPECT_TRUE(FailsAt(Load(kMinimal, overrides), 0, 0, {"duration override"}));
}

TEST(Overrides, UnknownAppIsAnError) {
  Overrides overrides;
  overrides.app = "builtin:circel";

  EXPECT_TRUE(FailsAt(Load(kMinimal, overrides), 0, 0, {"app override", "did you mean 'builtin:circle'?"}));
}

// --- files ------------------------------------------------------------------

TEST(LoadScenarioFile, ReadsAFileAndNamesItByItsStem) {
  const std::string path = WriteTempFile("scenario_load_test_swarm.yaml", kMinimal);

  const LoadResult result = LoadScenarioFile(path);

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->name, "scenario_load_test_swarm");
  EXPECT_EQ(result.scenario->source, path);
  std::filesystem::remove(path);
}

TEST(LoadScenarioFile, ErrorsNameTheFile) {
  const std::string path = WriteTempFile("scenario_load_test_bad.yaml", "robots: { count: x }\napp: builtin:idle\n");

  const LoadResult result = LoadScenarioFile(path);

  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error->ToString(), path + ":1:18: robots.count: expected an integer, got 'x'");
  std::filesystem::remove(path);
}

TEST(LoadScenarioFile, MissingFileIsAnError) {
  const LoadResult result = LoadScenarioFile(::testing::TempDir() + "no_such_scenario.yaml");

  EXPECT_TRUE(FailsAt(result, 0, 0, {"cannot open"}));
}

TEST(LoadScenarioFile, DirectoryIsAnError) {
  const LoadResult result = LoadScenarioFile(::testing::TempDir());

  EXPECT_TRUE(FailsAt(result, 0, 0, {"directory"}));
}

// A named pipe nobody writes to (a FIFO in an unpacked assignment folder)
// used to block the open forever; it now reads as empty. A pipe with a
// writer (`syrof run <(generate)`) still reads. The child fails on SIGALRM
// if the load hangs.
TEST(LoadScenarioFileDeathTest, ANamedPipeWithoutAWriterDoesNotHang) {
  const std::string path = ::testing::TempDir() + "scenario_load_test_fifo_" + std::to_string(getpid());
  ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);

  EXPECT_EXIT(
      {
        alarm(5);
        const LoadResult result = LoadScenarioFile(path);
        _exit(FailsAt(result, 0, 0, {"empty"}) ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
  std::filesystem::remove(path);
}

TEST(LoadScenarioFile, RefusesAFileOverTheCapWithItsSize) {
  const std::string path = WriteTempFile("scenario_load_test_big.yaml", std::string(kMaxScenarioBytes + 10, '#'));

  const LoadResult result = LoadScenarioFile(path);

  EXPECT_TRUE(FailsAt(result, 0, 0, {std::to_string(kMaxScenarioBytes + 10).c_str(), "limit is 1048576 bytes"}));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace syrof::lab::scenario
