// Real clocks measured in the simulated lab (docs/clocks.md, "Measured"):
// every robot boots up to a whole round late and drifts by up to the given
// ppm; the same runs with round alignment on and off, side by side, and the
// lab's shared perfect clock as the reference. Per row: when the rounds
// converged (every pair of members within 1 ms, for the rest of the run),
// the residual pairwise phase error after that (p50 / p99 / max, ms), the
// largest error of the whole run, P3 violations, the COOPERATIVE fraction
// and the largest epoch start skew (rounds and ms). Deterministic (fixed
// seeds): the table regenerates exactly.
//
// Every run: builtin:idle, 50 ms radio rounds, 1 s app rounds, K = 3, F = 6,
// 5 % i.i.d. loss, robots on a 1 m grid; seeds 1..3, figures pooled (times
// and errors: the worst seed; fractions: over all starts).
//
// Usage: bench_lab_clocks [--quick]   (--quick: one seed, 20 s runs)
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace {

using namespace syrof::lab;

struct Row {
  std::string name;
  std::string clocks;  // the scenario's clocks section ("" for the shared clock)
  std::string faults;
};

struct Pooled {
  std::optional<double> converged_s;  // worst seed; unset if any seed never converged
  bool never = false;
  double p50_ms = 0, p99_ms = 0, max_ms = 0, run_max_ms = 0;
  int64_t violations = 0;
  int64_t starts = 0, cooperative = 0;
  int64_t max_skew_rounds = 0;
  double max_skew_ms = 0;
};

std::string Scenario(int robots, double duration_s, uint64_t seed, const Row& row) {
  const int side = 4;
  const double arena_m = side + 1.0;
  return fmt::format(R"(seed: {seed}
arena:
  width_m: {arena}
  height_m: {arena}
  anchors:
    - {{x_m: 0, y_m: 0, z_m: 0}}
    - {{x_m: {arena}, y_m: {arena}, z_m: 0}}
    - {{x_m: 0, y_m: {arena}, z_m: 2}}
    - {{x_m: {arena}, y_m: 0, z_m: 2}}
robots: {{count: {robots}, placement: grid, spacing_m: 1.0}}
timing: {{radio_round_s: 0.05, app_round_s: 1.0, vote_rounds: 3, silence_rounds: 6, duration_s: {duration}}}
channel: {{model: iid, loss: 0.05}}
app: builtin:idle
{clocks}
{faults})",
                     fmt::arg("seed", seed), fmt::arg("arena", arena_m), fmt::arg("robots", robots),
                     fmt::arg("duration", duration_s), fmt::arg("clocks", row.clocks), fmt::arg("faults", row.faults));
}

void Add(Pooled& pooled, const std::string& text) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "bench");
  if (!loaded.ok()) {
    fmt::print(stderr, "bench scenario refused: {}\n{}\n", loaded.error->ToString(), text);
    std::exit(1);
  }
  const sim::RunReport report = sim::Run(*loaded.scenario, sim::SimulationOptions{}, 0.0);
  const metrics::Metrics& m = report.metrics;
  if (m.round_phase.converged_s) {
    pooled.converged_s = std::max(pooled.converged_s.value_or(0.0), *m.round_phase.converged_s);
    pooled.p50_ms = std::max(pooled.p50_ms, m.round_phase.residual.p50_ms);
    pooled.p99_ms = std::max(pooled.p99_ms, m.round_phase.residual.p99_ms);
    pooled.max_ms = std::max(pooled.max_ms, m.round_phase.residual.max_ms);
  } else {
    pooled.never = true;
  }
  pooled.run_max_ms = std::max(pooled.run_max_ms, m.round_phase.run.max_ms);
  pooled.violations += m.common_knowledge.violations;
  pooled.starts += m.epoch_starts;
  pooled.cooperative += m.common_knowledge.cooperative_starts;
  pooled.max_skew_rounds = std::max(pooled.max_skew_rounds, m.synchrony.max_start_skew_rounds);
  pooled.max_skew_ms = std::max(pooled.max_skew_ms, m.synchrony.max_start_skew_ms);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const int robots = 10;
  const double duration_s = quick ? 20 : 60;
  const int seeds = quick ? 1 : 3;
  // Robot 9 with a bad crystal; the others within +-50 ppm.
  const std::string bad_crystal = "[12, -30, 41, -7, 25, -50, 3, 50, -18, 1000]";
  const std::vector<Row> rows = {
      {"shared clock (no clocks section)", "", ""},
      {"clocks, no offset, no drift, on", "clocks: {alignment: on}", ""},
      {"offset <= 1 round, on", "clocks: {offset_max_ms: 50, alignment: on}", ""},
      {"offset <= 1 round, off", "clocks: {offset_max_ms: 50, alignment: off}", ""},
      {"offset <= 1 round, +-50 ppm, on", "clocks: {offset_max_ms: 50, drift_max_ppm: 50, alignment: on}", ""},
      {"offset <= 1 round, +-50 ppm, off", "clocks: {offset_max_ms: 50, drift_max_ppm: 50, alignment: off}", ""},
      {"offset <= 1 round, +-100 ppm, jitter 0.2 ms, on",
       "clocks: {offset_max_ms: 50, drift_max_ppm: 100, jitter_ms: 0.2, alignment: on}", ""},
      {"offset <= 1 round, +-100 ppm, jitter 0.2 ms, off",
       "clocks: {offset_max_ms: 50, drift_max_ppm: 100, jitter_ms: 0.2, alignment: off}", ""},
      {"one robot at +1000 ppm, on", "clocks: {offset_max_ms: 50, drift_ppm: " + bad_crystal + ", alignment: on}", ""},
      {"one robot at +1000 ppm, off", "clocks: {offset_max_ms: 50, drift_ppm: " + bad_crystal + ", alignment: off}",
       ""},
      {"joiner at 5 s + pause 8-10 s, +-50 ppm, on",
       "clocks: {offset_max_ms: 50, drift_max_ppm: 50, alignment: on}",
       "faults:\n  - {join: 9, at_s: 5}\n  - {pause: 3, at_s: 8, until_s: 10}"},
      {"joiner at 5 s + pause 8-10 s, +-50 ppm, off",
       "clocks: {offset_max_ms: 50, drift_max_ppm: 50, alignment: off}",
       "faults:\n  - {join: 9, at_s: 5}\n  - {pause: 3, at_s: 8, until_s: 10}"},
  };
  fmt::print("{} robots, {} s, {} seed(s), 50 ms rounds, 5 % loss; aligned = every member pair within 1 ms\n\n", robots,
             duration_s, seeds);
  fmt::print("| clocks | converged (s) | residual p50 / p99 / max (ms) | run max (ms) | P3 | COOPERATIVE | max skew (rounds / ms) |\n");
  fmt::print("| --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Row& row : rows) {
    Pooled pooled;
    for (int seed = 1; seed <= seeds; ++seed) Add(pooled, Scenario(robots, duration_s, static_cast<uint64_t>(seed), row));
    const std::string converged =
        pooled.never ? "never" : pooled.converged_s ? fmt::format("{:.2f}", *pooled.converged_s) : "-";
    const std::string residual =
        pooled.never ? "-" : fmt::format("{:.3f} / {:.3f} / {:.3f}", pooled.p50_ms, pooled.p99_ms, pooled.max_ms);
    const double fraction =
        pooled.starts == 0 ? 0.0 : 100.0 * static_cast<double>(pooled.cooperative) / static_cast<double>(pooled.starts);
    fmt::print("| {} | {} | {} | {:.3f} | {} | {:.1f} % | {} / {:.1f} |\n", row.name, converged, residual,
               pooled.run_max_ms, pooled.violations, fraction, pooled.max_skew_rounds, pooled.max_skew_ms);
  }
  return 0;
}
