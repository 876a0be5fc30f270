#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "syrof/app_host/app_supply.h"
#include "syrof/sim_dds/robot_process.h"

namespace syrof::sim_dds {
namespace {

namespace fs = std::filesystem;

// A scenario with a library app and the given budget lines, loaded from a
// fresh folder (the library must exist: the loader checks it).
lab::scenario::Scenario LoadLibraryScenario(const std::string& budgets) {
  const fs::path dir = fs::temp_directory_path() / ("syrof_robot_host_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "libmy.so") << "";
  std::ofstream(dir / "scenario.yaml") << "robots: { count: 2 }\napp: { library: libmy.so" << budgets << " }\n";
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile((dir / "scenario.yaml").string());
  fs::remove_all(dir);
  EXPECT_TRUE(loaded.ok()) << loaded.error->ToString();
  return loaded.ok() ? *loaded.scenario : lab::scenario::Scenario{};
}

// `syrof run` (and `syrof grade`) give a library app
// HostLimits::ForBudgets(cpu_budget_ms, wall_cap_ms): a DDS robot of the
// same scenario gets the very same limits.
TEST(RobotHostOptionsTest, ARobotGetsTheLimitsSyrofRunGivesTheSameScenario) {
  for (const std::string budgets : {"", ", cpu_budget_ms: 1000", ", cpu_budget_ms: 50", ", wall_cap_ms: 700",
                                    ", cpu_budget_ms: 300, wall_cap_ms: 900"}) {
    const lab::scenario::Scenario scenario = LoadLibraryScenario(budgets);
    RobotProcessOptions options;
    options.robot = 1;
    const app_host::HostLimits robot = RobotApps(scenario, options).hosts.at(0).limits;
    const app_host::HostLimits run = app_host::HostLimits::ForBudgets(scenario.app.cpu_budget_ms, scenario.app.wall_cap_ms);
    EXPECT_EQ(robot.cpu_budget_ms, run.cpu_budget_ms) << budgets;
    EXPECT_EQ(robot.wall_cap_ms, run.wall_cap_ms) << budgets;
    EXPECT_EQ(robot.load_wall_cap_ms, run.load_wall_cap_ms) << budgets;
    EXPECT_EQ(robot.address_space_bytes, run.address_space_bytes) << budgets;
  }
}

TEST(RobotHostOptionsTest, AOneSecondBudgetGetsAFourSecondWallCap) {
  const lab::scenario::Scenario scenario = LoadLibraryScenario(", cpu_budget_ms: 1000");
  RobotProcessOptions options;
  options.robot = 0;
  options.log_directory = "/tmp/out/robots";
  const app_host::HostOptions host = RobotApps(scenario, options).hosts.at(0);
  EXPECT_EQ(host.limits.cpu_budget_ms, 1000u);
  EXPECT_EQ(host.limits.wall_cap_ms, 4000u);
  EXPECT_EQ(host.library_path, scenario.app.library);
  EXPECT_EQ(host.log_directory, "/tmp/out/robots");
}

// A wall cap below the default CPU budget stops the robot process as it
// stops `syrof run` (it used to host the app with the wall cap under the budget).
TEST(RobotHostOptionsTest, AWallCapBelowTheDefaultCpuBudgetIsRefusedAsSyrofRunRefusesIt) {
  const lab::scenario::Scenario scenario = LoadLibraryScenario(", wall_cap_ms: 50");
  RobotProcessOptions options;
  options.robot = 0;

  const app_host::AppsResult apps = RobotApps(scenario, options);

  ASSERT_FALSE(apps.ok());
  EXPECT_EQ(apps.error->ToString(), "the wall cap (50 ms) must be at least the CPU budget (100 ms)");
}

}  // namespace
}  // namespace syrof::sim_dds
