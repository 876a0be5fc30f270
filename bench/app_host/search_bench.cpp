// Search tests' figures (docs/apps.md, "Search tests"): loss patterns run
// per second by lab/search at 3 and 4 robots, every single lost beacon in
// the first epoch of a 4 s scenario, three ways:
//   - builtin:idle in the lab, 1 and 2 jobs;
//   - bench_app.c linked in (CAbiApp), 1 job (its statics are shared, so
//     never on two threads);
//   - bench_app.c as a library through the app host (a process per robot
//     per run), 1 and 2 jobs;
//   - the same library through the fork server (loaded once in a held
//     host, each robot of each run a copy of it: LoadOnce), 1 and 2 jobs;
// each with the pruning of states seen (search.h) and without; then every
// pair of lost beacons in the first epoch, the same ways; and every pair in
// 6 epochs at 3 robots with pruning, and what it takes without (--full
// runs that too: about 9 minutes); and every SSYNC schedule of 3 robots
// (PrintSchedules), and every ASYNC one of 3 robots over 3 epochs with
// delays up to 1 (and, with --full, over 2 with cuts). Wall-clock figures: they move with the
// machine's load. "ended" counts the runs that ran to their end; the others
// stopped at a state seen before or were skipped without running.
//
// Usage: bench_search [--full | --schedules | --async | --hosted]
// (--schedules: only the schedule search, SSYNC over 4 and 6 epochs, ASYNC
// rigid and cut; --async: only the ASYNC rows; --hosted: only the rows
// through the app host, fresh hosts and the fork server)
#include <fmt/format.h>

#include <sys/resource.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

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

enum class Way { kBuiltin, kLinked, kHosted, kForked };

const char* Name(Way way) {
  switch (way) {
    case Way::kBuiltin:
      return "builtin:idle, in the lab";
    case Way::kLinked:
      return "bench_app.c linked in";
    case Way::kHosted:
      return "bench_app.c through the app host";
    case Way::kForked:
      return "bench_app.c, app host's fork server";
  }
  return "";
}

lab::search::SearchResult Measure(const lab::scenario::Scenario& scenario, Way way, int jobs, int max_losses,
                                  int epochs, bool prune = true) {
  lab::search::SearchOptions options;
  options.prune = prune;
  options.max_losses = max_losses;
  options.epochs = epochs;
  options.jobs = jobs;
  if (way == Way::kLinked) {
    options.apps.factory = [](uint16_t) { return std::make_unique<app::CAbiApp>(*bench_app_entry()); };
    options.apps.source = "bench_app (linked)";
  } else if (way == Way::kHosted) {
    app_host::HostOptions host;
    host.library_path = SYROF_BENCH_APP_LIBRARY;
    options.apps.factory = [host](uint16_t id) { return app_host::MakeHostedApp(host, id); };
    options.apps.source = SYROF_BENCH_APP_LIBRARY;
  } else if (way == Way::kForked) {
    // Loaded once for the search (its start counted in the search's time
    // only from the first run: it is made here, before the search starts).
    app_host::HostOptions host;
    host.library_path = SYROF_BENCH_APP_LIBRARY;
    std::shared_ptr<app_host::LoadedLibrary> loaded = app_host::LoadOnce(host);
    options.apps.factory = [host, loaded](uint16_t id) { return app_host::MakeHostedApp(host, id, loaded); };
    options.apps.source = SYROF_BENCH_APP_LIBRARY;
  }
  return lab::search::Search(scenario, options);
}

// The schedule search (docs/activation.md): every SSYNC schedule of
// lab/scenarios/gather3.yaml's 3 robots over E epochs, 2 jobs; 7^E
// schedules. E = 4 always, and 6 (117,649) with --full; without it the
// 6-epoch time is the 4-epoch rate applied to 7^6 (a 6-epoch window's runs
// are the same 8 s runs). CPU seconds are the process's (user + system).
double CpuSeconds() {
  struct rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
}

// ASYNC (docs/activation.md, "Under ASYNC"): every timing of the cycles
// that start in gather3.yaml's first epochs, delays up to 1 epoch: rigid
// over 3 epochs (16^3 = 4,096 schedules), and with `cuts` moves cut at 5 cm
// over 2 epochs (22^3 = 10,648).
void PrintAsyncSchedules(const lab::scenario::Scenario& scenario, bool cuts) {
  fmt::print("\nEvery ASYNC schedule of gather3.yaml, delays up to 1 epoch (3 robots, builtin:gather, 2 jobs; wall "
             "clock):\n");
  fmt::print("  {:>6} {:>9} {:>10} {:>10} {:>10} {:>12} {:>14}\n", "epochs", "moves", "schedules", "seconds", "CPU s",
             "schedules/s", "CPU ms/schedule");
  for (const auto& [epochs, min_move_m] : {std::pair{3, 0.0}, std::pair{2, 0.05}}) {
    if (min_move_m > 0 && !cuts) break;
    lab::search::SearchOptions options;
    options.activations = true;
    options.activation_model = sync::ActivationModel::kAsync;
    options.max_delay_epochs = 1;
    options.min_move_m = min_move_m;
    options.epochs = epochs;
    options.jobs = 2;
    const double cpu_before = CpuSeconds();
    const lab::search::SearchResult result = lab::search::Search(scenario, options);
    const double cpu = CpuSeconds() - cpu_before;
    const double async_rate = result.seconds > 0 ? static_cast<double>(result.runs) / result.seconds : 0.0;
    fmt::print("  {:>6} {:>9} {:>10} {:>10.1f} {:>10.1f} {:>12.0f} {:>14.2f}{}\n", epochs,
               min_move_m > 0 ? "cut 5 cm" : "rigid", result.runs, result.seconds, cpu, async_rate,
               result.runs > 0 ? 1000.0 * cpu / static_cast<double>(result.runs) : 0.0,
               result.counterexample ? "  (stopped at a counterexample)" : "");
  }
}

void PrintSchedules(bool full) {
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(SYROF_GATHER3_SCENARIO);
  if (!loaded.ok()) {
    fmt::print(stderr, "bench_search: {}\n", loaded.error->ToString());
    std::exit(1);
  }
  fmt::print("\nEvery SSYNC schedule of gather3.yaml (3 robots, builtin:gather, an 8 s run, 2 jobs; wall clock):\n");
  fmt::print("  {:>6} {:>10} {:>10} {:>10} {:>12} {:>14}\n", "epochs", "schedules", "seconds", "CPU s", "schedules/s",
             "CPU ms/schedule");
  double rate = 0;
  for (const int epochs : {4, 6}) {
    if (epochs == 6 && !full) break;
    lab::search::SearchOptions options;
    options.activations = true;
    options.epochs = epochs;
    options.jobs = 2;
    const double cpu_before = CpuSeconds();
    const lab::search::SearchResult result = lab::search::Search(*loaded.scenario, options);
    const double cpu = CpuSeconds() - cpu_before;
    rate = result.seconds > 0 ? static_cast<double>(result.runs) / result.seconds : 0.0;
    fmt::print("  {:>6} {:>10} {:>10.1f} {:>10.1f} {:>12.0f} {:>14.2f}{}\n", epochs, result.runs, result.seconds, cpu,
               rate, result.runs > 0 ? 1000.0 * cpu / static_cast<double>(result.runs) : 0.0,
               result.counterexample ? "  (stopped at a counterexample)" : "");
  }
  if (!full && rate > 0) {
    fmt::print("  6 epochs (117,649 schedules) at that rate: {:.1f} min (--full runs it)\n", 117649.0 / rate / 60.0);
  }
  PrintAsyncSchedules(*loaded.scenario, full);
}

}  // namespace

void PrintHeader() {
  fmt::print("  {:<36} {:>6} {:>4} {:>5} {:>9} {:>8} {:>8} {:>12} {:>10}\n", "app", "robots", "jobs", "prune",
             "patterns", "ended", "seconds", "patterns/s", "ms/pattern");
}

void PrintRow(Way way, int robots, int jobs, bool prune, const lab::search::SearchResult& result) {
  const double rate = result.seconds > 0 ? static_cast<double>(result.runs) / result.seconds : 0.0;
  // bench_app.c breaks nothing: a counterexample is the machine's (a
  // callback stopped by a cap), so what it broke is printed.
  std::string stopped;
  if (result.counterexample) {
    stopped = "  (stopped at a counterexample";
    if (!result.counterexample->violations.empty()) {
      stopped += ": " + result.counterexample->violations.front().property + ": " +
                 result.counterexample->violations.front().detail;
    }
    stopped += ")";
  }
  fmt::print("  {:<36} {:>6} {:>4} {:>5} {:>9} {:>8} {:>8.2f} {:>12.0f} {:>10.2f}{}\n", Name(way), robots, jobs,
             prune ? "on" : "off", result.runs, result.runs - result.skipped - result.stopped_early, result.seconds,
             rate, rate > 0 ? 1000.0 / rate : 0.0, stopped);
  std::fflush(stdout);
}

int main(int argc, char** argv) {
  const bool full = argc > 1 && std::strcmp(argv[1], "--full") == 0;
  if (argc > 1 && std::strcmp(argv[1], "--async") == 0) {
    const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(SYROF_GATHER3_SCENARIO);
    if (!loaded.ok()) {
      fmt::print(stderr, "bench_search: {}\n", loaded.error->ToString());
      return 1;
    }
    PrintAsyncSchedules(*loaded.scenario, /*cuts=*/true);  // the ASYNC rows alone
    return 0;
  }
  if (argc > 1 && std::strcmp(argv[1], "--schedules") == 0) {
    PrintSchedules(/*full=*/true);  // the schedule search alone, 4 and 6 epochs
    return 0;
  }
  const bool hosted_only = argc > 1 && std::strcmp(argv[1], "--hosted") == 0;
  std::vector<std::pair<Way, int>> ways = {{Way::kBuiltin, 1}, {Way::kBuiltin, 2}, {Way::kLinked, 1}, {Way::kHosted, 1},
                                           {Way::kHosted, 2},  {Way::kForked, 1},  {Way::kForked, 2}};
  if (hosted_only) ways = {{Way::kHosted, 1}, {Way::kHosted, 2}, {Way::kForked, 1}, {Way::kForked, 2}};
  fmt::print("Every single lost beacon in the first epoch of a 4 s run (wall clock):\n");
  PrintHeader();
  for (const int robots : {3, 4}) {
    const lab::scenario::Scenario scenario = Scenario(robots, 4.0);
    for (const auto& [way, jobs] : ways) {
      for (const bool prune : {true, false}) PrintRow(way, robots, jobs, prune, Measure(scenario, way, jobs, 1, 1, prune));
    }
  }
  fmt::print("\nEvery pair of lost beacons in the first epoch of a 4 s run, 3 robots (wall clock):\n");
  PrintHeader();
  const lab::scenario::Scenario three = Scenario(3, 4.0);
  for (const auto& [way, jobs] : ways) {
    if (hosted_only && way == Way::kHosted && jobs == 2) continue;  // about as long as 1 job
    PrintRow(way, 3, jobs, true, Measure(three, way, jobs, 2, 1, true));
    if (way != Way::kHosted && way != Way::kForked) PrintRow(way, 3, jobs, false, Measure(three, way, jobs, 2, 1, false));
  }
  if (hosted_only) return 0;

  // Every pair of lost beacons in 6 epochs at 3 robots, builtin:idle, 2 jobs.
  const lab::scenario::Scenario six = Scenario(3, 9.0);
  const lab::search::SearchResult pruned = Measure(six, Way::kBuiltin, 2, 2, 6, true);
  const int64_t patterns = lab::search::PatternCount(pruned.slots, 2);
  fmt::print("\nEvery pair of lost beacons in 6 epochs at 3 robots (a 9 s run, builtin:idle, 2 jobs):\n");
  fmt::print("  window {} radio rounds ({} epochs), {} slots, {} patterns\n", pruned.window_rounds,
             pruned.epochs_in_window, pruned.slots, patterns);
  fmt::print("  pruned: {:.1f} s ({}), {} skipped, {} stopped early, {} ran to their end; {} distinct states at {} "
             "round starts\n",
             pruned.seconds, pruned.counterexample ? "a counterexample" : "no counterexample", pruned.skipped,
             pruned.stopped_early, pruned.runs - pruned.skipped - pruned.stopped_early, pruned.distinct_states,
             pruned.round_starts);
  const lab::search::SearchResult rate_run = Measure(six, Way::kBuiltin, 2, 1, 6, false);
  const double rate = static_cast<double>(rate_run.runs) / rate_run.seconds;
  fmt::print("  without pruning, at {:.0f} patterns/s: {:.1f} min\n", rate, static_cast<double>(patterns) / rate / 60.0);
  if (full) {
    const lab::search::SearchResult all = Measure(six, Way::kBuiltin, 2, 2, 6, false);
    fmt::print("  ran it without pruning: {} patterns in {:.1f} min ({}), {}\n", all.runs, all.seconds / 60.0,
               all.stopped_by_time ? "stopped by time" : "complete",
               all.counterexample ? "a counterexample" : "no counterexample");
  }
  PrintSchedules(full);
  return 0;
}
