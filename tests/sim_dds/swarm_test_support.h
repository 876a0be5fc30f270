// What the swarm tests share: options for a scenario of tests/sim_dds/scenarios
// on a fresh domain with an output folder of the test's own, and the check
// that a run left no robot process behind.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>

#include "syrof/sim_dds/dds_world.h"
#include "test_domain.h"

namespace syrof::sim_dds::testing {

inline SwarmOptions OptionsFor(const std::string& scenario) {
  SwarmOptions options;
  options.scenario_path = std::string(SYROF_SWARM_SCENARIOS_DIR) + "/" + scenario;
  options.robot_binary = SYROF_ROBOT_BINARY;
  options.domain_id = FreshDomainId();
  // As docs/dds.md says to run a swarm on a loaded machine (as root; else
  // each robot says so and runs at normal priority): two 8-robot swarms of
  // ctest -j2 beside a build (load 14) otherwise lost robots to the failure
  // detector (11 removals where none crashed). P3 under stalls and late
  // samples is the stress tests' subject, at whatever priority.
  options.realtime = true;
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  options.out_dir = (std::filesystem::temp_directory_path() /
                     ("syrof_swarm_test_" + std::string(test->name()) + "_" + std::to_string(getpid())))
                        .string();
  return options;
}

// Every robot process the run started is gone (reaped: kill finds nothing).
inline void ExpectNoRobotLeft(const SwarmResult& result) {
  for (const int pid : result.robot_pids) {
    EXPECT_EQ(kill(pid, 0), -1) << "robot process " << pid << " is still there";
    EXPECT_EQ(errno, ESRCH);
  }
}

}  // namespace syrof::sim_dds::testing
