// HostedApp in the lab: a library run through the app host behaves as the
// same C source linked in (same replay and metrics bytes), a run is
// byte-identical on rerun, and a robot whose library faults stops like a
// crashed robot while the others go on.
#include <dirent.h>
#include <unistd.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "syrof/app/c_abi_app.h"
#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

extern "C" const syrof_app_descriptor* cooperative_app_entry(void);

namespace syrof::app_host {
namespace {

using nlohmann::json;
namespace sim = lab::sim;
namespace scenario = lab::scenario;

std::string Library(const std::string& name) { return std::string(SYROF_TEST_LIBS_DIR) + "/lib" + name + ".so"; }

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
  options.app_factory = std::move(factory);
  options.app_source = "test:cooperative";
  const sim::RunReport report = sim::Run(scenario, options, 0.0);
  return Outcome{report.metrics_json, replay.str()};
}

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

HostOptions Options(const std::string& library, const std::string& logs) {
  HostOptions options;
  options.library_path = Library(library);
  options.log_directory = logs;
  return options;
}

TEST(HostedAppSimulationTest, ALibraryRunsAsTheSameCodeLinkedInAndRerunsIdentically) {
  const scenario::Scenario scenario = Load(6, 8);
  const std::string logs_a = ::testing::TempDir() + "app_host_sim_a_" + std::to_string(getpid());
  const std::string logs_b = ::testing::TempDir() + "app_host_sim_b_" + std::to_string(getpid());
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

TEST(HostedAppSimulationTest, ARobotWhoseLibraryCrashesStopsAndTheOthersGoOn) {
  const scenario::Scenario scenario = Load(4, 10);
  const std::string logs = ::testing::TempDir() + "app_host_sim_crash_" + std::to_string(getpid());
  const HostOptions options = Options("robot2_crashes", logs);
  std::ostringstream replay;
  sim::SimulationOptions sim_options;
  sim_options.replay = &replay;
  sim_options.app_factory = [&](uint16_t id) { return MakeHostedApp(options, id); };
  sim_options.app_source = options.library_path;
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

}  // namespace
}  // namespace syrof::app_host
