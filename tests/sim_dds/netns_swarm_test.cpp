// Across hosts, on one machine: two network namespaces joined by a veth
// pair, the world and the even robots in one, the odd robots in the other,
// forming one swarm (docs/dds.md, "Running a swarm on several machines").
// Needs root (CI runs as root); skipped otherwise. Its own test binary: the
// test moves its thread into a namespace before any DDS thread exists.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/dds_world.h"

namespace syrof::sim_dds {
namespace {

bool Run(const std::string& command) { return std::system((command + " >/dev/null 2>&1").c_str()) == 0; }

// Two namespaces and a veth pair, removed again on destruction.
class VethPair {
 public:
  VethPair() {
    const std::string tag = std::to_string(getpid() % 100000);
    a_ = "syrof_a" + tag;
    b_ = "syrof_b" + tag;
    veth_a_ = "sya" + tag;
    veth_b_ = "syb" + tag;
    ok_ = Run("ip netns add " + a_) && Run("ip netns add " + b_) &&
          Run("ip link add " + veth_a_ + " type veth peer name " + veth_b_) &&
          Run("ip link set " + veth_a_ + " netns " + a_) && Run("ip link set " + veth_b_ + " netns " + b_) &&
          Run("ip -n " + a_ + " addr add 10.213.0.1/24 dev " + veth_a_) &&
          Run("ip -n " + b_ + " addr add 10.213.0.2/24 dev " + veth_b_) &&
          Run("ip -n " + a_ + " link set " + veth_a_ + " up") && Run("ip -n " + b_ + " link set " + veth_b_ + " up") &&
          Run("ip -n " + a_ + " link set lo up") && Run("ip -n " + b_ + " link set lo up");
  }
  ~VethPair() {
    Run("ip netns del " + a_);  // deleting a namespace deletes its end of the pair, and so the pair
    Run("ip netns del " + b_);
  }
  bool ok() const { return ok_; }
  std::string path_a() const { return "/var/run/netns/" + a_; }
  std::string path_b() const { return "/var/run/netns/" + b_; }
  const std::string& veth_a() const { return veth_a_; }
  const std::string& veth_b() const { return veth_b_; }

 private:
  std::string a_, b_, veth_a_, veth_b_;
  bool ok_ = false;
};

TEST(NetnsSwarmTest, RobotsInTwoNetworkNamespacesJoinedByVethFormOneSwarm) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root for network namespaces";
  VethPair pair;
  if (!pair.ok()) GTEST_SKIP() << "could not make network namespaces and a veth pair (ip netns)";
  const int home = open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
  const int a = open(pair.path_a().c_str(), O_RDONLY | O_CLOEXEC);
  ASSERT_GE(home, 0);
  ASSERT_GE(a, 0);
  ASSERT_EQ(setns(a, CLONE_NEWNET), 0);  // this thread (the world, its DDS threads) into A
  close(a);

  SwarmOptions options;
  options.scenario_path = std::string(SYROF_SWARM_SCENARIOS_DIR) + "/swarm_netns.yaml";
  options.robot_binary = SYROF_ROBOT_BINARY;
  options.interface = pair.veth_a();
  options.domain_id = DomainIdForRun(static_cast<uint64_t>(getpid()) * 7919);
  options.out_dir = (std::filesystem::temp_directory_path() / ("syrof_netns_swarm_" + std::to_string(getpid()))).string();
  options.replay = false;
  // As docs/dds.md says to run a swarm on a loaded machine, and as every
  // other swarm test runs (swarm_test_support.h's OptionsFor): at normal
  // priority, ctest -j2 of the DDS and firmware tests beside a -j2 build
  // (load 7) once lost robots to the failure detector here (8 removals
  // where none crashed, 1 of 14 rounds).
  options.realtime = true;
  // As on two hosts whose clocks are kept in sync: the start is read on
  // CLOCK_REALTIME.
  options.realtime_start = true;
  for (uint16_t id = 0; id < 6; ++id) {
    options.robot_networks.push_back(id % 2 == 0 ? SwarmOptions::RobotNetwork{pair.path_a(), pair.veth_a()}
                                                 : SwarmOptions::RobotNetwork{pair.path_b(), pair.veth_b()});
  }
  std::ostringstream log;
  const SwarmResult result = RunSwarm(options, log);
  ASSERT_EQ(setns(home, CLONE_NEWNET), 0);
  close(home);

  ASSERT_EQ(result.exit_code, 0) << result.error.value_or(lab::Error{}) << "\n" << log.str();
  const nlohmann::json m = nlohmann::json::parse(result.metrics_json);
  EXPECT_EQ(m["common_knowledge"]["violations"], 0);
  EXPECT_GE(m["epochs_started"].get<int>(), 2);
  EXPECT_GT(m["common_knowledge"]["cooperative_starts"].get<int>(), 0);
  EXPECT_EQ(m["membership"]["removals"], 0);
  EXPECT_EQ(m["dds"]["reports_late"], 0);
  // Beacons cross the pair: were the halves apart, each robot would hear
  // two of five others (ratio about 0.4).
  EXPECT_GT(result.delivery_ratio, 0.8);
  for (size_t id = 0; id < result.robot_exits.size(); ++id) {
    ASSERT_TRUE(result.robot_exits[id].has_value());
    EXPECT_EQ(*result.robot_exits[id], 0) << "robot " << id;
  }
  std::filesystem::remove_all(options.out_dir);
}

}  // namespace
}  // namespace syrof::sim_dds
