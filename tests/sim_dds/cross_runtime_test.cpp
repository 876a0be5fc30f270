// The lab and the DDS swarm give the same answers (docs/replay.md,
// "Comparing two runs"): the same scenario and seed start the same epochs,
// in the same modes, with the same members, faults included; and the world's
// rules (the join wait) are the same in both (lab/sim/world_player.h).
// Wall-clock runs of a few seconds each.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "syrof/lab/replay/comparison.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/sim_dds/dds_world.h"
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
  // The robots, their network threads and the world's loop at SCHED_FIFO
  // (as root; otherwise said and ignored): without it a build beside the
  // test (load 5 to 8) held beacons and faults past their round, and the
  // ASYNC comparison failed 2 of 3 times; with it, 5 of 5 passed at load 4
  // to 6 and 3 of 4 under four busy loops (load 7 to 8). CI runs it alone.
  options.realtime = true;
  std::ostringstream log;
  SwarmResult result = RunSwarm(options, log);
  EXPECT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  return result;
}

// A swarm run against the lab's replay: "" when they agree, else what differs.
std::string DdsAgainstLab(const std::string& scenario, const std::string& lab_replay, const std::filesystem::path& out,
                          const LabRun& lab) {
  const SwarmResult dds = RunOverDds(scenario, out);
  if (dds.exit_code != 0) return "the swarm failed: " + dds.error.value_or(lab::Error{}).ToString();
  std::istringstream lab_stream(lab_replay);
  std::ifstream dds_stream(out / "replay", std::ios::binary);
  const lab::replay::ReplayComparison compared = lab::replay::CompareReplays(lab_stream, dds_stream, {});
  if (!compared.comparable()) return compared.b.error ? compared.b.error->ToString() : "the robots differ";
  EXPECT_TRUE(compared.epochs.members_compared);
  // The faults happened: robot 3 joined, nobody broke P3.
  EXPECT_EQ(dds.metrics.membership.robots_joined, lab.metrics.membership.robots_joined);
  EXPECT_EQ(dds.metrics.common_knowledge.violations, 0);
  // Under SSYNC the robots' own reports show who ran newRound: as many
  // calls as in the lab, less at most the DDS run's last epoch (4 robots).
  if (lab.metrics.activation) {
    if (!dds.metrics.activation) return "the swarm's metrics have no activation";
    if (!lab.metrics.agreement || !dds.metrics.agreement) return "a run has no agreement metrics";
    const int64_t lab_calls = lab.metrics.agreement->new_round_calls;
    const int64_t dds_calls = dds.metrics.agreement->new_round_calls;
    if (dds_calls > lab_calls || dds_calls < lab_calls - 4) {
      return "newRound calls: " + std::to_string(dds_calls) + " over DDS, " + std::to_string(lab_calls) + " in the lab";
    }
  }
  if (const auto& first = compared.epochs.first_difference) {
    return "first difference at epoch " + std::to_string(first->number) + " (in-round delivery " +
           std::to_string(dds.delivery_ratio) + ", round-start skew max " + std::to_string(dds.skew.max_us) + " us)";
  }
  // 20 s of 1 s epochs; the DDS run may stop a round or two early.
  if (compared.epochs.epochs_compared < 15) return std::to_string(compared.epochs.epochs_compared) + " epochs compared";
  return "";
}

// Real processes on a real clock: a machine loaded past its cores can hold a
// robot past a round boundary, so a run that disagrees gets one more try
// (ctest runs this test alone: RUN_SERIAL). Two disagreeing runs fail.
TEST(CrossRuntimeTest, LabAndDdsStartTheSameEpochsModesAndMembersWithLossAJoinAPauseAndACrash) {
  const std::string scenario = std::string(SYROF_LAB_SCENARIOS_DIR) + "/four_runtimes.yaml";
  const std::filesystem::path out = OutDir("four");
  const LabRun lab = RunInTheLab(scenario);
  ASSERT_GE(lab.metrics.membership.robots_joined, 1);

  const std::string first = DdsAgainstLab(scenario, lab.replay, out, lab);
  if (!first.empty()) {
    std::cerr << "the first swarm run disagreed with the lab: " << first << "; trying once more\n";
    EXPECT_EQ(DdsAgainstLab(scenario, lab.replay, out, lab), "") << "(the first run: " << first << ")";
  }
  std::filesystem::remove_all(out);
}

// Drones over DDS: the world process moves them (tilt lag, seeded drift)
// and builds their sensors at flight height as the lab does, and their
// robots brake and hold as in the lab, so the epochs, modes and members
// agree as for the other kinds.
TEST(CrossRuntimeTest, LabAndDdsAgreeWithDronesAmongTheKinds) {
  const std::string scenario = std::string(SYROF_SWARM_SCENARIOS_DIR) + "/drone_runtimes.yaml";
  const std::filesystem::path out = OutDir("drones");
  const LabRun lab = RunInTheLab(scenario);
  ASSERT_GE(lab.metrics.membership.robots_joined, 1);
  EXPECT_EQ(lab.metrics.collisions.count, 0);

  const std::string first = DdsAgainstLab(scenario, lab.replay, out, lab);
  if (!first.empty()) {
    std::cerr << "the first swarm run disagreed with the lab: " << first << "; trying once more\n";
    EXPECT_EQ(DdsAgainstLab(scenario, lab.replay, out, lab), "") << "(the first run: " << first << ")";
  }
  std::filesystem::remove_all(out);
}

// Under SSYNC the decision "who is active" is each robot's own
// (sync::IsActive on its epoch's map), so both runtimes activate the same
// robots: the same epochs, modes and members, and an active robot-epoch count
// that differs by at most the DDS run's last, unfinished epoch.
TEST(CrossRuntimeTest, LabAndDdsAgreeUnderSsync) {
  const std::string scenario = std::string(SYROF_SWARM_SCENARIOS_DIR) + "/ssync_runtimes.yaml";
  const std::filesystem::path out = OutDir("ssync");
  const LabRun lab = RunInTheLab(scenario);
  ASSERT_TRUE(lab.metrics.activation.has_value());
  ASSERT_GT(lab.metrics.activation->inactive_starts, 0);

  std::string differs = DdsAgainstLab(scenario, lab.replay, out, lab);
  if (!differs.empty()) {
    std::cerr << "the first swarm run disagreed with the lab: " << differs << "; trying once more\n";
    differs = DdsAgainstLab(scenario, lab.replay, out, lab);
  }
  EXPECT_EQ(differs, "");
  // SSYNC left robots out: fewer newRound calls than COOPERATIVE starts.
  ASSERT_TRUE(lab.metrics.agreement.has_value());
  EXPECT_LT(lab.metrics.agreement->new_round_calls,
            lab.metrics.activation->active_starts + lab.metrics.activation->inactive_starts);
  std::filesystem::remove_all(out);
}

// Under ASYNC each robot follows its own cycles (sync::AsyncTracker) from
// its epoch starts, so both runtimes start the same epochs, modes and
// members, and look (call newRound) as often, less the DDS run's last epoch.
TEST(CrossRuntimeTest, LabAndDdsAgreeUnderAsync) {
  const std::string scenario = std::string(SYROF_SWARM_SCENARIOS_DIR) + "/async_runtimes.yaml";
  const std::filesystem::path out = OutDir("async");
  const LabRun lab = RunInTheLab(scenario);
  ASSERT_TRUE(lab.metrics.activation.has_value());
  ASSERT_TRUE(lab.metrics.activation->async.has_value());
  ASSERT_GT(lab.metrics.activation->async->stale_move_epochs, 0);

  std::string differs = DdsAgainstLab(scenario, lab.replay, out, lab);
  if (!differs.empty()) {
    std::cerr << "the first swarm run disagreed with the lab: " << differs << "; trying once more\n";
    differs = DdsAgainstLab(scenario, lab.replay, out, lab);
  }
  EXPECT_EQ(differs, "");
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
