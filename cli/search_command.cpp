#include "search_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "syrof/app_host/app_supply.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/search/search.h"
#include "syrof/lab/view/view.h"
#include "usage.h"
#include "view_command.h"

namespace syrof::cli {
namespace {

namespace scenario = lab::scenario;
namespace search = lab::search;

// What the pruning of states seen (docs/apps.md, "Search tests") spared.
void PrintPruning(std::ostream& out, const search::SearchResult& result) {
  if (result.round_starts == 0) return;
  const int64_t ran = result.runs - result.skipped - result.stopped_early;
  fmt::print(out,
             "  states: {} distinct at {} round starts; of the runs, {} skipped and {} stopped early at a state seen "
             "before, {} run to the end\n",
             result.distinct_states, result.round_starts, result.skipped, result.stopped_early, ran);
  if (result.pruning_checked == 0) return;
  if (result.pruning_mismatches == 0) {
    fmt::print(out, "  pruning checked: all {} pruned patterns end as the patterns they stood for\n",
               result.pruning_checked);
  } else {
    fmt::print(out, "  PRUNING WRONG for {} of {} pruned patterns; the first: {}\n", result.pruning_mismatches,
               result.pruning_checked, result.first_mismatch);
  }
}

void PrintViolations(std::ostream& out, const std::vector<search::Violation>& violations) {
  for (const search::Violation& violation : violations) {
    fmt::print(out, "  broken: {}: {}\n", violation.property, violation.detail);
  }
}

// The library's search options from the command's.
search::SearchOptions SearchOptionsFor(const SearchOptions& options) {
  search::SearchOptions search_options;
  search_options.max_losses = std::max(options.max_losses, 0);
  search_options.activations = !options.activations.empty();
  if (options.max_inactive > 0) search_options.max_inactive = options.max_inactive;
  search_options.fair_within = options.fair_within;
  if (options.activations == "async") {
    search_options.activation_model = sync::ActivationModel::kAsync;
    if (options.max_deviations > 0) search_options.max_deviations = options.max_deviations;
    search_options.max_delay_epochs = options.max_delay;
    search_options.min_move_m = options.min_move_m;
  }
  search_options.epochs = options.epochs;
  search_options.jobs = options.jobs;
  search_options.time_limit_s = options.time_limit_s;
  search_options.prune = !options.no_prune;
  search_options.check_pruning = options.check_pruning;
  return search_options;
}

// What a search's lines call what it chooses: a lost beacon, an inactive
// robot-epoch or a deviating cycle, and a pattern or a schedule.
struct Words {
  const char* unit;
  const char* units;
  const char* tried;
};

Words WordsOf(bool async, bool activations) {
  return {async ? "deviating cycle" : activations ? "inactive robot-epoch" : "lost beacon",
          async ? "deviating cycles" : activations ? "inactive robot-epochs" : "losses",
          activations ? "schedule" : "pattern"};
}

// The line that says what the search tries.
void PrintPlan(std::ostream& out, const SearchOptions& options, const scenario::Scenario& scenario, bool async,
               bool activations) {
  // The bounds the ASYNC search runs under, as it resolves them.
  const bool scenario_async = scenario.activation.model == sync::ActivationModel::kAsync;
  const int max_delay = options.max_delay > 0 ? options.max_delay : scenario.activation.max_delay_epochs;
  const double min_move_m = options.min_move_m.value_or(scenario_async ? scenario.activation.min_move_m : 0.0);
  if (async) {
    fmt::print(out,
               "  ASYNC schedules of the first {} epoch{}: start delays up to {} epoch{}, moves up to {} epochs{}; "
               "fewest deviating cycles (other than a one-epoch uncut move) and earliest first\n",
               options.epochs, options.epochs == 1 ? "" : "s", max_delay, max_delay == 1 ? "" : "s", max_delay + 1,
               min_move_m > 0 ? fmt::format(", cut once they covered {} m", min_move_m) : std::string(", rigid"));
  } else if (activations) {
    fmt::print(out, "  SSYNC schedules of the first {} epoch{}, fewest inactive robot-epochs and earliest first{}\n",
               options.epochs, options.epochs == 1 ? "" : "s",
               options.fair_within > 0 ? fmt::format("; no robot left out of {} epochs in a row", options.fair_within)
                                       : std::string());
  } else {
    fmt::print(out, "  patterns of up to {} lost beacon{} in the first {} epoch{}, fewest and earliest first\n",
               options.max_losses, options.max_losses == 1 ? "" : "s", options.epochs, options.epochs == 1 ? "" : "s");
  }
}

// The window the loss-free run set, and how many patterns it holds.
void PrintWindow(std::ostream& out, const SearchOptions& options, const search::SearchResult& result, bool async,
                 bool activations) {
  if (result.complete_losses < 0) return;
  if (async) {
    fmt::print(out, "  window: {} radio rounds ({} epoch{} of the run with every robot active), {} robot-epochs; {} "
                    "schedules{}\n",
               result.window_rounds, result.epochs_in_window, result.epochs_in_window == 1 ? "" : "s", result.slots,
               result.patterns_in_all,
               options.max_deviations > 0 ? fmt::format(" of at most {} deviating cycle{}", options.max_deviations,
                                                        options.max_deviations == 1 ? "" : "s")
                                          : std::string());
  } else if (activations) {
    fmt::print(out, "  window: {} radio rounds ({} epoch{} of the run with every robot active), {} robot-epochs; {} "
                    "schedules{}\n",
               result.window_rounds, result.epochs_in_window, result.epochs_in_window == 1 ? "" : "s", result.slots,
               result.patterns_in_all, options.fair_within > 0 ? " before the fairness bound" : "");
  } else {
    fmt::print(out, "  window: {} radio rounds ({} epoch{} of the loss-free run), {} beacon slots; {} patterns in all\n",
               result.window_rounds, result.epochs_in_window, result.epochs_in_window == 1 ? "" : "s", result.slots,
               search::PatternCount(result.slots, options.max_losses));
  }
}

// A search that found nothing: how far it went.
void PrintNothingBroke(std::ostream& out, const SearchOptions& options, const search::SearchResult& result,
                       const Words& words) {
  const double rate = result.seconds > 0 ? static_cast<double>(result.runs) / result.seconds : 0.0;
  if (result.stopped_by_time) {
    fmt::print(out, "no {} broke it before the time limit: {} run{} in {:.1f} s ({:.0f} a second); every "
                    "{} of up to {} {}{} was tried\n",
               words.tried, result.runs, result.runs == 1 ? "" : "s", result.seconds, rate, words.tried,
               result.complete_losses, words.unit, result.complete_losses == 1 ? "" : "s");
  } else {
    fmt::print(out, "no {} broke it: {} {} run{} in {:.1f} s ({:.0f} a second)\n", words.tried,
               result.runs == 1 ? "its" : "all", result.runs, result.runs == 1 ? "" : "s", result.seconds, rate);
  }
  fmt::print(out, "  {} distinct outcome{} (runs whose metrics differ); the {} fell in the first {} epoch{}\n",
             result.distinct_outcomes, result.distinct_outcomes == 1 ? "" : "s", words.units, result.epochs_in_window,
             result.epochs_in_window == 1 ? "" : "s");
  if (result.not_schedules > 0) {
    fmt::print(out, "  {} pattern{} left an epoch with no active robot{} and did not run\n", result.not_schedules,
               result.not_schedules == 1 ? "" : "s", options.fair_within > 0 ? " or were unfair" : "");
  }
  PrintPruning(out, result);
}

// The BROKEN line: the pattern or schedule that broke the app.
void PrintFound(std::ostream& out, const search::Counterexample& found, bool async, bool activations) {
  if (activations && found.inactive.empty() && found.cycles.empty()) {
    fmt::print(out, "BROKEN with every robot active (FSYNC)\n");
  } else if (async) {
    fmt::print(out,
               "BROKEN by a schedule with {} deviating cycle{} ([look epoch, robot, start_delay, move_epochs(, "
               "cut)]):",
               found.cycles.size(), found.cycles.size() == 1 ? "" : "s");
    for (const sync::ScriptedCycle& cycle : found.cycles) {
      fmt::print(out, " [{}, {}, {}, {}{}]", cycle.epoch, cycle.robot, cycle.start_delay, cycle.move_epochs,
                 cycle.cut ? ", 1" : "");
    }
    fmt::print(out, "\n");
  } else if (activations) {
    fmt::print(out, "BROKEN by a schedule leaving {} robot-epoch{} out ([epoch: robot]):", found.inactive.size(),
               found.inactive.size() == 1 ? "" : "s");
    for (const search::Inactivation& left_out : found.inactive) {
      fmt::print(out, " [{}: {}]", left_out.epoch, left_out.robot);
    }
    fmt::print(out, "\n");
  } else if (found.lost.empty()) {
    fmt::print(out, "BROKEN without any lost beacon (the loss-free run)\n");
  } else {
    fmt::print(out, "BROKEN by {} lost beacon{} ([round, sender, receiver]):", found.lost.size(),
               found.lost.size() == 1 ? "" : "s");
    for (const lab::world::LostBeacon& beacon : found.lost) {
      fmt::print(out, " [{}, {}, {}]", beacon.round, beacon.from, beacon.to);
    }
    fmt::print(out, "\n");
  }
}

}  // namespace

CLI::App* SetupSearchCommand(CLI::App& app, SearchOptions& options) {
  CLI::App* command = app.add_subcommand(
      "search", "Search test: run a scenario under every pattern of up to F lost beacons; show one that breaks it");
  command->add_option("scenario", options.scenario_path, "Scenario file (YAML, docs/scenarios.md)")->required();
  command->add_option("--max-losses", options.max_losses, "Most beacons a pattern loses (F; required unless --activations)")
      ->check(CLI::Range(0, search::kMaxSearchLosses));
  command->add_option("--activations", options.activations,
                      "Search activation schedules instead of losses: ssync or async (docs/activation.md)");
  command->add_option("--max-inactive", options.max_inactive,
                      "With --activations: most robot-epochs a schedule leaves out (default: every schedule)")
      ->check(CLI::Range(1, search::kMaxSearchInactive));
  command->add_option("--fair-within", options.fair_within,
                      "With --activations: no robot left out of this many epochs in a row (default: no bound)")
      ->check(CLI::Range(1, search::kMaxSearchEpochs));
  command->add_option("--max-deviations", options.max_deviations,
                      "With --activations async: most cycles other than a one-epoch uncut move (default: every schedule)")
      ->check(CLI::Range(1, search::kMaxSearchDeviations));
  command->add_option("--max-delay", options.max_delay,
                      "With --activations async: the delay bound D in epochs (default: the scenario's max_delay_epochs)")
      ->check(CLI::Range(1, static_cast<int>(sync::kMaxAsyncDelayEpochs)));
  command->add_option("--min-move", options.min_move_m,
                      "With --activations async: cut moves once they covered this many metres; 0 rigid (default: the "
                      "scenario's min_move_m)")
      ->check(CLI::Range(0.0, 30.0));
  command->add_option("--epochs", options.epochs, "The losses (with --activations, the schedules) fall in the run's first E epochs (default 3)")
      ->check(CLI::Range(1, search::kMaxSearchEpochs));
  command->add_option("--jobs", options.jobs, "Runs side by side (default 1); the result does not depend on it")
      ->check(CLI::Range(1, search::kMaxSearchJobs));
  command->add_option("--time-limit", options.time_limit_s, "Stop after this many seconds of wall time (default: none)")
      ->check(CLI::Range(0.0, 7.0 * 86400));
  command->add_option("--app", options.app, "App to run instead of the scenario's: builtin:NAME or your library's path");
  command->add_option("--seed", options.seed, "Seed instead of the scenario's");
  command->add_option("--duration", options.duration_s, "Simulated seconds of each run instead of the scenario's")
      ->check(DurationValidator());
  command->add_option("--out", options.out_dir, "Output folder (default: out/<scenario name>-search)");
  command->add_flag("--quiet", options.quiet, "No progress line");
  command->add_flag("--no-prune", options.no_prune, "Run every pattern to its end (no pruning of states seen)");
  command->add_flag("--check-pruning", options.check_pruning,
                    "Self-test: rerun each pruned pattern to its end against the pattern it stood for");
  return command;
}

// The flags that go together: losses or activations, and the activation
// search's own flags only with it. Nothing when they do.
std::optional<lab::Error> CheckSearchFlags(const SearchOptions& options) {
  auto refused = [](std::string message) { return lab::Error{.where = "", .message = std::move(message)}; };
  if (options.activations.empty()) {
    if (options.max_losses < 0) return refused("--max-losses is required (or --activations ssync to search schedules)");
    if (options.max_inactive >= 0) return refused("--max-inactive applies to --activations only");
    if (options.fair_within > 0) return refused("--fair-within applies to --activations only");
    if (options.max_deviations >= 0 || options.max_delay > 0 || options.min_move_m) {
      return refused("--max-deviations, --max-delay and --min-move apply to --activations async only");
    }
    return std::nullopt;
  }
  if (options.activations != "ssync" && options.activations != "async") {
    return refused("--activations must be ssync or async, not '" + options.activations + "'");
  }
  if (options.max_losses >= 0) {
    return refused("--max-losses and --activations do not combine yet: search losses or schedules, one at a time");
  }
  if (options.activations == "async") {
    if (options.max_inactive >= 0) {
      return refused("--max-inactive applies to --activations ssync only (async: --max-deviations)");
    }
    if (options.fair_within > 0) return refused("--fair-within applies to --activations ssync only");
    return std::nullopt;
  }
  if (options.max_deviations >= 0 || options.max_delay > 0 || options.min_move_m) {
    return refused("--max-deviations, --max-delay and --min-move apply to --activations async only");
  }
  if (options.fair_within > options.epochs) {
    return refused(fmt::format("--fair-within {} is more than the {} epochs searched (--epochs)",
                               options.fair_within, options.epochs));
  }
  return std::nullopt;
}

int RunSearchCommand(const SearchOptions& options, std::ostream& out, std::ostream& err, bool err_is_terminal) {
  if (const std::optional<lab::Error> problem = CheckSearchFlags(options)) {
    fmt::print(err, "syrof search: {}\n", problem->ToString());
    return 2;
  }
  scenario::Overrides overrides;
  overrides.app = options.app;
  overrides.seed = options.seed;
  overrides.duration_s = options.duration_s;
  const std::string scenario_file = ScenarioArgument(options.scenario_path, "search", err, options.quiet);
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(scenario_file, overrides);
  if (!loaded.ok()) {
    fmt::print(err, "syrof search: {}\n", loaded.error->ToString());
    return 2;
  }
  scenario::Scenario scenario = *loaded.scenario;
  const bool async = options.activations == "async";
  if (async && options.max_delay == 0 && scenario.activation.model != sync::ActivationModel::kAsync) {
    fmt::print(err,
               "syrof search: --activations async needs a delay bound: {}'s activation is {}, so give --max-delay D "
               "(1 .. {} epochs), or search a scenario with activation.model async and its max_delay_epochs\n",
               options.scenario_path, sync::ToString(scenario.activation.model), sync::kMaxAsyncDelayEpochs);
    return 2;
  }
  if (scenario.app.is_library()) {
    // As the counterexample's file names it (absolute, to run from any
    // folder), so that its rerun's metrics.json is the search's run's.
    scenario.app.library = std::filesystem::absolute(scenario.app.library).lexically_normal().string();
    scenario.app.name = scenario.app.library;
  }
  search::SearchOptions search_options = SearchOptionsFor(options);
  // A library is checked once before the search, as `syrof run` does, then
  // loaded once in a held host: each run's robots are copies of it (the
  // fork server, docs/app_host.md), not hosts started afresh.
  app_host::AppRequest request;
  request.check_first = true;
  request.load_once = true;
  app_host::AppsResult apps = app_host::AppsFor(scenario, request);
  if (!apps.ok()) {
    fmt::print(err, "syrof search: {}\n", apps.error->ToString());
    return 2;
  }
  search_options.apps = std::move(apps.supply);
  const std::filesystem::path dir = options.out_dir.empty()
                                        ? std::filesystem::path("out") / (scenario.name + "-search")
                                        : std::filesystem::path(options.out_dir);
  std::error_code error;
  const bool dir_existed = std::filesystem::exists(dir, error);
  std::filesystem::create_directories(dir, error);
  if (error) {
    fmt::print(err, "syrof search: cannot create output folder {}: {}\n", dir.string(), error.message());
    return 2;
  }
  // An earlier search's counterexample would pass for this one's.
  for (const char* name : {"counterexample.yaml", "replay", "metrics.json", "replay.html"}) {
    std::filesystem::remove(dir / name, error);
  }

  fmt::print(out, "syrof search: {} ({}), {} robots, seed {}, {:.1f} s a run\n", scenario.name, scenario.app.name,
             scenario.robots.size(), scenario.seed, scenario.timing.duration_s);
  if (search_options.apps.sandbox) {
    for (const std::string& note : *search_options.apps.sandbox) fmt::print(out, "  sandbox: {}\n", note);
  }
  const Words words = WordsOf(async, search_options.activations);
  PrintPlan(out, options, scenario, async, search_options.activations);
  if (!options.quiet && err_is_terminal) {
    search_options.progress = [&err, unit = words.unit](int64_t runs, int losses) {
      fmt::print(err, "\r  {} runs, now {} {}{}   ", runs, losses, unit, losses == 1 ? "" : "s");
      err.flush();
    };
  }
  const search::SearchResult result = search::Search(scenario, search_options);
  if (search_options.progress) fmt::print(err, "\n");
  if (!result.error.empty()) {
    fmt::print(err, "syrof search: {}\n", result.error);
    if (!dir_existed) std::filesystem::remove(dir, error);  // nothing written: only if still empty
    return 2;
  }
  PrintWindow(out, options, result, async, search_options.activations);
  if (!result.counterexample) {
    PrintNothingBroke(out, options, result, words);
    return result.pruning_mismatches > 0 ? 1 : 0;
  }

  const search::Counterexample& found = *result.counterexample;
  const std::filesystem::path yaml_path = dir / "counterexample.yaml";
  const search::CounterexampleSource source{scenario_file, options.app, options.duration_s};
  if (const std::optional<lab::Error> problem =
          search::WriteCounterexample(dir.string(), scenario, source, found, search_options)) {
    fmt::print(err, "syrof search: {}\n", problem->ToString());
    for (const search::Violation& violation : found.violations) {
      fmt::print(err, "  the pattern's own run broke {}: {}\n", violation.property, violation.detail);
    }
    return 1;
  }
  lab::view::PageOptions page_options;  // the banner says what broke, and the lost beacons
  page_options.metrics = found.metrics;
  // The run the page shows: under the schedule found, whose left-out
  // robots it marks.
  const scenario::Scenario shown =
      async ? search::WithCycles(scenario, found.cycles, found.max_delay_epochs, found.min_move_m)
      : search_options.activations ? search::WithInactivations(scenario, found.window_epochs, found.inactive)
                                   : scenario;
  page_options.scenario = &shown;
  const std::optional<lab::Error> page_problem =
      WritePage((dir / "replay").string(), (dir / "replay.html").string(), page_options);

  PrintFound(out, found, async, search_options.activations);
  PrintViolations(out, found.violations);
  fmt::print(out, "  after {} run{} ({} distinct outcome{}) in {:.1f} s; every {} of fewer {} passed\n", result.runs,
             result.runs == 1 ? "" : "s", result.distinct_outcomes, result.distinct_outcomes == 1 ? "" : "s",
             result.seconds, words.tried, words.units);
  PrintPruning(out, result);
  fmt::print(out, "  written: {} (with replay, metrics.json{})\n", yaml_path.string(),
             page_problem ? "" : ", replay.html");
  fmt::print(out, "  rerun:   syrof run {} --out {}\n", yaml_path.string(), (dir / "rerun").string());
  fmt::print(out, "  view:    syrof view {}\n", (dir / "replay").string());
  return 1;
}

}  // namespace syrof::cli
