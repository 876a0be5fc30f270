// The lab and the DDS swarm give the same answers (docs/replay.md,
// "Comparing two runs"): the same scenario and seed start the same epochs,
// in the same modes, with the same members, faults included; and the world's
// rules (the join wait) are the same in both (lab/sim/world_player.h).
// Wall-clock runs of a few seconds each.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "syrof/lab/replay/comparison.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/sim_dds/swarm.h"
#include "test_domain.h"

namespace syrof::sim_dds {
namespace {

std::filesystem::path OutDir(const std::string& what) {
  return std::filesystem::temp_directory_path() / ("syrof_cross_runtime_" + what + "_" + std::to_string(getpid()));
}

// The scenario in the lab; its replay's bytes and its metrics.
struct LabRun {
  std::string replay;
  lab::metrics::Metrics metrics;
};

LabRun RunInTheLab(const std::string& path) {
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(path);
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  std::ostringstream replay;
  lab::sim::SimulationOptions options;
  options.replay = &replay;
  const lab::sim::RunReport report = lab::sim::Run(*loaded.scenario, options);
  return LabRun{replay.str(), report.metrics};
}

SwarmResult RunOverDds(const std::string& path, const std::filesystem::path& out) {
  SwarmOptions options;
  options.scenario_path = path;
  options.robot_binary = SYROF_ROBOT_BINARY;
  options.domain_id = testing::FreshDomainId();
  options.out_dir = out.string();
  std::ostringstream log;
  SwarmResult result = RunSwarm(options, log);
  EXPECT_EQ(result.exit_code, 0) << result.error << "\n" << log.str();
  return result;
}

TEST(CrossRuntimeTest, LabAndDdsStartTheSameEpochsModesAndMembersWithLossAJoinAPauseAndACrash) {
  const std::string scenario = std::string(SYROF_LAB_SCENARIOS_DIR) + "/four_runtimes.yaml";
  const std::filesystem::path out = OutDir("four");
  const LabRun lab = RunInTheLab(scenario);
  const SwarmResult dds = RunOverDds(scenario, out);
  ASSERT_EQ(dds.exit_code, 0);

  std::istringstream lab_replay(lab.replay);
  std::ifstream dds_replay(out / "replay", std::ios::binary);
  const lab::replay::ReplayComparison compared = lab::replay::CompareReplays(lab_replay, dds_replay, {});

  ASSERT_TRUE(compared.comparable()) << (compared.b.error ? compared.b.error->ToString() : "robots differ");
  EXPECT_TRUE(compared.epochs.members_compared);
  // 20 s of 1 s epochs; the DDS run may stop a round or two early.
  EXPECT_GE(compared.epochs.epochs_compared, 15u);
  const auto& first = compared.epochs.first_difference;
  EXPECT_FALSE(first.has_value()) << "first difference at epoch " << first->number;
  // The faults happened: robot 3 joined, robot 2 was removed after its crash.
  EXPECT_EQ(dds.metrics.membership.robots_joined, lab.metrics.membership.robots_joined);
  EXPECT_GE(lab.metrics.membership.robots_joined, 1);
  EXPECT_EQ(dds.metrics.common_knowledge.violations, 0);
  std::filesystem::remove_all(out);
}

// The DDS world waits for a joiner's start disc as the lab does: robot 2
// never starts, one JOIN_WAIT in both.
TEST(CrossRuntimeTest, ADdsJoinerWaitsForAClearStartDiscAsInTheLab) {
  const std::string scenario = std::string(SYROF_SWARM_SCENARIOS_DIR) + "/join_wait.yaml";
  const std::filesystem::path out = OutDir("join_wait");
  const LabRun lab = RunInTheLab(scenario);
  const SwarmResult dds = RunOverDds(scenario, out);
  ASSERT_EQ(dds.exit_code, 0);

  EXPECT_EQ(lab.metrics.safety.join_waits, 1);
  EXPECT_EQ(dds.metrics.safety.join_waits, 1);
  ASSERT_EQ(dds.robot_exits.size(), 3u);
  EXPECT_FALSE(dds.robot_exits[2].has_value());  // its process was never started
  EXPECT_EQ(dds.metrics.common_knowledge.starts_by_robot.at(2), 0);
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace syrof::sim_dds
