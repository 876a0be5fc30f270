// Two DDS swarms that land on one domain at once (sim_dds/dds_world.h):
// each keeps to its own robots. Two runs of 6 robot processes each on a
// machine of 2 cores: a test of its own that ctest runs alone (RUN_SERIAL),
// since a third test beside it starved robots of a run until it started no
// COOPERATIVE epoch at all (a fresh-clone CI run, 2026-12-06: robots 3-5 of
// one run never started an epoch; P3 held).
#include <gtest/gtest.h>
#include <signal.h>

#include <cerrno>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <utility>

#include "syrof/sim_dds/dds_world.h"
#include "swarm_test_support.h"
#include "test_domain.h"

namespace syrof::sim_dds {
namespace {

using testing::ExpectNoRobotLeft;
using testing::OptionsFor;

// Two runs that land on one domain at once: concurrent runs draw their
// domain from 231 (docs/dds.md, "Domain ids"), so on a machine running many
// (ctest -j, benches, several sessions) some pairs share one. Each swarm
// must still be a swarm of its own: before beacons carried the run id, the
// robots of each run heard the other's robots as their own (same ids, other
// epochs, views and snapshots) and both runs broke P3 on nearly every try,
// aligning from beacons or on the world's grid (issue 46).
TEST(SwarmTest, TwoRunsOnOneDomainAtOnceEachKeepP3) {
  SwarmOptions first = OptionsFor("swarm_stress.yaml");
  SwarmOptions second = first;
  first.align_rounds = true;
  second.align_rounds = true;
  second.out_dir += "_second";
  second.replay = false;
  first.replay = false;
  std::ostringstream first_log, second_log;
  SwarmResult second_result;
  std::thread beside([&] { second_result = RunSwarm(second, second_log); });
  SwarmResult first_result = RunSwarm(first, first_log);
  beside.join();
  for (const auto& [result, log] : {std::pair{&first_result, &first_log}, std::pair{&second_result, &second_log}}) {
    ASSERT_EQ(result->exit_code, 0) << result->error.value_or(lab::Error{}) << "\n" << log->str();
    const nlohmann::json m = nlohmann::json::parse(result->metrics_json);
    // A failure says what the world saw and the log.
    const std::string seen = m["common_knowledge"].dump() + "\n" + m["membership"].dump() + "\n" +
                             m["synchrony"].dump() + "\n" + m["dds"].dump() + "\n" + log->str();
    // They did share the domain: each world saw the other's robots' reports.
    EXPECT_GT(m["dds"]["reports_other_runs"].get<int>(), 0) << seen;
    // And each other's drive commands, which neither world applied; each
    // robot took only its own world's readings (sensor topics are keyed by
    // the run, TwoRunsOnOneDomainNeverPushOutEachOthersSamples).
    EXPECT_GT(m["dds"]["drives_other_runs"].get<int>(), 0) << seen;
    EXPECT_EQ(m["common_knowledge"]["violations"], 0) << seen;
    EXPECT_GT(m["common_knowledge"]["cooperative_starts"].get<int>(), 0) << seen;
    ExpectNoRobotLeft(*result);
  }
  std::filesystem::remove_all(first.out_dir);
  std::filesystem::remove_all(second.out_dir);
}

}  // namespace
}  // namespace syrof::sim_dds
