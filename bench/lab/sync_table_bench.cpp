// The synchronizer measured in the simulated lab: COOPERATIVE fraction,
// start skew and mode agreement per epoch against loss (i.i.d. 0-60 %, and
// bursty) and K, for 10 and 50 robots; then the faults that stretch the
// skew (a deaf robot, a pause); then partial connectivity (dead directed
// links, deaf, mute, a flaky link), COOPERATIVE among the robots the
// connectivity rule keeps. These are the tables of docs/protocol.md,
// "Measured"; the figures are deterministic (fixed seeds), so the table
// regenerates exactly.
//
// Every run: builtin:idle, 50 ms radio rounds, 1 s app rounds, F = 2K,
// robots on a 1 m grid; three seeds per cell, figures pooled over them.
//
// Usage: bench_lab_sync_table [--quick]   (--quick: 10 robots, one seed, 30 s runs)
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace {

using namespace syrof::lab;

struct Cell {
  int64_t starts = 0;
  int64_t cooperative_starts = 0;
  int64_t epochs = 0;
  int64_t mixed_epochs = 0;
  int64_t skew_sum_x_epochs = 0;  // mean skew times epochs, summed
  double skew_sum = 0;
  int64_t max_skew = 0;
  int64_t max_disagreement = 0;
  int64_t violations = 0;
  int64_t kept_starts = 0;              // starts of the robots in `kept` (partial connectivity)
  int64_t kept_cooperative_starts = 0;
};

std::string Scenario(int robots, int k, const std::string& channel, const std::string& faults, double duration_s,
                     uint64_t seed, const std::string& app = "builtin:idle") {
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(robots))));
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
timing: {{radio_round_s: 0.05, app_round_s: 1.0, vote_rounds: {k}, silence_rounds: {f}, duration_s: {duration}}}
channel: {channel}
app: {app}
{faults})",
                     fmt::arg("seed", seed), fmt::arg("arena", arena_m), fmt::arg("robots", robots), fmt::arg("k", k), fmt::arg("f", 2 * k),
                     fmt::arg("duration", duration_s), fmt::arg("channel", channel), fmt::arg("faults", faults),
                     fmt::arg("app", app));
}

void Add(Cell& cell, const std::string& text, const std::vector<int>& kept = {}) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "bench");
  if (!loaded.ok()) {
    fmt::print(stderr, "bench scenario refused: {}\n{}\n", loaded.error->ToString(), text);
    std::exit(1);
  }
  const sim::RunReport report = sim::Run(*loaded.scenario, sim::SimulationOptions{}, 0.0);
  const metrics::Metrics& metrics = report.metrics;
  const metrics::CommonKnowledgeMetrics& knowledge = metrics.common_knowledge;
  const metrics::SynchronyMetrics& synchrony = metrics.synchrony;
  cell.starts += metrics.epoch_starts;
  cell.cooperative_starts += knowledge.cooperative_starts;
  const int64_t epochs = synchrony.epochs_measured;
  cell.epochs += epochs;
  cell.mixed_epochs += knowledge.mixed_mode_epochs;
  if (synchrony.mean_start_skew_rounds) {
    cell.skew_sum += *synchrony.mean_start_skew_rounds * static_cast<double>(epochs);
  }
  cell.max_skew = std::max(cell.max_skew, synchrony.max_start_skew_rounds);
  cell.max_disagreement = std::max(cell.max_disagreement, knowledge.max_mode_disagreement_rounds);
  cell.violations += knowledge.violations;
  for (const int robot : kept) {
    cell.kept_starts += knowledge.starts_by_robot.at(static_cast<size_t>(robot));
    cell.kept_cooperative_starts += knowledge.cooperative_starts_by_robot.at(static_cast<size_t>(robot));
  }
}

void PrintRow(const std::string& label, int robots, int k, const Cell& cell) {
  const double cooperative = cell.starts > 0 ? 100.0 * cell.cooperative_starts / cell.starts : 0;
  const double mixed = cell.epochs > 0 ? 100.0 * cell.mixed_epochs / cell.epochs : 0;
  const double mean_skew = cell.epochs > 0 ? cell.skew_sum / cell.epochs : 0;
  fmt::print("| {} | {} | {} | {:.1f} % | {:.2f} | {} | {:.1f} % | {} | {} |\n", label, robots, k, cooperative, mean_skew,
             cell.max_skew, mixed, cell.max_disagreement, cell.violations);
}

void PrintHeader() {
  fmt::print("| channel | robots | K | COOPERATIVE starts | mean skew (rounds) | max skew | mixed-mode epochs | "
             "longest disagreement (rounds) | P3 violations |\n");
  fmt::print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const double duration_s = quick ? 30 : 120;
  const std::vector<uint64_t> seeds = quick ? std::vector<uint64_t>{1} : std::vector<uint64_t>{1, 2, 3};
  const std::vector<int> sizes = quick ? std::vector<int>{10} : std::vector<int>{10, 50};
  const std::vector<int> ks = {2, 3, 5, 8};
  struct Channel {
    std::string label;
    std::string yaml;
  };
  const std::vector<Channel> channels = {
      {"i.i.d. 0 %", "{model: iid, loss: 0}"},
      {"i.i.d. 10 %", "{model: iid, loss: 0.1}"},
      {"i.i.d. 20 %", "{model: iid, loss: 0.2}"},
      {"i.i.d. 40 %", "{model: iid, loss: 0.4}"},
      {"i.i.d. 60 %", "{model: iid, loss: 0.6}"},
      {"bursty (GE 0.05/0.3, 1 %/90 %)",
       "{model: gilbert_elliott, good_to_bad: 0.05, bad_to_good: 0.3, loss_good: 0.01, loss_bad: 0.9}"},
  };

  fmt::print("synchronizer in the simulated lab: {} s runs, seeds", duration_s);
  for (const uint64_t seed : seeds) fmt::print(" {}", seed);
  fmt::print(" pooled; builtin:idle, alpha = 50 ms, app round 1 s, F = 2K\n\n");
  PrintHeader();
  for (const Channel& channel : channels) {
    for (const int robots : sizes) {
      for (const int k : ks) {
        Cell cell;
        for (const uint64_t seed : seeds) Add(cell, Scenario(robots, k, channel.yaml, "", duration_s, seed));
        PrintRow(channel.label, robots, k, cell);
      }
    }
  }

  fmt::print("\nfaults, K = 3, i.i.d. 5 % loss, 10 robots\n\n");
  PrintHeader();
  struct Fault {
    std::string label;
    std::string yaml;
  };
  const std::vector<Fault> faults = {
      {"robot 2 deaf 10-60 s", "faults: [{deaf: 2, at_s: 10, until_s: 60}]\n"},
      {"robot 2 mute 10-60 s", "faults: [{mute: 2, at_s: 10, until_s: 60}]\n"},
      {"robot 2 paused 5 rounds, every 10 s",
       "faults: [{pause: 2, at_s: 10, until_s: 10.25}, {pause: 2, at_s: 20, until_s: 20.25}, "
       "{pause: 2, at_s: 30, until_s: 30.25}, {pause: 2, at_s: 40, until_s: 40.25}]\n"},
      {"robot 2 paused 2 s at 10 s", "faults: [{pause: 2, at_s: 10, until_s: 12}]\n"},
  };
  for (const Fault& fault : faults) {
    Cell cell;
    for (const uint64_t seed : seeds) {
      Add(cell, Scenario(10, 3, "{model: iid, loss: 0.05}", fault.yaml, std::max(duration_s, 60.0), seed));
    }
    PrintRow(fault.label, 10, 3, cell);
  }

  fmt::print("\npartial connectivity, K = 3, i.i.d. 5 % loss, 60 s, {} seeds; COOPERATIVE starts of the robots the "
             "connectivity rule keeps (those that hear each other both ways), and of all\n\n",
             quick ? 2 : 10);
  fmt::print("| case | robots | kept | COOPERATIVE starts, kept robots | COOPERATIVE starts, all | P3 violations |\n");
  fmt::print("| --- | --- | --- | --- | --- | --- |\n");
  struct Partial {
    std::string label;
    int robots;
    std::string channel;
    std::string faults;
    std::vector<int> kept;
    std::string app = "builtin:idle";
  };
  const std::string base = "{model: iid, loss: 0.05";
  const std::vector<Partial> partials = {
      {"every link alive", 8, base + "}", "", {0, 1, 2, 3, 4, 5, 6, 7}},
      {"robot 5 never hears robot 3", 8, base + ", links: [{from: 3, to: 5, loss: 1.0}]}", "", {0, 1, 2, 3, 4, 6, 7}},
      {"robot 3 never hears robot 5", 8, base + ", links: [{from: 5, to: 3, loss: 1.0}]}", "", {0, 1, 2, 3, 4, 6, 7}},
      {"every link alive", 10, base + "}", "", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}},
      {"1 never hears 6, 8 never hears 2", 10,
       base + ", links: [{from: 6, to: 1, loss: 1.0}, {from: 2, to: 8, loss: 1.0}]}", "", {0, 1, 2, 3, 4, 5, 7, 9}},
      {"6 deaf and 2 mute 10-40 s, 1 to 4 at 90 % loss", 8, base + ", links: [{from: 1, to: 4, loss: 0.9}]}",
       "faults: [{deaf: 6, at_s: 10, until_s: 40}, {mute: 2, at_s: 10, until_s: 40}]\n", {0, 1, 3, 5, 7}},
      {"leader_follow, every link alive", 6, base + "}", "", {0, 1, 2, 3, 4, 5}, "builtin:leader_follow"},
      {"leader_follow, leader mute 15-35 s", 6, base + "}", "faults: [{mute: 0, at_s: 15, until_s: 35}]\n",
       {1, 2, 3, 4, 5}, "builtin:leader_follow"},
  };
  const int partial_seeds = quick ? 2 : 10;
  for (const Partial& partial : partials) {
    Cell cell;
    for (int seed = 1; seed <= partial_seeds; ++seed) {
      Add(cell, Scenario(partial.robots, 3, partial.channel, partial.faults, 60, static_cast<uint64_t>(seed), partial.app),
          partial.kept);
    }
    std::string kept;
    for (const int robot : partial.kept) kept += (kept.empty() ? "" : " ") + std::to_string(robot);
    fmt::print("| {} | {} | {} | {:.1f} % | {:.1f} % | {} |\n", partial.label, partial.robots,
               partial.kept.size() == static_cast<size_t>(partial.robots) ? std::string("all") : kept,
               cell.kept_starts > 0 ? 100.0 * cell.kept_cooperative_starts / cell.kept_starts : 0,
               cell.starts > 0 ? 100.0 * cell.cooperative_starts / cell.starts : 0, cell.violations);
  }
  return 0;
}
