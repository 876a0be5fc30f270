// AppsFor: the one setup of a run's apps (app_supply.h), for a built-in app,
// a scenario's library and libraries in its place; its errors name the
// option or the file.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "syrof/app_host/app_supply.h"
#include "syrof/lab/scenario/scenario.h"

namespace syrof::app_host {
namespace {

namespace scenario = lab::scenario;

std::string TestLibrary(const std::string& name) { return std::string(SYROF_TEST_LIBS_DIR) + "/lib" + name + ".so"; }

// Three robots running `app_text` (the value of `app:`), with a listed input.
scenario::Scenario LoadWithApp(const std::string& app_text) {
  const std::string text = "seed: 5\nrobots: {count: 3, placement: grid, spacing_m: 0.6}\ntiming: {duration_s: 2}\n"
                           "inputs: {charge: [0.25, 0.5, 0.75]}\napp: " + app_text + "\n";
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml", {});
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return loaded.ok() ? *loaded.scenario : scenario::Scenario{};
}

TEST(AppsForTest, ABuiltinAppIsMadeInProcessWithNoSourceAndNoSandbox) {
  const scenario::Scenario scenario = LoadWithApp("builtin:circle");

  const AppsResult apps = AppsFor(scenario, AppRequest{});

  ASSERT_TRUE(apps.ok()) << apps.error->ToString();
  ASSERT_TRUE(apps.supply.factory);
  const std::unique_ptr<app::App> app = apps.supply.factory(1);
  ASSERT_NE(app, nullptr);
  EXPECT_EQ(app->name(), "circle");
  EXPECT_EQ(apps.supply.source, "");
  EXPECT_FALSE(apps.supply.sandbox.has_value());
  EXPECT_TRUE(apps.hosts.empty());
}

TEST(AppsForTest, ABudgetForABuiltinAppNamesTheOption) {
  const scenario::Scenario scenario = LoadWithApp("builtin:idle");
  AppRequest request;
  request.wall_cap_ms = 500;

  const AppsResult apps = AppsFor(scenario, request);

  ASSERT_FALSE(apps.ok());
  EXPECT_EQ(apps.error->ToString(), "--wall-cap-ms is for a library app; builtin:idle runs inside the simulator");
}

TEST(AppsForTest, AScenariosLibraryGetsItsParamsEveryRobotsInputsTheLogFolderAndTheRunsLimits) {
  const scenario::Scenario scenario =
      LoadWithApp("{library: " + TestLibrary("cooperative") + ", params: {gain: 2}, cpu_budget_ms: 300}");
  AppRequest request;
  request.log_directory = "/tmp/out/robots";

  const AppsResult apps = AppsFor(scenario, request);

  ASSERT_TRUE(apps.ok()) << apps.error->ToString();
  ASSERT_EQ(apps.hosts.size(), 1u);
  const HostOptions& host = apps.hosts[0];
  EXPECT_EQ(host.library_path, scenario.app.library);
  EXPECT_EQ(host.log_directory, "/tmp/out/robots");
  EXPECT_EQ(host.params, (std::map<std::string, double>{{"gain", 2.0}}));
  ASSERT_EQ(host.inputs.size(), 3u);
  EXPECT_EQ(host.inputs.at(2).at("charge"), 0.75);
  EXPECT_EQ(host.limits.cpu_budget_ms, 300u);
  EXPECT_EQ(host.limits.wall_cap_ms, 2000u);
  EXPECT_EQ(apps.supply.source, scenario.app.library);
  EXPECT_TRUE(apps.supply.sandbox.has_value());
  EXPECT_TRUE(apps.supply.factory);
}

TEST(AppsForTest, TheRequestsBudgetsWinOverTheScenarios) {
  const scenario::Scenario scenario = LoadWithApp("{library: " + TestLibrary("cooperative") + ", cpu_budget_ms: 300}");
  AppRequest request;
  request.cpu_budget_ms = 1000;

  const AppsResult apps = AppsFor(scenario, request);

  ASSERT_TRUE(apps.ok()) << apps.error->ToString();
  EXPECT_EQ(apps.hosts.at(0).limits.cpu_budget_ms, 1000u);
  EXPECT_EQ(apps.hosts.at(0).limits.wall_cap_ms, 4000u);  // HostLimits::ForBudgets
}

// The scenario loader accepts a wall cap alone; below the default CPU budget
// it is refused here, by every runtime alike.
TEST(AppsForTest, AWallCapBelowTheDefaultCpuBudgetIsRefused) {
  const scenario::Scenario scenario = LoadWithApp("{library: " + TestLibrary("cooperative") + ", wall_cap_ms: 50}");

  const AppsResult apps = AppsFor(scenario, AppRequest{});

  ASSERT_FALSE(apps.ok());
  EXPECT_EQ(apps.error->ToString(), "the wall cap (50 ms) must be at least the CPU budget (100 ms)");
}

TEST(AppsForTest, LibrariesInTheScenariosPlaceAreNamedAsShownJoined) {
  const scenario::Scenario scenario = LoadWithApp("builtin:idle");
  AppRequest request;
  request.libraries = {TestLibrary("cooperative"), TestLibrary("parameters")};
  request.shown_libraries = {"a/libcooperative.so", "b/libparameters.so"};

  const AppsResult apps = AppsFor(scenario, request);

  ASSERT_TRUE(apps.ok()) << apps.error->ToString();
  ASSERT_EQ(apps.hosts.size(), 2u);
  EXPECT_EQ(apps.hosts[0].library_path, TestLibrary("cooperative"));
  EXPECT_EQ(apps.hosts[1].library_path, TestLibrary("parameters"));
  EXPECT_EQ(apps.supply.source, "a/libcooperative.so + b/libparameters.so");
}

TEST(AppsForTest, CheckingFirstRefusesALibraryThatDoesNotLoadNamingTheFile) {
  const scenario::Scenario scenario = LoadWithApp("builtin:idle");
  AppRequest request;
  request.libraries = {TestLibrary("cooperative"), TestLibrary("missing_entry")};
  request.check_first = true;

  const AppsResult apps = AppsFor(scenario, request);

  ASSERT_FALSE(apps.ok());
  EXPECT_EQ(apps.error->ToString().rfind(TestLibrary("missing_entry") + ": ", 0), 0u) << apps.error->ToString();
}

TEST(AppsForTest, CheckingFirstPassesALibraryThatLoads) {
  const scenario::Scenario scenario = LoadWithApp("{library: " + TestLibrary("cooperative") + "}");
  AppRequest request;
  request.check_first = true;

  const AppsResult apps = AppsFor(scenario, request);

  EXPECT_TRUE(apps.ok()) << apps.error->ToString();
}

}  // namespace
}  // namespace syrof::app_host
