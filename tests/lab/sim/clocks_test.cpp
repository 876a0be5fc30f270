// Real clocks in the lab (docs/clocks.md), end to end on small seeded runs:
// P3 holds whatever the clocks do; with alignment the rounds converge below
// 1 ms and stay there; joiners and paused robots come back aligned; a robot
// 1000 ppm fast does not disturb the rest; a run is deterministic; and a
// scenario without a clocks section is untouched by any of it.
#include <gtest/gtest.h>

#include <string>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::sim {
namespace {

scenario::Scenario Load(const std::string& text) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

std::string Text(const std::string& clocks, const std::string& faults = "", double duration_s = 15, int seed = 1) {
  return "seed: " + std::to_string(seed) +
         "\nrobots: {count: 6, placement: grid, spacing_m: 1.0}\n"
         "arena: {width_m: 4, height_m: 4}\n"
         "timing: {radio_round_s: 0.05, app_round_s: 1.0, duration_s: " +
         std::to_string(duration_s) +
         "}\n"
         "channel: {model: iid, loss: 0.05}\n"
         "app: builtin:idle\n" +
         clocks + "\n" + faults + "\n";
}

RunReport RunText(const std::string& text) { return Run(Load(text), SimulationOptions{}); }

TEST(ClocksTest, P3HoldsWithoutAlignmentWhateverTheClocksDo) {
  for (int seed = 1; seed <= 3; ++seed) {
    const RunReport report =
        RunText(Text("clocks: {offset_max_ms: 50, drift_max_ppm: 1000, jitter_ms: 1, alignment: off}", "", 15, seed));
    EXPECT_EQ(report.metrics.common_knowledge.violations, 0) << "seed " << seed;
    EXPECT_GT(report.metrics.epoch_starts, 0);
  }
}

TEST(ClocksTest, AlignedRoundsConvergeBelowAMillisecondAtFiftyPpm) {
  const RunReport report = RunText(Text("clocks: {offset_max_ms: 50, drift_max_ppm: 50, alignment: on}"));
  const metrics::RoundPhaseMetrics& phase = report.metrics.round_phase;
  ASSERT_TRUE(phase.converged_s.has_value());
  EXPECT_LT(*phase.converged_s, 2.0);
  EXPECT_LE(phase.residual.max_ms, 1.0);
  EXPECT_EQ(report.metrics.common_knowledge.violations, 0);
  // Unaligned, the same clocks stay apart.
  const RunReport off = RunText(Text("clocks: {offset_max_ms: 50, drift_max_ppm: 50, alignment: off}"));
  EXPECT_FALSE(off.metrics.round_phase.converged_s.has_value());
}

TEST(ClocksTest, JoinerAndPausedRobotComeBackAligned) {
  const RunReport report =
      RunText(Text("clocks: {offset_max_ms: 50, drift_max_ppm: 50, alignment: on}",
                   "faults:\n  - {join: 5, at_s: 3}\n  - {pause: 2, at_s: 5, until_s: 7}"));
  const metrics::RoundPhaseMetrics& phase = report.metrics.round_phase;
  ASSERT_TRUE(phase.converged_s.has_value());
  EXPECT_LE(phase.residual.max_ms, 1.0);
  EXPECT_EQ(report.metrics.common_knowledge.violations, 0);
  EXPECT_GE(report.metrics.membership.completed_joins, 1);
}

TEST(ClocksTest, ABadCrystalIsTrackedWithoutDisturbingTheRest) {
  const RunReport report =
      RunText(Text("clocks: {offset_max_ms: 50, drift_ppm: [10, -20, 30, -40, 0, 1000], alignment: on}"));
  const metrics::RoundPhaseMetrics& phase = report.metrics.round_phase;
  ASSERT_TRUE(phase.converged_s.has_value());
  EXPECT_LE(phase.residual.max_ms, 1.0);
  EXPECT_EQ(report.metrics.common_knowledge.violations, 0);
}

TEST(ClocksTest, SameScenarioAndSeedSameBytes) {
  const std::string text = Text("clocks: {offset_max_ms: 50, drift_max_ppm: 100, jitter_ms: 0.5}", "", 5);
  EXPECT_EQ(RunText(text).metrics_json, RunText(text).metrics_json);
}

TEST(ClocksTest, SharedClockRunsAreAlignedByConstruction) {
  const RunReport report = RunText(Text("", "", 5));
  EXPECT_EQ(report.metrics.round_phase.run.max_ms, 0.0);
  ASSERT_TRUE(report.metrics.round_phase.converged_s.has_value());
  EXPECT_NEAR(report.metrics.synchrony.max_start_skew_ms,
              static_cast<double>(report.metrics.synchrony.max_start_skew_rounds) * 50.0, 1e-9);
}

}  // namespace
}  // namespace syrof::lab::sim
