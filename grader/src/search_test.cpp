// A search test of an assignment (docs/grading.md, "Search tests"): the
// student's library under every loss pattern, or every SSYNC schedule,
// within the test's budget (lab/search), scored all or nothing.
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <utility>

#include "syrof/app_host/app_supply.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/search/search.h"
#include "run_scenario.h"

namespace syrof::grader::internal {
namespace {

namespace fs = std::filesystem;

std::string Plural(int64_t count, const char* word) {
  return fmt::format("{} {}{}", count, word, count == 1 ? "" : "s");
}

std::string PatternText(const std::vector<lab::world::LostBeacon>& lost) {
  if (lost.empty()) return "without any lost beacon (the loss-free run)";
  std::string text = "by " + Plural(static_cast<int64_t>(lost.size()), "lost beacon") + " [round, sender, receiver]:";
  for (const lab::world::LostBeacon& beacon : lost) {
    text += fmt::format(" [{}, {}, {}]", beacon.round, beacon.from, beacon.to);
  }
  return text;
}

std::string ScheduleText(const std::vector<lab::search::Inactivation>& inactive) {
  if (inactive.empty()) return "with every robot active (FSYNC)";
  std::string text =
      "by a schedule leaving " + Plural(static_cast<int64_t>(inactive.size()), "robot-epoch") + " out [epoch: robot]:";
  for (const lab::search::Inactivation& left_out : inactive) {
    text += fmt::format(" [{}: {}]", left_out.epoch, left_out.robot);
  }
  return text;
}

std::string CyclesText(const std::vector<sync::ScriptedCycle>& cycles) {
  if (cycles.empty()) return "with every cycle one epoch long (FSYNC)";
  std::string text = "by a schedule with " + Plural(static_cast<int64_t>(cycles.size()), "deviating cycle") +
                     " [look epoch, robot, start_delay, move_epochs(, cut)]:";
  for (const sync::ScriptedCycle& cycle : cycles) {
    text += fmt::format(" [{}, {}, {}, {}{}]", cycle.epoch, cycle.robot, cycle.start_delay, cycle.move_epochs,
                        cycle.cut ? ", 1" : "");
  }
  return text;
}

// What the test searched, in the reasons' words. `max_delay` and
// `min_move_m` are the ASYNC search's, the scenario's where the test gives
// none.
std::string BudgetText(const assignment::SearchTestSpec& spec, int max_delay, double min_move_m) {
  if (!spec.activations) {
    return fmt::format("pattern of up to {} in the first {}", Plural(spec.max_losses, "lost beacon"),
                       Plural(spec.epochs, "epoch"));
  }
  if (spec.async) {
    std::string text = "ASYNC schedule";
    if (spec.max_deviations > 0) text += fmt::format(" of up to {}", Plural(spec.max_deviations, "deviating cycle"));
    text += fmt::format(" in the first {} with delays up to {}", Plural(spec.epochs, "epoch"),
                        Plural(max_delay, "epoch"));
    if (min_move_m > 0) text += fmt::format(", moves cut at {} m", min_move_m);
    return text;
  }
  std::string text = "SSYNC schedule";
  if (spec.max_inactive > 0) text += fmt::format(" of up to {} out", Plural(spec.max_inactive, "robot-epoch"));
  text += fmt::format(" in the first {}", Plural(spec.epochs, "epoch"));
  if (spec.fair_within > 0) {
    text += fmt::format(" that leaves no robot out of {} in a row", Plural(spec.fair_within, "epoch"));
  }
  return text;
}

}  // namespace

void RunSearchTest(const assignment::SearchTestSpec& spec, const std::string& library,
                   const std::string& shown_library, const std::string& out_dir, bool fork_server,
                   assignment::TestResult& test) {
  // The library in the scenario's place, as `syrof search --app` puts it, so
  // the counterexample's file names it and reruns the same.
  lab::scenario::Overrides overrides;
  overrides.app = library;
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(spec.path, overrides);
  if (!loaded.ok()) {
    test.run_error = "the scenario does not load: " + loaded.error->ToString();
    return;
  }
  const lab::scenario::Scenario& scenario = *loaded.scenario;
  app_host::AppRequest request;
  request.libraries = {library};
  request.shown_libraries = {shown_library};
  // Loaded once for the whole search; each run's robots are copies of it
  // (the fork server, docs/app_host.md), unless a bench or test asks for
  // fresh hosts. This thread outlives the search.
  request.load_once = fork_server;
  app_host::AppsResult apps = app_host::AppsFor(scenario, request);
  if (!apps.ok()) {
    test.run_error = "the app cannot be set up: " + apps.error->ToString();
    return;
  }
  lab::search::SearchOptions options;
  options.max_losses = spec.max_losses;
  options.activations = spec.activations;
  if (spec.max_inactive > 0) options.max_inactive = spec.max_inactive;
  options.fair_within = spec.fair_within;
  const bool scenario_async = scenario.activation.model == sync::ActivationModel::kAsync;
  const int max_delay = spec.max_delay > 0 ? spec.max_delay : scenario_async ? scenario.activation.max_delay_epochs : 0;
  const double min_move_m = spec.min_move_m >= 0 ? spec.min_move_m : scenario_async ? scenario.activation.min_move_m : 0;
  if (spec.async) {
    options.activation_model = sync::ActivationModel::kAsync;
    options.max_delay_epochs = spec.max_delay;
    if (spec.min_move_m >= 0) options.min_move_m = spec.min_move_m;
    if (spec.max_deviations > 0) options.max_deviations = spec.max_deviations;
  }
  options.epochs = spec.epochs;
  options.jobs = 1;  // the grader's workers already run tests side by side
  options.time_limit_s = spec.time_limit_s;
  options.apps = std::move(apps.supply);
  const lab::search::SearchResult result = lab::search::Search(scenario, options);
  test.wall_seconds = result.seconds;

  assignment::CriterionScore score;
  score.criterion = "search";
  score.max_points = spec.points;
  const std::string budget = BudgetText(spec, max_delay, min_move_m);
  if (!result.error.empty()) {
    test.run_error = "the search could not start: " + result.error;
    return;
  }
  if (result.stopped_by_time) {
    test.run_error = fmt::format("the search took longer than its time limit of {} s (wall clock) and was stopped "
                                 "after {}",
                                 spec.time_limit_s, Plural(result.runs, "run"));
    return;
  }
  if (!result.counterexample) {
    score.points = spec.points;
    score.reason = fmt::format("no {} broke it ({})", budget, Plural(result.runs, "run"));
  } else {
    const lab::search::Counterexample& found = *result.counterexample;
    score.points = 0;
    score.reason = "broken " +
                   (spec.async         ? CyclesText(found.cycles)
                    : spec.activations ? ScheduleText(found.inactive)
                                       : PatternText(found.lost)) +
                   ":";
    for (size_t i = 0; i < found.violations.size(); ++i) {
      score.reason += fmt::format("{} {}: {}", i == 0 ? "" : ";", found.violations[i].property,
                                  found.violations[i].detail);
    }
    const fs::path dir = fs::path(out_dir) / test.output_dir;
    std::error_code error;
    fs::create_directories(dir, error);
    const lab::search::CounterexampleSource source{spec.path, library, std::nullopt};
    if (const std::optional<lab::Error> problem =
            lab::search::WriteCounterexample(dir.string(), scenario, source, found, options)) {
      score.reason += " (the counterexample could not be written: " + problem->ToString() + ")";
    } else {
      test.replay_path = test.output_dir + "/replay";
    }
  }
  test.score.criteria.push_back(score);
  test.score.points = score.points;
  test.score.max_points = score.max_points;
}

}  // namespace syrof::grader::internal
