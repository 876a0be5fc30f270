// SSYNC and ASYNC in the lab, end to end: a robot the schedule leaves out
// gets no newRound and does not move, yet stays a member; under ASYNC a
// move starts and ends epochs after its look, spread over its epochs, and
// may be cut; the metrics count both; FSYNC written out is the same run as
// no `activation:` at all.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

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

// The run's replay bytes, and its report in `report`.
std::string ReplayOf(const scenario::Scenario& scenario, RunReport& report) {
  std::ostringstream replay;
  SimulationOptions options = DriftOptions();
  options.replay = &replay;
  report = sim::Run(scenario, options);
  return replay.str();
}

// Under ASYNC with every cycle one epoch long (a script listing none) the
// run is FSYNC's, byte for byte, but for the metrics' activation section.
TEST(LabAsyncTest, OneEpochCyclesAreTheFsyncRun) {
  RunReport fsync;
  RunReport async;
  const std::string fsync_replay = ReplayOf(LoadText(kSwarm), fsync);
  const std::string async_replay = ReplayOf(
      LoadText(std::string(kSwarm) + "activation: { model: async, schedule: scripted, max_delay_epochs: 2, cycles: [] }\n"),
      async);
  EXPECT_GT(fsync_replay.size(), 1000u);
  EXPECT_EQ(fsync_replay, async_replay);
  ASSERT_TRUE(async.metrics.activation.has_value());
  ASSERT_TRUE(async.metrics.activation->async.has_value());
  EXPECT_EQ(async.metrics.activation->inactive_starts, 0);
  EXPECT_EQ(async.metrics.activation->async->stale_move_epochs, 0);
  EXPECT_EQ(async.metrics.activation->async->move_epochs, async.metrics.activation->active_starts);
}

// Robot 0 looks in epoch 2, waits one epoch, then moves over two: no
// newRound in epochs 3 and 4, endOfRound once the move's second maneuver
// ends, half the speed in each so it covers one maneuver's distance, and
// the others see it mid-move at the start of epoch 4.
TEST(LabAsyncTest, AMoveStartsAndEndsInTheEpochsItsCycleNames) {
  const scenario::Scenario scenario =
      LoadText(std::string(kSwarm) +
               "activation: { model: async, schedule: scripted, max_delay_epochs: 2, cycles: [[2, 0, 1, 2]] }\n");
  Simulation simulation(scenario, DriftOptions());
  const runtime::Robot& robot = simulation.robot(0);
  // Where robot 0 is when each epoch starts (the lab's truth), and its calls.
  std::vector<double> x_at_start;
  std::vector<uint32_t> new_rounds_at_start;
  std::vector<uint32_t> end_of_rounds_at_start;
  uint16_t seen_epoch = 0;
  while (simulation.now_s() < scenario.timing.duration_s) {
    simulation.RunUntil(simulation.now_s() + 0.05);
    if (robot.ldmap().epoch != seen_epoch) {
      seen_epoch = robot.ldmap().epoch;
      x_at_start.push_back(simulation.world().state(0).x_m);
      new_rounds_at_start.push_back(robot.counters().new_rounds);
      end_of_rounds_at_start.push_back(robot.counters().end_of_rounds);
    }
  }
  ASSERT_GE(x_at_start.size(), 6u);
  // Index k is epoch k + 1. newRound in epochs 1 and 2, none in 3 and 4,
  // then again in 5.
  EXPECT_EQ(new_rounds_at_start[0], 1u);
  EXPECT_EQ(new_rounds_at_start[1], 2u);
  EXPECT_EQ(new_rounds_at_start[2], 2u);
  EXPECT_EQ(new_rounds_at_start[3], 2u);
  EXPECT_EQ(new_rounds_at_start[4], 3u);
  // endOfRound after epoch 1's maneuver, then only after epoch 4's.
  EXPECT_EQ(end_of_rounds_at_start[2], 1u);
  EXPECT_EQ(end_of_rounds_at_start[3], 1u);
  EXPECT_EQ(end_of_rounds_at_start[4], 2u);
  const double one_maneuver = x_at_start[1] - x_at_start[0];  // epoch 1: a whole move at 5 cm/s
  EXPECT_GT(one_maneuver, 0.02);
  EXPECT_LT(std::abs(x_at_start[2] - x_at_start[1]), 0.002);          // epoch 2: looked, waits
  const double first_half = x_at_start[3] - x_at_start[2];             // epoch 3: half speed
  const double second_half = x_at_start[4] - x_at_start[3];            // epoch 4: half speed
  EXPECT_NEAR(first_half, one_maneuver / 2, one_maneuver * 0.2);
  EXPECT_NEAR(second_half, one_maneuver / 2, one_maneuver * 0.2);
  EXPECT_NEAR(x_at_start[5] - x_at_start[4], one_maneuver, one_maneuver * 0.2);  // epoch 5: one epoch again
  const RunReport report = simulation.Finish(0);
  ASSERT_TRUE(report.metrics.activation && report.metrics.activation->async);
  EXPECT_EQ(report.metrics.activation->model, "async");
  EXPECT_EQ(report.metrics.activation->async->stale_move_epochs, 2);  // robot 0 in epochs 3 and 4
  EXPECT_EQ(report.metrics.activation->inactive_starts, 2);
  EXPECT_EQ(report.metrics.activation->fair_within_achieved, 3);
}

// Non-rigid: a cut move stops once it covered min_move_m, and the robot
// holds there until the move's last epoch ends.
TEST(LabAsyncTest, ACutMoveStopsOnceItCoveredTheLeastDistance) {
  const scenario::Scenario scenario = LoadText(
      std::string(kSwarm) +
      "activation: { model: async, schedule: scripted, max_delay_epochs: 1, min_move_m: 0.01, cycles: [[2, 0, 0, 1, 1]] }\n");
  Simulation simulation(scenario, DriftOptions());
  const runtime::Robot& robot = simulation.robot(0);
  std::vector<double> x_at_start;
  uint16_t seen_epoch = 0;
  while (simulation.now_s() < scenario.timing.duration_s) {
    simulation.RunUntil(simulation.now_s() + 0.05);
    if (robot.ldmap().epoch != seen_epoch) {
      seen_epoch = robot.ldmap().epoch;
      x_at_start.push_back(simulation.world().state(0).x_m);
    }
  }
  ASSERT_GE(x_at_start.size(), 4u);
  const double whole = x_at_start[1] - x_at_start[0];
  const double cut = x_at_start[2] - x_at_start[1];
  EXPECT_GT(whole, 0.03);
  EXPECT_GT(cut, 0.008);       // it covered the least distance (less the estimate's error) ...
  EXPECT_LT(cut, whole * 0.6);  // ... and stopped well short of the whole move
  EXPECT_EQ(robot.counters().moves_cut, 1u);
  const RunReport report = simulation.Finish(0);
  EXPECT_EQ(report.metrics.activation->async->moves_cut, 1);
}

TEST(LabAsyncTest, ARandomScheduleIsTheSameRunForTheSameSeed) {
  const std::string text = std::string(kSwarm) + "activation: { model: async, schedule: random, max_delay_epochs: 2, min_move_m: 0.02 }\n";
  RunReport first;
  RunReport second;
  EXPECT_EQ(ReplayOf(LoadText(text), first), ReplayOf(LoadText(text), second));
  EXPECT_EQ(first.metrics_json, second.metrics_json);
  ASSERT_TRUE(first.metrics.activation && first.metrics.activation->async);
  EXPECT_GT(first.metrics.activation->async->stale_move_epochs, 0);
  EXPECT_GT(first.metrics.activation->inactive_starts, 0);
  EXPECT_EQ(first.metrics.common_knowledge.violations, 0);
}

}  // namespace
}  // namespace syrof::lab::sim
