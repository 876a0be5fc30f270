// The safety filter's margin against the estimator's true error, in the lab
// (docs/safety.md, "What the estimate says of itself"; the full table is
// bench_lab_margin_coverage's): the EKF's position NEES is near its
// dimension in mixed swarms with loss, joins and pauses, and with the
// lab's default configuration (no configure_robot: SafetyConfig::own_sigmas
// = motion::kOwnSigmas, four; docs/safety.md "Margin coverage") each driving
// robot's true position error stays within the allowance the filter used for
// it (motion::OwnErrorAllowanceM) in at least 99.9% of robot-rounds, and the
// mixed swarm that collides with two sigmas does not. Were the default two
// again, the first two tests would fail (10% of robot-rounds past the
// allowance; the collision at 20.94 s).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "syrof/estimation/state.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/motion/safety_filter.h"

namespace syrof::lab::sim {
namespace {

scenario::Scenario LoadCoverageFile(const std::string& file, const scenario::Overrides& overrides) {
  const scenario::LoadResult loaded =
      scenario::LoadScenarioFile(std::string(SYROF_SCENARIOS_DIR) + "/" + file, overrides);
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

struct Coverage {
  int64_t robot_rounds = 0;
  int64_t beyond = 0;  // true error beyond the filter's allowance
  double nees_sum = 0;
};

SimulationOptions WithOwnSigmas(float own_sigmas) {
  SimulationOptions options;
  options.configure_robot = [own_sigmas](runtime::RobotConfig& config) { config.safety.own_sigmas = own_sigmas; };
  return options;
}

Coverage Measure(const std::string& file, uint64_t seed, double duration_s) {
  scenario::Overrides overrides;
  overrides.seed = seed;
  overrides.duration_s = duration_s;
  const scenario::Scenario scenario = LoadCoverageFile(file, overrides);
  Simulation simulation(scenario, SimulationOptions{});  // the default margin rule
  Coverage coverage;
  const double round_s = scenario.timing.radio_round_s;
  for (int64_t round = 1; static_cast<double>(round) * round_s <= duration_s + 1e-9; ++round) {
    simulation.RunUntil(static_cast<double>(round) * round_s);
    for (uint16_t id = 0; id < simulation.robot_count(); ++id) {
      const runtime::Robot& robot = simulation.robot(id);
      if (simulation.world().presence(id) != world::BodyPresence::kActive || !robot.estimate_valid()) continue;
      const world::BodyState& truth = simulation.world().state(id);
      const estimation::StateEstimate& estimate = robot.estimate();
      const double error_m = std::hypot(truth.x_m - estimate.x_m, truth.y_m - estimate.y_m);
      ++coverage.robot_rounds;
      if (error_m > motion::OwnErrorAllowanceM(robot.config().safety, estimate)) ++coverage.beyond;
      const auto& filter = robot.estimator().filter();
      const Eigen::Vector2d e(truth.x_m - filter.state()(estimation::kStateX),
                              truth.y_m - filter.state()(estimation::kStateY));
      const Eigen::Matrix2d p = filter.covariance().topLeftCorner<2, 2>().cast<double>();
      coverage.nees_sum += e.dot(p.ldlt().solve(e));
    }
  }
  return coverage;
}

// With two sigmas the error is past the allowance in 10% of these
// robot-rounds (13.5% expected of a consistent 2-D estimate); with the
// default four, in none of the 23,000. The NEES checks that the filter's sigma is honest
// there (the margin can only be as good as it).
TEST(MarginCoverageTest, TheAllowanceCoversTheTrueErrorInMixedSwarms) {
  Coverage total;
  for (const char* file : {"mixed/gather_4_4_loss.yaml", "mixed/circle_6_6_loss.yaml"}) {
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      const Coverage run = Measure(file, seed, 15.0);
      total.robot_rounds += run.robot_rounds;
      total.beyond += run.beyond;
      total.nees_sum += run.nees_sum;
    }
  }
  ASSERT_GT(total.robot_rounds, 20000);
  EXPECT_LE(static_cast<double>(total.beyond), 0.001 * static_cast<double>(total.robot_rounds))
      << total.beyond << " of " << total.robot_rounds << " robot-rounds beyond the allowance";
  const double nees = total.nees_sum / static_cast<double>(total.robot_rounds);
  EXPECT_GT(nees, 1.5);
  EXPECT_LT(nees, 2.5);
}

// Four omni robots and four rovers gathering under 10% loss: at 20.94 s
// omni robot 0, its estimate about 7 cm off, drives into rover 4 with an
// allowance of two sigmas (4.4 cm; bench_lab_margin_coverage --own-sigmas 2
// --first 2 --seeds 1 --list shows it, and the second half of this test).
// With the default four (8.8 cm) it keeps clear.
TEST(MarginCoverageTest, AMixedSwarmDoesNotCollideWhereAnEstimateWasSevenCentimetresOff) {
  scenario::Overrides overrides;
  overrides.seed = 2;
  overrides.duration_s = 22;
  const scenario::Scenario scenario = LoadCoverageFile("mixed/gather_4_4_loss.yaml", overrides);
  const nlohmann::json metrics = nlohmann::json::parse(sim::Run(scenario, SimulationOptions{}, 0.0).metrics_json);
  EXPECT_EQ(metrics["collisions"]["count"], 0) << metrics["collisions"].dump();
  EXPECT_TRUE(metrics["goal"]["reached"].get<bool>()) << metrics["goal"].dump();
  // The same run with two sigmas collides: the case is one the default decides.
  const nlohmann::json two = nlohmann::json::parse(sim::Run(scenario, WithOwnSigmas(2.0f), 0.0).metrics_json);
  EXPECT_EQ(two["collisions"]["count"], 1) << two["collisions"].dump();
}

// The mixed-kind files over twenty seeds with the default margin rule: no
// collision, no P3 violation. Not under the sanitizers (ASAN_EXCLUDE, "TwentySeeds"): 60
// runs, about 5 s.
TEST(MarginCoverageTest, TwentySeedsOfEveryMixedSwarmWithTheDefaultMargin) {
  for (const char* file : {"mixed/gather_4_4_loss.yaml", "mixed/gather_join_pause.yaml", "mixed/circle_6_6_loss.yaml"}) {
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      scenario::Overrides overrides;
      overrides.seed = seed;
      const nlohmann::json metrics = nlohmann::json::parse(
          sim::Run(LoadCoverageFile(file, overrides), SimulationOptions{}, 0.0).metrics_json);
      EXPECT_EQ(metrics["collisions"]["count"], 0) << file << " seed " << seed << ": " << metrics["collisions"].dump();
      EXPECT_EQ(metrics["common_knowledge"]["violations"], 0) << file << " seed " << seed;
    }
  }
}

}  // namespace
}  // namespace syrof::lab::sim
