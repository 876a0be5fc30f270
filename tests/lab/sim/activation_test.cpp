// SSYNC in the lab, end to end: a robot the schedule leaves out gets no
// newRound and does not move, yet stays a member; the metrics count it;
// FSYNC written out is the same run as no `activation:` at all.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::sim {
namespace {

scenario::Scenario LoadText(const std::string& text) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// Drives right at 5 cm/s in every maneuver it is given.
class DriftApp final : public app::App {
 public:
  const char* name() const override { return "drift_test"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform&, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap&, uint8_t& global_state,
                           uint32_t) override {
    command = syrof_car_command{};
    command.kind = SYROF_COMMAND_VELOCITY;
    command.vx_mps = 0.05f;
    ++global_state;
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }
};

constexpr const char* kSwarm =
    "seed: 4\n"
    "arena: { width_m: 6, height_m: 6 }\n"
    "robots: { count: 3, placement: grid, spacing_m: 1.0 }\n"
    "timing: { duration_s: 8 }\n"
    "app: builtin:idle\n";

SimulationOptions DriftOptions() {
  SimulationOptions options;
  options.apps.factory = [](uint16_t) { return std::make_unique<DriftApp>(); };
  options.apps.source = "drift_test";
  return options;
}

TEST(LabActivationTest, ARobotLeftOutOfEveryEpochNeitherComputesNorMovesButStaysAMember) {
  // Robot 0 is named in no listed epoch: it is never active.
  const scenario::Scenario scenario = LoadText(std::string(kSwarm) +
                                               "activation:\n  model: ssync\n  schedule: scripted\n"
                                               "  active: [[1, [1, 2]], [2, [1]], [3, [2]], [4, [1, 2]],"
                                               " [5, [1, 2]], [6, [1, 2]], [7, [1, 2]], [8, [1, 2]]]\n");
  Simulation simulation(scenario, DriftOptions());
  const double start_x0 = simulation.world().state(0).x_m;
  const double start_x1 = simulation.world().state(1).x_m;
  simulation.RunUntil(scenario.timing.duration_s);

  const runtime::Robot& left_out = simulation.robot(0);
  EXPECT_EQ(left_out.counters().new_rounds, 0u);
  EXPECT_EQ(left_out.counters().end_of_rounds, 0u);
  EXPECT_GE(left_out.counters().inactive_epochs, 5u);
  EXPECT_EQ(left_out.global_state(), 0);  // held
  EXPECT_LT(std::abs(simulation.world().state(0).x_m - start_x0), 0.002);
  // It still beacons and stays a member of the others' maps.
  EXPECT_TRUE(simulation.robot(1).ldmap().members.test(0));
  EXPECT_TRUE(simulation.robot(0).ldmap().members.test(0));
  // The others move in the epochs they are given.
  EXPECT_GT(simulation.world().state(1).x_m - start_x1, 0.1);
  EXPECT_GE(simulation.robot(1).counters().new_rounds, 5u);
  EXPECT_EQ(simulation.robot(1).counters().inactive_epochs, 1u);  // epoch 3
  EXPECT_EQ(simulation.robot(2).counters().inactive_epochs, 1u);  // epoch 2

  const RunReport report = simulation.Finish(0);
  ASSERT_TRUE(report.metrics.activation.has_value());
  const metrics::ActivationMetrics& activation = *report.metrics.activation;
  EXPECT_EQ(activation.schedule, "scripted");
  EXPECT_FALSE(activation.fair_within.has_value());
  EXPECT_EQ(activation.inactive_starts, left_out.counters().inactive_epochs + 2);
  EXPECT_EQ(activation.active_starts + activation.inactive_starts, report.metrics.epoch_starts);
  EXPECT_EQ(activation.fair_within_achieved, static_cast<int64_t>(left_out.counters().inactive_epochs) + 1);
  EXPECT_NE(report.metrics_json.find("\"activation\""), std::string::npos);
}

TEST(LabActivationTest, RoundRobinMovesOneRobotAnEpoch) {
  const scenario::Scenario scenario =
      LoadText(std::string(kSwarm) + "activation: { model: ssync, schedule: round_robin }\n");
  Simulation simulation(scenario, DriftOptions());
  simulation.RunUntil(scenario.timing.duration_s);
  uint32_t new_rounds = 0;
  uint32_t inactive = 0;
  for (uint16_t id = 0; id < 3; ++id) {
    new_rounds += simulation.robot(id).counters().new_rounds;
    inactive += simulation.robot(id).counters().inactive_epochs;
  }
  const RunReport report = simulation.Finish(0);
  ASSERT_TRUE(report.metrics.activation.has_value());
  // One newRound per epoch among three members: two left out of each.
  EXPECT_EQ(new_rounds, static_cast<uint32_t>(report.metrics.epochs_started));
  EXPECT_EQ(inactive, 2 * new_rounds);
  EXPECT_EQ(report.metrics.activation->active_starts, new_rounds);
  EXPECT_EQ(report.metrics.activation->fair_within_achieved, 3);
}

TEST(LabActivationTest, FsyncWrittenOutIsTheDefaultRunByteForByte) {
  const RunReport implicit = sim::Run(LoadText(kSwarm), DriftOptions());
  const RunReport explicit_fsync = sim::Run(LoadText(std::string(kSwarm) + "activation: { model: fsync }\n"), DriftOptions());
  EXPECT_EQ(implicit.metrics_json, explicit_fsync.metrics_json);
  EXPECT_EQ(implicit.metrics_json.find("\"activation\""), std::string::npos);
  EXPECT_FALSE(implicit.metrics.activation.has_value());
}

}  // namespace
}  // namespace syrof::lab::sim
