// Search tests' figures (docs/apps.md, "Search tests"): loss patterns run
// per second by lab/search at 3 and 4 robots, every single lost beacon in
// the first epoch of a 4 s scenario, three ways:
//   - builtin:idle in the lab, 1 and 2 jobs;
//   - bench_app.c linked in (CAbiApp), 1 job (its statics are shared, so
//     never on two threads);
//   - bench_app.c as a library through the app host (a process per robot
//     per run), 1 and 2 jobs;
// and what an exhaustive search of every pair of lost beacons in 6 epochs
// at 3 robots would take at the measured in-process rate (--full runs it).
// Wall-clock figures: they move with the machine's load.
//
// Usage: bench_search [--full]
#include <fmt/format.h>

#include <cstring>
#include <memory>
#include <string>

#include "syrof/app/c_abi_app.h"
#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/search/search.h"

extern "C" const syrof_app_descriptor* bench_app_entry(void);

namespace {

using namespace syrof;

lab::scenario::Scenario Scenario(int robots, double duration_s) {
  const std::string text = fmt::format(
      "name: search_bench\nseed: 1\nrobots: {{count: {}, spacing_m: 1.0}}\ntiming: {{duration_s: {}}}\n"
      "app: builtin:idle\n",
      robots, duration_s);
  lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioText(text, "search_bench.yaml");
  if (!loaded.ok()) {
    fmt::print(stderr, "bench_search: {}\n", loaded.error->ToString());
    std::exit(1);
  }
  return *loaded.scenario;
}

enum class Way { kBuiltin, kLinked, kHosted };

const char* Name(Way way) {
  switch (way) {
    case Way::kBuiltin:
      return "builtin:idle, in the lab";
    case Way::kLinked:
      return "bench_app.c linked in";
    case Way::kHosted:
      return "bench_app.c through the app host";
  }
  return "";
}

lab::search::SearchResult Measure(const lab::scenario::Scenario& scenario, Way way, int jobs, int max_losses,
                                  int epochs) {
  lab::search::SearchOptions options;
  options.max_losses = max_losses;
  options.epochs = epochs;
  options.jobs = jobs;
  if (way == Way::kLinked) {
    options.app_factory = [](uint16_t) { return std::make_unique<app::CAbiApp>(*bench_app_entry()); };
    options.app_source = "bench_app (linked)";
  } else if (way == Way::kHosted) {
    app_host::HostOptions host;
    host.library_path = SYROF_BENCH_APP_LIBRARY;
    options.app_factory = [host](uint16_t id) { return app_host::MakeHostedApp(host, id); };
    options.app_source = SYROF_BENCH_APP_LIBRARY;
  }
  return lab::search::Search(scenario, options);
}

}  // namespace

int main(int argc, char** argv) {
  const bool full = argc > 1 && std::strcmp(argv[1], "--full") == 0;
  fmt::print("Every single lost beacon in the first epoch of a 4 s run (patterns per second, wall clock):\n");
  fmt::print("  {:<36} {:>6} {:>4} {:>9} {:>8} {:>12} {:>10}\n", "app", "robots", "jobs", "patterns", "seconds",
             "patterns/s", "ms/pattern");
  for (const int robots : {3, 4}) {
    const lab::scenario::Scenario scenario = Scenario(robots, 4.0);
    for (const auto& [way, jobs] : {std::pair{Way::kBuiltin, 1}, std::pair{Way::kBuiltin, 2},
                                    std::pair{Way::kLinked, 1}, std::pair{Way::kHosted, 1},
                                    std::pair{Way::kHosted, 2}}) {
      const lab::search::SearchResult result = Measure(scenario, way, jobs, 1, 1);
      const double rate = result.seconds > 0 ? static_cast<double>(result.runs) / result.seconds : 0.0;
      fmt::print("  {:<36} {:>6} {:>4} {:>9} {:>8.2f} {:>12.0f} {:>10.2f}{}\n", Name(way), robots, jobs, result.runs,
                 result.seconds, rate, rate > 0 ? 1000.0 / rate : 0.0,
                 result.counterexample ? "  (stopped at a counterexample)" : "");
    }
  }

  // Every pair of lost beacons in 6 epochs at 3 robots, builtin:idle, 2 jobs.
  const lab::scenario::Scenario six = Scenario(3, 9.0);
  lab::search::SearchResult sample = Measure(six, Way::kBuiltin, 2, 0, 6);  // the window and its slots
  const int64_t patterns = lab::search::PatternCount(sample.slots, 2);
  const lab::search::SearchResult rate_run = Measure(six, Way::kBuiltin, 2, 1, 6);
  const double rate = static_cast<double>(rate_run.runs) / rate_run.seconds;
  fmt::print("\nEvery pair of lost beacons in 6 epochs at 3 robots (a 9 s run, builtin:idle, 2 jobs):\n");
  fmt::print("  window {} radio rounds ({} epochs), {} slots, {} patterns; at {:.0f} patterns/s: {:.1f} min\n",
             sample.window_rounds, sample.epochs_in_window, sample.slots, patterns, rate,
             static_cast<double>(patterns) / rate / 60.0);
  if (full) {
    const lab::search::SearchResult all = Measure(six, Way::kBuiltin, 2, 2, 6);
    fmt::print("  ran it: {} patterns in {:.1f} min ({}), {}\n", all.runs, all.seconds / 60.0,
               all.stopped_by_time ? "stopped by time" : "complete",
               all.counterexample ? "a counterexample" : "no counterexample");
  }
  return 0;
}
