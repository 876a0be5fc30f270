// HostedApp in the lab: a library run through the app host behaves as the
// same C source linked in (same replay and metrics bytes), a run is
// byte-identical on rerun, and a robot whose library faults stops like a
// crashed robot while the others go on.
#include <dirent.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>
#include <map>
#include <utility>
#include <vector>
#include <memory>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "syrof/app/c_abi_app.h"
#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/simulation.h"

extern "C" const syrof_app_descriptor* cooperative_app_entry(void);
extern "C" const syrof_app_descriptor* parameters_app_entry(void);
extern "C" double parameters_app_target_x_m(void);
extern "C" uint8_t parameters_app_checks(void);
extern "C" const syrof_app_descriptor* inputs_app_entry(void);
extern "C" const syrof_app_descriptor* kinds_app_entry(void);

namespace syrof::app_host {
namespace {

using nlohmann::json;
namespace sim = lab::sim;
namespace scenario = lab::scenario;

std::string HostedLibrary(const std::string& name) { return std::string(SYROF_TEST_LIBS_DIR) + "/lib" + name + ".so"; }

scenario::Scenario Load(int robots, double duration_s) {
  const std::string text = "seed: 5\nrobots: {count: " + std::to_string(robots) +
                           ", placement: grid, spacing_m: 0.6}\ntiming: {duration_s: " + std::to_string(duration_s) +
                           "}\nchannel: {model: iid, loss: 0.1}\napp: builtin:idle\n";
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml", {});
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

struct Outcome {
  std::string metrics;
  std::string replay;
};

Outcome RunWith(const scenario::Scenario& scenario, std::function<std::unique_ptr<app::App>(uint16_t)> factory) {
  std::ostringstream replay;
  sim::SimulationOptions options;
  options.replay = &replay;
  options.apps.factory = std::move(factory);
  options.apps.source = "test:cooperative";
  const sim::RunReport report = sim::Run(scenario, options, 0.0);
  return Outcome{report.metrics_json, replay.str()};
}

// Removes a test's log folder when the test ends.
class ScopedFolder {
 public:
  explicit ScopedFolder(std::string path) : path_(std::move(path)) {}
  ~ScopedFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScopedFolder(const ScopedFolder&) = delete;
  ScopedFolder& operator=(const ScopedFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

HostOptions Options(const std::string& library, const std::string& logs) {
  HostOptions options;
  options.library_path = HostedLibrary(library);
  options.log_directory = logs;
  return options;
}

TEST(HostedAppSimulationTest, ALibraryRunsAsTheSameCodeLinkedInAndRerunsIdentically) {
  const scenario::Scenario scenario = Load(6, 8);
  const ScopedFolder folder_a(::testing::TempDir() + "app_host_sim_a_" + std::to_string(getpid()));
  const ScopedFolder folder_b(::testing::TempDir() + "app_host_sim_b_" + std::to_string(getpid()));
  const std::string& logs_a = folder_a.path();
  const std::string& logs_b = folder_b.path();
  const HostOptions options_a = Options("cooperative", logs_a);
  const HostOptions options_b = Options("cooperative", logs_b);

  const Outcome hosted = RunWith(scenario, [&](uint16_t id) { return MakeHostedApp(options_a, id); });
  const Outcome again = RunWith(scenario, [&](uint16_t id) { return MakeHostedApp(options_b, id); });
  // In-process every robot runs the same code in the test's own process
  // (the app keeps nothing in globals, so sharing them changes nothing).
  const Outcome linked_in = RunWith(scenario, [](uint16_t) {
    return std::make_unique<app::CAbiApp>(*cooperative_app_entry());
  });

  const json metrics = json::parse(hosted.metrics);
  EXPECT_TRUE(metrics["app"]["faults"].empty()) << metrics["app"].dump();
  EXPECT_GT(metrics["app"]["payload_refused"]["count"].get<int>(), 0);  // the app's overlong payloads
  // (EXPECT_TRUE: the replays are binary and long.)
  EXPECT_TRUE(hosted.metrics == again.metrics);
  EXPECT_TRUE(hosted.replay == again.replay);
  EXPECT_GT(hosted.replay.size(), 1000u);
  for (int id = 0; id < 6; ++id) {
    const std::string log = ReadFile(logs_a + "/" + std::to_string(id) + ".log");
    EXPECT_EQ(log.rfind("robot " + std::to_string(id) + " of 6 starts\n", 0), 0u) << log;
    EXPECT_EQ(log, ReadFile(logs_b + "/" + std::to_string(id) + ".log"));
  }
  EXPECT_TRUE(hosted.metrics == linked_in.metrics);
  EXPECT_TRUE(hosted.replay == linked_in.replay);
}

// The scenario's app params reach a library through syrofAppParameter the
// same way in-process (the robot's Platform answers from the scenario) and
// hosted (the host answers from its init request): the same bytes, and not
// those of a run without the params.
TEST(HostedAppSimulationTest, ALibraryReadsTheScenariosParamsTheSameWayHostedAndInProcess) {
  scenario::Scenario scenario = Load(4, 6);
  scenario.app.params = {{"target_x_m", 1.25}, {"speed_mps", 0.2}, {"unused_by_the_app", -1}};
  const ScopedFolder folder(::testing::TempDir() + "app_host_sim_params_" + std::to_string(getpid()));
  HostOptions options = Options("parameters", folder.path());
  options.params = scenario.app.params;

  const Outcome hosted = RunWith(scenario, [&](uint16_t id) { return MakeHostedApp(options, id); });
  const Outcome linked_in =
      RunWith(scenario, [](uint16_t) { return std::make_unique<app::CAbiApp>(*parameters_app_entry()); });
  EXPECT_EQ(parameters_app_target_x_m(), 1.25);
  EXPECT_EQ(parameters_app_checks(), 15);  // missing, NULL name, NULL value, overlong name
  scenario::Scenario defaults = scenario;
  defaults.app.params.clear();
  options.params.clear();
  const ScopedFolder folder_defaults(folder.path() + "_defaults");
  options.log_directory = folder_defaults.path();
  const Outcome hosted_defaults = RunWith(defaults, [&](uint16_t id) { return MakeHostedApp(options, id); });

  EXPECT_TRUE(json::parse(hosted.metrics)["app"]["faults"].empty()) << hosted.metrics;
  EXPECT_TRUE(hosted.metrics == linked_in.metrics);
  EXPECT_TRUE(hosted.replay == linked_in.replay);
  EXPECT_FALSE(hosted.replay == hosted_defaults.replay);
  for (int id = 0; id < 4; ++id) {
    EXPECT_EQ(ReadFile(folder.path() + "/" + std::to_string(id) + ".log"),
              "robot " + std::to_string(id) + ": target_x_m 1.250 (status 0), speed_mps 0.200, checks 15\n");
    EXPECT_EQ(ReadFile(folder_defaults.path() + "/" + std::to_string(id) + ".log"),
              "robot " + std::to_string(id) + ": target_x_m 0.500 (status 4), speed_mps 0.100, checks 15\n");
  }
}

TEST(HostedAppSimulationTest, ARobotWhoseLibraryCrashesStopsAndTheOthersGoOn) {
  const scenario::Scenario scenario = Load(4, 10);
  const ScopedFolder folder(::testing::TempDir() + "app_host_sim_crash_" + std::to_string(getpid()));
  const std::string& logs = folder.path();
  const HostOptions options = Options("robot2_crashes", logs);
  std::ostringstream replay;
  sim::SimulationOptions sim_options;
  sim_options.replay = &replay;
  sim_options.apps.factory = [&](uint16_t id) { return MakeHostedApp(options, id); };
  sim_options.apps.source = options.library_path;
  sim::Simulation simulation(scenario, sim_options);
  const json metrics = json::parse(simulation.Finish(0.0).metrics_json);

  EXPECT_EQ(metrics["sim_seconds"].get<double>(), 10.0);
  const json& app = metrics["app"];
  EXPECT_EQ(app["name"], "hostile");
  ASSERT_EQ(app["faults"].size(), 1u) << app.dump();
  EXPECT_EQ(app["faults"][0]["robot"], 2);
  EXPECT_EQ(app["faults"][0]["callback"], "new_round");
  EXPECT_EQ(app["faults"][0]["verdict"], "crashed");
  EXPECT_EQ(app["faults"][0]["detail"], "SIGSEGV");
  // The others removed robot 2 and went on.
  EXPECT_FALSE(simulation.robot(0).sync_state().members.test(2));
  EXPECT_EQ(metrics["membership"]["robots_removed"], 1);
  EXPECT_GT(metrics["epochs_started"].get<int>(), 6);
}

// One swarm, a different hostile library on each robot but robot 0: each
// fault stays in its robot, with its verdict, and robot 0 runs on.
TEST(HostedAppSimulationTest, EachHostileRobotFaultsAloneAndTheWellBehavedOneRunsOn) {
  const scenario::Scenario scenario = Load(7, 6);
  const ScopedFolder folder(::testing::TempDir() + "app_host_sim_mixed_" + std::to_string(getpid()));
  const std::string& logs = folder.path();
  const std::vector<std::pair<std::string, std::string>> plan = {
      {"cooperative", ""},      {"segfault", "crashed"},          {"infinite_loop", "timeout"},
      {"flood_output", "output_limit"}, {"kill_parent", "forbidden_syscall"}, {"allocate_gigabytes", "memory"},
      {"exit0", "exited"}};
  sim::SimulationOptions sim_options;
  sim_options.apps.factory = [&](uint16_t id) {
    HostOptions options = Options(plan[id].first, logs);
    options.limits.cpu_budget_ms = 50;
    return MakeHostedApp(options, id);
  };
  sim_options.apps.source = "test:mixed";
  sim::Simulation simulation(scenario, sim_options);
  const json metrics = json::parse(simulation.Finish(0.0).metrics_json);

  EXPECT_EQ(metrics["sim_seconds"].get<double>(), 6.0);
  std::map<int, std::string> verdicts;
  for (const json& fault : metrics["app"]["faults"]) verdicts[fault["robot"].get<int>()] = fault["verdict"];
  for (uint16_t id = 1; id < plan.size(); ++id) EXPECT_EQ(verdicts[id], plan[id].second) << plan[id].first;
  EXPECT_EQ(verdicts.count(0), 0u) << verdicts[0];
  // Robot 0 went on alone: every other robot left its map.
  for (uint16_t id = 1; id < plan.size(); ++id) EXPECT_FALSE(simulation.robot(0).sync_state().members.test(id));
  const std::string log = ReadFile(logs + "/0.log");
  EXPECT_EQ(log.rfind("robot 0 of 7 starts\n", 0), 0u) << log.substr(0, 200);
  EXPECT_NE(log.find("epoch 5 at"), std::string::npos) << log.substr(0, 2000);
}

// Each robot's private input reaches only that robot, through
// syrofAppInput, the same way in-process (the robot's Platform answers from
// its own row of the scenario's inputs) and hosted (each host gets its own
// robot's with the init request): the same bytes, and the robots' values
// differ (each drives to its own x and says so in its payload).
TEST(HostedAppSimulationTest, EachRobotReadsItsOwnPrivateInputHostedAndInProcess) {
  scenario::Scenario scenario = Load(4, 6);
  scenario.inputs = {{"charge", {0.25, 1.5, 0.75, 1.0}}};
  scenario.app.params = {{"speed_mps", 0.2}};
  const ScopedFolder folder(::testing::TempDir() + "app_host_sim_inputs_" + std::to_string(getpid()));
  HostOptions options = Options("inputs", folder.path());
  options.params = scenario.app.params;
  for (uint16_t id = 0; id < 4; ++id) options.inputs[id] = sim::InputValuesOf(scenario, id);

  const Outcome hosted = RunWith(scenario, [&](uint16_t id) { return MakeHostedApp(options, id); });
  const Outcome linked_in =
      RunWith(scenario, [](uint16_t) { return std::make_unique<app::CAbiApp>(*inputs_app_entry()); });
  scenario::Scenario swapped = scenario;
  swapped.inputs = {{"charge", {1.5, 0.25, 0.75, 1.0}}};
  const Outcome linked_in_swapped =
      RunWith(swapped, [](uint16_t) { return std::make_unique<app::CAbiApp>(*inputs_app_entry()); });

  EXPECT_TRUE(json::parse(hosted.metrics)["app"]["faults"].empty()) << hosted.metrics;
  EXPECT_TRUE(hosted.metrics == linked_in.metrics);
  EXPECT_TRUE(hosted.replay == linked_in.replay);
  EXPECT_FALSE(linked_in.replay == linked_in_swapped.replay);
  const char* const charges[] = {"0.250", "1.500", "0.750", "1.000"};
  for (int id = 0; id < 4; ++id) {
    EXPECT_EQ(ReadFile(folder.path() + "/" + std::to_string(id) + ".log"),
              "robot " + std::to_string(id) + ": charge " + charges[id] + " (status 0), checks 63\n");
  }
}

// Every robot's kind reaches every app: its own in init's info, each
// member's in the map (docs/apps.md, "Robot kinds"), hosted and in-process
// alike (the same replay: the payloads carry the kinds), in a swarm of all
// three kinds.
TEST(HostedAppSimulationTest, EveryAppReadsItsOwnKindAndEachMembersHostedAndInProcess) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(R"(seed: 5
robots:
  kind: omni
  poses:
    - { x_m: 1.0, y_m: 1.0 }
    - { x_m: 1.8, y_m: 1.0, kind: rover }
    - { x_m: 1.0, y_m: 1.8, kind: drone }
    - { x_m: 1.8, y_m: 1.8 }
timing: { duration_s: 4 }
app: builtin:idle
)",
                                                                 "kinds.yaml", {});
  ASSERT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  const scenario::Scenario& scenario = *loaded.scenario;
  const ScopedFolder folder(::testing::TempDir() + "app_host_sim_kinds_" + std::to_string(getpid()));
  const HostOptions options = Options("kinds", folder.path());

  const Outcome hosted = RunWith(scenario, [&](uint16_t id) { return MakeHostedApp(options, id); });
  const Outcome linked_in =
      RunWith(scenario, [](uint16_t) { return std::make_unique<app::CAbiApp>(*kinds_app_entry()); });

  EXPECT_TRUE(json::parse(hosted.metrics)["app"]["faults"].empty()) << hosted.metrics;
  EXPECT_TRUE(hosted.replay == linked_in.replay);
  const char* const kinds[] = {"omni", "rover", "drone", "omni"};
  for (int id = 0; id < 4; ++id) {
    EXPECT_EQ(ReadFile(folder.path() + "/" + std::to_string(id) + ".log"),
              "robot " + std::to_string(id) + " is a " + kinds[id] +
                  "\nepoch 3: 0 omni 1 rover 2 drone 3 omni\n");
  }
}

}  // namespace
}  // namespace syrof::app_host
