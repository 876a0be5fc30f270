// The DDS swarm end to end: robot processes, the world, real faults and a
// clean stop (sim_dds/dds_world.h). Wall-clock runs of a few seconds each; the
// bounds are generous for a loaded 2-core CI machine.
#include "syrof/sim_dds/dds_world.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <span>
#include <sstream>
#include <vector>
#include <thread>
#include <tuple>

#include "swarm_test_support.h"
#include "test_domain.h"

namespace syrof::sim_dds {
namespace {

using testing::ExpectNoRobotLeft;
using testing::OptionsFor;

TEST(SwarmTest, EightRobotProcessesForTenSecondsWithLossKeepP3AndAgreeOnMembership) {
  const SwarmOptions options = OptionsFor("swarm8_loss.yaml");
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  ASSERT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  const nlohmann::json m = nlohmann::json::parse(result.metrics_json);

  EXPECT_EQ(m["runtime"], "dds");
  EXPECT_EQ(m["common_knowledge"]["violations"], 0);  // P3, checked as the lab checks it
  EXPECT_GE(m["epochs_started"].get<int>(), 3);       // 10 s of 1 s epochs, minus start-up
  EXPECT_GT(m["common_knowledge"]["cooperative_starts"].get<int>(), 0);
  EXPECT_EQ(m["membership"]["removals"], 0);          // nobody crashed: nobody removed
  EXPECT_EQ(m["dds"]["reports_rejected"], 0);
  EXPECT_GT(result.delivery_ratio, 0.8);              // loopback delivers nearly all
  EXPECT_LE(result.delivery_ratio, 1.0);              // in-round deliveries over beacons sent: a fraction
  EXPECT_EQ(m["dds"]["delivery_ratio"], result.delivery_ratio);
  // The loss the synchronizer sees is the scenario's 5 %: most epochs start
  // COOPERATIVE, as in the lab (a robot that woke late once stepped beacons
  // of the next round early and broke that).
  EXPECT_GE(m["common_knowledge"]["cooperative_fraction"].get<double>(), 0.6);
  // The apps' states are reported and compared as in the lab.
  EXPECT_GT(m["agreement"]["agreed_epochs"].get<int>(), 0);
  EXPECT_EQ(m["agreement"]["agreed_epochs"], m["agreement"]["cooperative_epochs"]);
  EXPECT_GT(result.skew.samples, 100);
  ASSERT_EQ(result.robot_exits.size(), 8u);
  for (size_t id = 0; id < 8; ++id) {
    ASSERT_TRUE(result.robot_exits[id].has_value()) << "robot " << id;
    EXPECT_EQ(*result.robot_exits[id], 0) << "robot " << id << " did not stop cleanly";
    EXPECT_GT(result.cpu_seconds[id], 0.0);
  }
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(options.out_dir) / "metrics.json"));
  EXPECT_GT(std::filesystem::file_size(std::filesystem::path(options.out_dir) / "replay"), 0u);
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

// Robots that align their rounds from the beacons they hear (the way for
// hosts without synchronised clocks) keep the protocol's figures: P3 0,
// nobody removed, and epochs COOPERATIVE as without alignment. A beacon
// from a sender a little earlier than the receiver used to be stepped a
// round early, and the sender looked silent the round after.
//
// Half of them read the start as hosts whose clocks disagree would, up to
// most of a round off (41 ms of 50): they line up on robot 0's phase, and
// those off by more than half a round take the swarm's round count from its
// samples. Without alignment that swarm falls apart (P3 held, but 4 % of
// the epochs COOPERATIVE and in-round delivery 55 %, in one run).
TEST(SwarmTest, EightRobotProcessesAligningTheirRoundsFromBeaconsKeepP3AndCooperativeEpochs) {
  SwarmOptions options = OptionsFor("swarm8_loss.yaml");
  options.align_rounds = true;
  options.robot_clock_offsets_us = {0, 37'000, 0, -13'000, 0, 21'000, 0, -41'000};
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  ASSERT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  const nlohmann::json m = nlohmann::json::parse(result.metrics_json);

  EXPECT_EQ(m["common_knowledge"]["violations"], 0);
  EXPECT_GE(m["epochs_started"].get<int>(), 3);
  EXPECT_EQ(m["membership"]["removals"], 0);
  EXPECT_GE(m["common_knowledge"]["cooperative_fraction"].get<double>(), 0.8) << log.str();
  EXPECT_EQ(m["agreement"]["agreed_epochs"], m["agreement"]["cooperative_epochs"]);
  // The group's boundaries drift off the world's start grid (the transport's
  // latency is not the expected one); robots number their own rounds and the
  // world follows them, so in-round delivery is judged on the robots' rounds
  // (it fell to 50-74 % on the world's grid).
  EXPECT_GT(result.delivery_ratio, 0.8);
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

// A RoundSink counting what the world told it (the live page is one).
struct CountingSink : lab::replay::RoundSink {
  void OnHeader(const lab::replay::Header& header) override { robots = header.robots.size(); ++headers; }
  void OnRound(uint32_t index, int64_t, std::span<const lab::replay::RobotFrame> frames,
               std::span<const lab::replay::Event>, std::span<const lab::replay::RobotMap>) override {
    indices.push_back(index);
    frames_per_round.push_back(frames.size());
  }
  void OnFinish(bool complete) override { finishes.push_back(complete); }
  size_t robots = 0;
  int headers = 0;
  std::vector<uint32_t> indices;
  std::vector<size_t> frames_per_round;
  std::vector<bool> finishes;
};

// `syrof swarm --live` passes its server as a sink: it hears every round
// the replay gets, and the end.
TEST(SwarmTest, ASinkHearsEveryRoundAndTheEnd) {
  SwarmOptions options = OptionsFor("swarm8_loss.yaml");
  options.overrides.duration_s = 3;
  CountingSink sink;
  options.sinks = {&sink};
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  ASSERT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  EXPECT_EQ(sink.headers, 1);
  EXPECT_EQ(sink.robots, 8u);
  EXPECT_GE(sink.indices.size(), 50u);  // 3 s of 50 ms rounds, less the start
  for (size_t i = 1; i < sink.indices.size(); ++i) EXPECT_GT(sink.indices[i], sink.indices[i - 1]);
  for (const size_t frames : sink.frames_per_round) EXPECT_EQ(frames, 8u);
  EXPECT_EQ(sink.finishes, std::vector<bool>{true});
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

TEST(SwarmTest, AStudentLibraryRunsInEveryRobotProcessThroughTheAppHost) {
  SwarmOptions options = OptionsFor("swarm_library.yaml");
  options.overrides.app = SYROF_STARTER_LIBRARY;
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  ASSERT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  const nlohmann::json m = nlohmann::json::parse(result.metrics_json);

  EXPECT_EQ(m["app"]["source"], SYROF_STARTER_LIBRARY);
  EXPECT_TRUE(m["app"]["faults"].empty()) << m["app"]["faults"].dump();
  EXPECT_EQ(m["common_knowledge"]["violations"], 0);
  EXPECT_GE(m["epochs_started"].get<int>(), 2);
  EXPECT_GT(m["agreement"]["agreed_epochs"].get<int>(), 0);
  EXPECT_EQ(m["agreement"]["agreed_epochs"], m["agreement"]["cooperative_epochs"]);
  // Each robot's app host wrote its log where `syrof run` writes it.
  for (int id = 0; id < 4; ++id) {
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(options.out_dir) / "robots" / (std::to_string(id) + ".log")))
        << "robot " << id;
  }
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

// On the world's start grid, and with robots aligning from beacons: a late
// joiner's count then comes from the swarm's samples, not the start grid.
class FaultSwarmTest : public ::testing::TestWithParam<bool> {};

TEST_P(FaultSwarmTest, CrashPauseAndJoinAreRealSignalsAndTheSwarmKeepsP3) {
  SwarmOptions options = OptionsFor("swarm_faults.yaml");
  options.align_rounds = GetParam();
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  ASSERT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  const nlohmann::json m = nlohmann::json::parse(result.metrics_json);

  EXPECT_EQ(m["common_knowledge"]["violations"], 0);
  // The crashed robot died of SIGKILL; the paused one was resumed and, like
  // the late joiner, stopped cleanly at the end.
  ASSERT_EQ(result.robot_exits.size(), 6u);
  ASSERT_TRUE(result.robot_exits[1].has_value());
  EXPECT_EQ(*result.robot_exits[1], -SIGKILL);
  ASSERT_TRUE(result.robot_exits[2].has_value());
  EXPECT_EQ(*result.robot_exits[2], 0);
  ASSERT_TRUE(result.robot_exits[5].has_value());
  EXPECT_EQ(*result.robot_exits[5], 0);
  // The others removed the crashed robot and the paused one, and admitted
  // the joiner (and the paused robot back).
  // A failure says what the world saw (membership, synchrony) and the log.
  const std::string seen = m["membership"].dump() + "\n" + m["synchrony"].dump() + "\n" + log.str();
  EXPECT_GE(m["membership"]["robots_removed"].get<int>(), 2) << seen;
  EXPECT_GE(m["membership"]["robots_joined"].get<int>(), 1) << seen;
  EXPECT_GT(result.delivery_ratio, 0.8) << seen;
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

INSTANTIATE_TEST_SUITE_P(Rounds, FaultSwarmTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& param) {
                           return param.param ? std::string("AligningFromBeacons") : std::string("OnTheWorldsGrid");
                         });

// Seeded stress (stress.h): crash, pause, a late join and 10 % loss, with
// robots and the world stopped by SIGSTOP bursts of 10-200 ms. P3 holds;
// a failure names the seed that reruns it (`syrof swarm
// tests/sim_dds/scenarios/swarm_stress.yaml --stress SEED`). The long runs
// are bench_sim_dds_stress's (docs/dds.md, "Stress"). Both round modes:
// the aligned runs that broke P3 on loaded machines were runs that shared
// their domain with another run at the time (issue 46; beacons now carry
// the run id, SwarmTest.TwoRunsOnOneDomainAtOnceEachKeepP3).
class StressedSwarmTest : public ::testing::TestWithParam<std::tuple<bool, uint64_t>> {};

TEST_P(StressedSwarmTest, P3HoldsUnderSigstopBursts) {
  SwarmOptions options = OptionsFor("swarm_stress.yaml");
  options.realtime = false;  // stalls at normal priority, as a student's machine runs it
  options.align_rounds = std::get<0>(GetParam());
  options.stress.seed = std::get<1>(GetParam());
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  ASSERT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  const nlohmann::json m = nlohmann::json::parse(result.metrics_json);
  EXPECT_EQ(result.stress_seed, options.stress.seed);
  EXPECT_GT(result.stalls, 0);
  EXPECT_EQ(m["common_knowledge"]["violations"], 0)
      << "stress seed " << options.stress.seed << (options.align_rounds ? " --align-rounds" : "") << ": "
      << m["common_knowledge"]["first_violations"].dump() << "\n" << log.str();
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

INSTANTIATE_TEST_SUITE_P(Seeds, StressedSwarmTest,
                         ::testing::Combine(::testing::Values(false, true), ::testing::Values(uint64_t{1}, uint64_t{2})),
                         [](const ::testing::TestParamInfo<std::tuple<bool, uint64_t>>& param) {
                           return std::string(std::get<0>(param.param) ? "Aligning" : "OnTheGrid") + "Seed" +
                                  std::to_string(std::get<1>(param.param));
                         });

TEST(SwarmTest, AStopRequestEndsTheRunEarlyWithEveryRobotStopped) {
  SwarmOptions options = OptionsFor("swarm8_loss.yaml");
  std::atomic<bool> stop{false};
  options.stop = &stop;
  options.replay = false;
  std::thread stopper([&stop] {
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    stop.store(true);  // what the SIGINT handler of `syrof swarm` does
  });
  std::ostringstream log;
  const auto before = std::chrono::steady_clock::now();
  const SwarmResult result = RunSwarm(options, log);
  stopper.join();
  EXPECT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{});
  EXPECT_TRUE(result.stopped_early);
  EXPECT_LT(std::chrono::steady_clock::now() - before, std::chrono::seconds(9));  // not the full 10 s
  EXPECT_FALSE(result.robot_pids.empty());
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

// A robot binary that passes the "executable" check but cannot be executed
// (its interpreter is missing) is named with the kernel's reason, before
// discovery (it read as a robot that exited before it attached).
TEST(SwarmTest, ARobotBinaryThatCannotBeExecutedIsNamedWithTheReason) {
  SwarmOptions options = OptionsFor("swarm8_loss.yaml");
  std::filesystem::create_directories(options.out_dir);
  options.robot_binary = options.out_dir + "/robot-without-interpreter";
  std::ofstream(options.robot_binary) << "#!/nonexistent/interpreter\n";
  ASSERT_EQ(chmod(options.robot_binary.c_str(), 0755), 0);
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.error.value_or(lab::Error{}).ToString(), "robot 0: cannot start " + options.robot_binary + ": No such file or directory");
  EXPECT_TRUE(result.robot_pids.empty());
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

// A robot whose network namespace cannot be opened is named with the path
// and the reason (it was "fork failed for robot 2"), and the robots already
// started are ended and reaped.
TEST(SwarmTest, ARobotNetworkNamespaceThatCannotBeOpenedIsNamedAndNoRobotIsLeft) {
  SwarmOptions options = OptionsFor("swarm8_loss.yaml");
  options.robot_networks.resize(3);
  options.robot_networks[2].netns_path = "/nonexistent/netns";
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.error.value_or(lab::Error{}).ToString(), "robot 2: cannot open its network namespace /nonexistent/netns: No such file or directory");
  EXPECT_EQ(result.robot_pids.size(), 2u);  // robots 0 and 1
  ExpectNoRobotLeft(result);
  std::filesystem::remove_all(options.out_dir);
}

}  // namespace
}  // namespace syrof::sim_dds
