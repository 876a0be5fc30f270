// Search tests (lab/search): an app that fails in an AUTONOMOUS epoch is
// broken by the smallest loss pattern that leaves a robot out, and the
// search finds it, the same with one job or two; a correct app survives the
// same search; the counterexample replays exactly as a scripted channel.
// With the default K = 3 vote rounds no pattern of 2 losses in 2 epochs
// leaves a robot out of 3 (50,722 runs), so these scenarios vote for one
// round (K = 1, F = 2), where one loss can.
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/search/search.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::search {
namespace {

scenario::Scenario LoadText(const std::string& text) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// Holds still; its global state is the epoch number. With `breaks` it has
// the student's bug of assuming every epoch is COOPERATIVE: it fails in an
// AUTONOMOUS one, which only a loss pattern that leaves a robot out makes.
class CountingApp final : public app::App {
 public:
  explicit CountingApp(bool breaks) : drifts_(breaks) {}
  const char* name() const override { return "counting_test"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform&, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command&, const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t) override {
    if (drifts_ && ldmap.mode == SYROF_MODE_AUTONOMOUS) {
      return app::CallStatus::Fault(app::Verdict::kAppError, "assumed a COOPERATIVE epoch");
    }
    global_state = static_cast<uint8_t>(ldmap.epoch);
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }

 private:
  bool drifts_;
};

const char* const kThree =
    "seed: 3\nrobots: {count: 3, spacing_m: 1.0}\ntiming: {duration_s: 4, vote_rounds: 1, silence_rounds: 2}\nchannel: {model: iid, loss: 0.2}\n"
    "app: builtin:idle\n";

SearchOptions OptionsFor(bool drifts, int max_losses, int jobs) {
  SearchOptions options;
  options.max_losses = max_losses;
  options.epochs = 2;
  options.jobs = jobs;
  options.apps.factory = [drifts](uint16_t) { return std::make_unique<CountingApp>(drifts); };
  options.apps.source = "test:counting";
  return options;
}

TEST(SearchTest, FindsTheSmallestEarliestPatternThatBreaksAnAppAssumingCooperation) {
  const scenario::Scenario scenario = LoadText(kThree);
  const SearchResult result = Search(scenario, OptionsFor(/*drifts=*/true, 2, 1));
  ASSERT_TRUE(result.counterexample.has_value()) << result.runs << " runs";
  const Counterexample& found = *result.counterexample;
  ASSERT_FALSE(found.lost.empty());
  ASSERT_FALSE(found.violations.empty());
  EXPECT_EQ(found.violations.front().property, "app fault");
  // Every pattern of fewer losses passed: the search finished those sizes.
  EXPECT_EQ(result.complete_losses, static_cast<int>(found.lost.size()) - 1);
  // The loss-free run, then patterns in order: the found one is the last run.
  EXPECT_GT(result.runs, 1);
}

TEST(SearchTest, TheResultDoesNotDependOnTheJobs) {
  const scenario::Scenario scenario = LoadText(kThree);
  const SearchResult one = Search(scenario, OptionsFor(true, 2, 1));
  const SearchResult two = Search(scenario, OptionsFor(true, 2, 2));
  ASSERT_TRUE(one.counterexample && two.counterexample);
  EXPECT_EQ(one.counterexample->lost, two.counterexample->lost);
  EXPECT_EQ(metrics::ToJson(one.counterexample->metrics), metrics::ToJson(two.counterexample->metrics));
  EXPECT_EQ(one.runs, two.runs);
  EXPECT_EQ(one.distinct_outcomes, two.distinct_outcomes);
}

TEST(SearchTest, TheCounterexampleReplaysExactlyAsAScriptedChannel) {
  const scenario::Scenario scenario = LoadText(kThree);
  SearchOptions options = OptionsFor(true, 2, 1);
  const SearchResult result = Search(scenario, options);
  ASSERT_TRUE(result.counterexample.has_value());
  sim::SimulationOptions sim_options;
  sim_options.apps.factory = options.apps.factory;
  sim_options.apps.source = options.apps.source;
  const sim::RunReport again = sim::Run(WithLosses(scenario, result.counterexample->lost), sim_options, 0);
  EXPECT_EQ(again.metrics_json, metrics::ToJson(result.counterexample->metrics));
  // One loss fewer (the last dropped) no longer breaks it.
  std::vector<world::LostBeacon> fewer = result.counterexample->lost;
  fewer.pop_back();
  const sim::RunReport smaller = sim::Run(WithLosses(scenario, fewer), sim_options, 0);
  EXPECT_TRUE(ViolationsOf(smaller.metrics, false).empty());
}

TEST(SearchTest, AnAppFollowingTheEpochSurvivesTheSameSearch) {
  const scenario::Scenario scenario = LoadText(kThree);
  const SearchResult result = Search(scenario, OptionsFor(/*drifts=*/false, 1, 2));
  EXPECT_FALSE(result.counterexample.has_value()) << result.counterexample->violations.front().detail;
  EXPECT_EQ(result.complete_losses, 1);
  EXPECT_EQ(result.runs, 1 + result.slots);
  EXPECT_GT(result.slots, 0);
  // Some single losses change the run (an epoch starts AUTONOMOUS), many
  // change nothing the metrics see.
  EXPECT_GE(result.distinct_outcomes, 2);
  EXPECT_LT(result.distinct_outcomes, result.runs);
}

TEST(SearchTest, SlotsLeaveOutBeaconsTheScenarioAlreadyLoses) {
  // Robot 2 crashes at 0.5 s: after round 10 it sends and hears nothing, so
  // only the 6 links of rounds 0..9 and then 0 <-> 1 are slots.
  const scenario::Scenario scenario = LoadText(
      "seed: 3\nrobots: {count: 3, spacing_m: 1.0}\ntiming: {duration_s: 3}\napp: builtin:idle\n"
      "faults: [{crash: 2, at_s: 0.5}]\n");
  SearchOptions options = OptionsFor(false, 0, 1);
  options.epochs = 1;
  const SearchResult result = Search(scenario, options);
  ASSERT_GT(result.window_rounds, 10);
  EXPECT_EQ(result.slots, 10 * 6 + (result.window_rounds - 10) * 2);
  EXPECT_EQ(result.runs, 1);  // F = 0: the loss-free run only
}

// A scripted channel once ignored the scenario's links, so a search ran a
// dead link alive: a swarm that never hears robot 2 at robot 0 looked whole.
TEST(SearchTest, ADeadLinkStaysDeadAndIsNoSlot) {
  const char* text =
      "seed: 3\nrobots: {count: 3, spacing_m: 1.0}\ntiming: {duration_s: 3}\napp: builtin:idle\n"
      "channel: {model: iid, loss: 0.0, links: [{from: 2, to: 0, loss: 1.0}]}\n";
  const scenario::Scenario scenario = LoadText(text);
  SearchOptions options = OptionsFor(false, 0, 1);
  options.epochs = 1;
  const SearchResult result = Search(scenario, options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  EXPECT_EQ(result.slots, result.window_rounds * 5);  // 6 directed links, one dead
}

TEST(SearchTest, ALinkWithRandomLossIsRefused) {
  const scenario::Scenario scenario = LoadText(
      "seed: 3\nrobots: {count: 3, spacing_m: 1.0}\ntiming: {duration_s: 3}\napp: builtin:idle\n"
      "channel: {model: iid, loss: 0.0, links: [{from: 2, to: 0, loss: 0.3}]}\n");
  const SearchResult result = Search(scenario, OptionsFor(false, 1, 1));
  EXPECT_NE(result.error.find("channel link 2 -> 0 loses 0.3 of its beacons at random"), std::string::npos)
      << result.error;
  EXPECT_EQ(result.runs, 0);
}

// Pruning states seen (search.h) changes how much is run, never what is
// found: the same counterexample, and without one the same patterns passed.
TEST(SearchTest, PruningFindsWhatRunningEveryPatternFinds) {
  const scenario::Scenario scenario = LoadText(kThree);
  SearchOptions pruned = OptionsFor(true, 2, 1);
  SearchOptions every = pruned;
  every.prune = false;
  const SearchResult a = Search(scenario, pruned);
  const SearchResult b = Search(scenario, every);
  ASSERT_TRUE(a.counterexample && b.counterexample);
  EXPECT_EQ(a.counterexample->lost, b.counterexample->lost);
  EXPECT_EQ(metrics::ToJson(a.counterexample->metrics), metrics::ToJson(b.counterexample->metrics));
  EXPECT_EQ(a.runs, b.runs);
  EXPECT_EQ(b.skipped + b.stopped_early + b.round_starts + b.distinct_states, 0);
}

TEST(SearchTest, PruningStopsRunsAtStatesSeenAndSkipsWhatExtendsThem) {
  const scenario::Scenario scenario = LoadText(kThree);
  SearchOptions options = OptionsFor(false, 2, 1);
  options.epochs = 1;
  const SearchResult result = Search(scenario, options);
  ASSERT_FALSE(result.counterexample.has_value());
  EXPECT_EQ(result.complete_losses, 2);
  EXPECT_EQ(result.runs, PatternCount(result.slots, 2));
  // Most single losses are forgotten within a few rounds: their runs stop
  // there, and every pair that adds a later loss to one is never run.
  EXPECT_GT(result.stopped_early, result.slots / 2);
  EXPECT_GT(result.skipped, result.runs / 2);
  EXPECT_LT(result.distinct_states, result.round_starts);
}

TEST(SearchTest, PrunedFiguresDoNotDependOnTheJobs) {
  const scenario::Scenario scenario = LoadText(kThree);
  SearchOptions one = OptionsFor(false, 2, 1);
  one.epochs = 1;
  SearchOptions two = one;
  two.jobs = 2;
  const SearchResult a = Search(scenario, one);
  const SearchResult b = Search(scenario, two);
  EXPECT_EQ(a.runs, b.runs);
  EXPECT_EQ(a.skipped, b.skipped);
  EXPECT_EQ(a.stopped_early, b.stopped_early);
  EXPECT_EQ(a.distinct_states, b.distinct_states);
  EXPECT_EQ(a.round_starts, b.round_starts);
  EXPECT_EQ(a.distinct_outcomes, b.distinct_outcomes);
}

// The self-test of the pruning: every pattern pruned, run to its end, ends
// in the state of the pattern it stood for and breaks what that one breaks.
// On swarms that move (the safety filter and the estimator then see each
// loss), with a joiner and a crash, and with an app that counts epochs.
void ExpectPruningHolds(const std::string& text, const SearchOptions& base, int max_losses, int epochs) {
  SearchOptions options = base;
  options.max_losses = max_losses;
  options.epochs = epochs;
  options.check_pruning = true;
  const SearchResult result = Search(LoadText(text), options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  EXPECT_GT(result.pruning_checked, 0) << text;
  EXPECT_EQ(result.pruning_mismatches, 0) << result.first_mismatch;
}

TEST(SearchTest, EveryPrunedPairEndsAsThePatternItStoodFor) {
  // Pairs of losses, in a shorter run of kThree's swarm.
  ExpectPruningHolds(
      "seed: 3\nrobots: {count: 3, spacing_m: 1.0}\ntiming: {duration_s: 2, app_round_s: 0.3, vote_rounds: 1, silence_rounds: 2}\n"
      "app: builtin:idle\n",
      OptionsFor(false, 0, 1), 2, 1);
}

TEST(SearchTest, EveryPrunedPatternOfAMovingSwarmWithAJoinerEndsAsThePatternItStoodFor) {
  ExpectPruningHolds(
      "seed: 5\nrobots: {count: 3, placement: circle, radius_m: 0.8}\n"
      "timing: {duration_s: 5, vote_rounds: 1, silence_rounds: 2}\napp: builtin:gather\n"
      "faults: [{join: 2, at_s: 0.8}]\n",
      SearchOptions{}, 1, 3);
}

TEST(SearchTest, EveryPrunedPatternOfACircleWithACrashEndsAsThePatternItStoodFor) {
  ExpectPruningHolds(
      "seed: 6\narena: {width_m: 5, height_m: 5}\nrobots: {count: 4, placement: circle, radius_m: 1.2}\n"
      "timing: {duration_s: 4, vote_rounds: 1}\napp: builtin:circle\nfaults: [{crash: 3, at_s: 1.5}]\n",
      SearchOptions{}, 1, 2);
}

TEST(SearchTest, PatternCountsAddUpBinomials) {
  EXPECT_EQ(PatternCount(10, 0), 1);
  EXPECT_EQ(PatternCount(10, 1), 11);
  EXPECT_EQ(PatternCount(10, 2), 1 + 10 + 45);
  EXPECT_EQ(PatternCount(3, 5), 8);  // every subset
  EXPECT_EQ(PatternCount(int64_t{1} << 40, 8), INT64_MAX);
}

// ---- The activation search (SSYNC schedules, search.h) ----

// Holds still; its global state counts its own newRound calls: the same on
// every robot under FSYNC, and one behind on a robot an SSYNC schedule left
// out of an epoch, which the agreement check sees in the next epoch all
// run.
class TurnCountingApp final : public app::App {
 public:
  const char* name() const override { return "turn_counting_test"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform&, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command&, const syrof_ldmap&, uint8_t& global_state, uint32_t) override {
    ++global_state;
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }
};

const char* const kThreeClean =
    "seed: 3\nrobots: {count: 3, spacing_m: 1.0}\ntiming: {duration_s: 4}\napp: builtin:idle\n";

SearchOptions ActivationOptions(std::function<std::unique_ptr<app::App>(uint16_t)> factory, int epochs, int jobs) {
  SearchOptions options;
  options.activations = true;
  options.epochs = epochs;
  options.jobs = jobs;
  options.apps.factory = std::move(factory);
  options.apps.source = "test:activation";
  return options;
}

std::unique_ptr<app::App> TurnCounting(uint16_t) { return std::make_unique<TurnCountingApp>(); }
std::unique_ptr<app::App> EpochFollowing(uint16_t) { return std::make_unique<CountingApp>(false); }

TEST(ActivationSearchTest, FindsTheSmallestEarliestScheduleThatBreaksAnAppCountingItsTurns) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  for (const int jobs : {1, 2}) {
    const SearchResult result = Search(scenario, ActivationOptions(TurnCounting, 3, jobs));
    ASSERT_TRUE(result.error.empty()) << result.error;
    ASSERT_TRUE(result.counterexample.has_value()) << result.runs << " runs";
    const Counterexample& found = *result.counterexample;
    EXPECT_TRUE(found.lost.empty());
    // One robot left out of one epoch is enough, and the first such
    // pattern (the first epoch, the lowest id) already breaks it.
    ASSERT_EQ(found.inactive.size(), 1u);
    ASSERT_FALSE(found.window_epochs.empty());
    EXPECT_EQ(found.inactive[0].epoch, found.window_epochs[0].epoch);
    EXPECT_EQ(found.inactive[0].robot, found.window_epochs[0].members[0]);
    EXPECT_EQ(result.complete_losses, 0);
    EXPECT_EQ(result.runs, 2);  // every robot active, then the first pattern
    ASSERT_FALSE(found.violations.empty());
    EXPECT_EQ(found.violations.front().property, "agreement");
  }
}

TEST(ActivationSearchTest, TheCounterexampleReplaysAsAScriptedSchedule) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  const SearchOptions options = ActivationOptions(TurnCounting, 3, 1);
  const SearchResult result = Search(scenario, options);
  ASSERT_TRUE(result.counterexample.has_value());
  const Counterexample& found = *result.counterexample;
  const scenario::Scenario again = WithInactivations(scenario, found.window_epochs, found.inactive);
  EXPECT_EQ(again.activation.model, sync::ActivationModel::kSsync);
  EXPECT_EQ(again.activation.schedule, sync::ActivationSchedule::kScripted);
  // The listed epoch activates the others; nothing else is listed.
  ASSERT_EQ(again.activation.script.size(), found.window_epochs[0].members.size() - 1);
  for (const sync::ScriptedActivation& entry : again.activation.script) {
    EXPECT_EQ(entry.epoch, found.inactive[0].epoch);
    EXPECT_NE(entry.robot, found.inactive[0].robot);
  }
  sim::SimulationOptions sim_options;
  sim_options.apps.factory = options.apps.factory;
  sim_options.apps.source = options.apps.source;
  EXPECT_EQ(sim::Run(again, sim_options, 0).metrics_json, metrics::ToJson(found.metrics));
  // Every robot active: FSYNC, and nothing breaks.
  const sim::RunReport fsync = sim::Run(WithInactivations(scenario, found.window_epochs, {}), sim_options, 0);
  EXPECT_TRUE(ViolationsOf(fsync.metrics, false).empty());
}

// Every schedule of 3 robots over 3 epochs: 7^3 = 343 with the one every
// robot is active in; 169 of the 512 subsets of the 9 robot-epochs leave an
// epoch empty, 123 of them with at most 6 robot-epochs (the largest a
// schedule can leave out).
TEST(ActivationSearchTest, AnAppFollowingTheEpochSurvivesEveryScheduleOfThreeRobotsOverThreeEpochs) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  SearchOptions options = ActivationOptions(EpochFollowing, 3, 2);
  const SearchResult result = Search(scenario, options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  EXPECT_FALSE(result.counterexample.has_value()) << result.counterexample->violations.front().detail;
  EXPECT_EQ(result.slots, 9);
  EXPECT_EQ(result.patterns_in_all, 343);
  EXPECT_EQ(result.runs, 343);
  EXPECT_EQ(result.not_schedules, 123);
  EXPECT_EQ(result.complete_losses, 6);
  // Each schedule calls the apps differently: none is pruned.
  EXPECT_EQ(result.skipped + result.stopped_early + result.round_starts, 0);
}

// The fairness bound: no robot left out of fair_within epochs in a row.
// Counted here by brute force over the 512 subsets.
TEST(ActivationSearchTest, AFairnessBoundRunsOnlyTheFairSchedules) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  int64_t fair = 0;
  for (int subset = 0; subset < 512; ++subset) {
    auto out = [&](int epoch, int robot) { return ((subset >> (epoch * 3 + robot)) & 1) != 0; };
    bool ok = true;
    for (int epoch = 0; epoch < 3; ++epoch) ok = ok && !(out(epoch, 0) && out(epoch, 1) && out(epoch, 2));
    for (int robot = 0; robot < 3; ++robot) {
      ok = ok && !(out(0, robot) && out(1, robot)) && !(out(1, robot) && out(2, robot));
    }
    fair += ok ? 1 : 0;
  }
  SearchOptions options = ActivationOptions(EpochFollowing, 3, 1);
  options.fair_within = 2;
  const SearchResult result = Search(scenario, options);
  ASSERT_FALSE(result.counterexample.has_value());
  EXPECT_EQ(result.runs, fair);
  EXPECT_EQ(result.runs - 1 + result.not_schedules, PatternCount(9, 6) - 1);
  options.fair_within = 1;  // nobody may be left out
  EXPECT_EQ(Search(scenario, options).runs, 1);
}



// The built-in moving apps under every SSYNC schedule of 3 robots over 3
// epochs (lab/scenarios/gather3.yaml's swarm): none breaks P3, agreement,
// the no-collision rule or the app. `syrof apps` and docs/activation.md
// give the longer searches (gather over 6 epochs: bench_search --full).
TEST(ActivationSearchTest, TheBuiltInMovingAppsSurviveEveryScheduleOfThreeRobotsOverThreeEpochs) {
  for (const char* app : {"gather", "circle", "leader_follow"}) {
    const scenario::Scenario scenario = LoadText(
        std::string("seed: 5\nrobots: {count: 3, placement: circle, radius_m: 0.8}\ntiming: {duration_s: 8}\napp: builtin:") +
        app + "\n");
    SearchOptions options;
    options.activations = true;
    options.epochs = 3;
    options.jobs = 2;
    const SearchResult result = Search(scenario, options);
    ASSERT_TRUE(result.error.empty()) << result.error;
    EXPECT_FALSE(result.counterexample.has_value())
        << app << ": " << result.counterexample->violations.front().property << ": "
        << result.counterexample->violations.front().detail;
    EXPECT_EQ(result.runs, 343) << app;
    // The schedules do change what the robots do.
    EXPECT_GT(result.distinct_outcomes, 100) << app;
  }
}

// The ASYNC schedule search (docs/activation.md, "The schedule search"):
// cycle timings instead of inactive robot-epochs.
SearchOptions AsyncOptions(std::function<std::unique_ptr<app::App>(uint16_t)> factory, int epochs, int jobs) {
  SearchOptions options = ActivationOptions(std::move(factory), epochs, jobs);
  options.activation_model = sync::ActivationModel::kAsync;
  options.max_delay_epochs = 1;
  return options;
}

bool SameCycle(const sync::ScriptedCycle& a, const sync::ScriptedCycle& b) {
  return a.epoch == b.epoch && a.robot == b.robot && a.start_delay == b.start_delay &&
         a.move_epochs == b.move_epochs && a.cut == b.cut;
}

// A robot whose first move lasts two epochs skips its look of the second:
// it counts one turn fewer than the others when it looks again. The first
// schedule of one deviating cycle (the first look of the lowest id, the
// shortest cycle) breaks the agreement; the FSYNC run does not.
TEST(AsyncSearchTest, FindsTheSmallestEarliestScheduleThatBreaksAnAppCountingItsTurns) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  for (const int jobs : {1, 2}) {
    const SearchResult result = Search(scenario, AsyncOptions(TurnCounting, 3, jobs));
    ASSERT_TRUE(result.error.empty()) << result.error;
    ASSERT_TRUE(result.counterexample.has_value()) << result.runs << " runs";
    const Counterexample& found = *result.counterexample;
    EXPECT_TRUE(found.inactive.empty());
    ASSERT_EQ(found.cycles.size(), 1u);
    ASSERT_FALSE(found.window_epochs.empty());
    const sync::ScriptedCycle expected{found.window_epochs[0].epoch, found.window_epochs[0].members[0], 0, 2, false};
    EXPECT_TRUE(SameCycle(found.cycles[0], expected))
        << found.cycles[0].epoch << " " << found.cycles[0].robot << " " << int{found.cycles[0].start_delay} << " "
        << int{found.cycles[0].move_epochs};
    EXPECT_EQ(found.max_delay_epochs, 1);
    EXPECT_EQ(result.complete_losses, 0);
    EXPECT_EQ(result.runs, 2);  // the FSYNC run, then the first schedule
    EXPECT_EQ(result.slots, 9);  // 3 robots, 3 epochs
    ASSERT_FALSE(found.violations.empty());
    EXPECT_EQ(found.violations.front().property, "agreement");
  }
}

TEST(AsyncSearchTest, TheCounterexampleReplaysAsAScriptedAsyncSchedule) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  const SearchOptions options = AsyncOptions(TurnCounting, 3, 1);
  const SearchResult result = Search(scenario, options);
  ASSERT_TRUE(result.counterexample.has_value());
  const Counterexample& found = *result.counterexample;
  const scenario::Scenario again = WithCycles(scenario, found.cycles, found.max_delay_epochs, found.min_move_m);
  EXPECT_EQ(again.activation.model, sync::ActivationModel::kAsync);
  EXPECT_EQ(again.activation.schedule, sync::ActivationSchedule::kScripted);
  EXPECT_EQ(again.activation.max_delay_epochs, 1);
  ASSERT_EQ(again.activation.cycles.size(), 1u);
  sim::SimulationOptions sim_options;
  sim_options.apps.factory = options.apps.factory;
  sim_options.apps.source = options.apps.source;
  EXPECT_EQ(sim::Run(again, sim_options, 0).metrics_json, metrics::ToJson(found.metrics));
  const sim::RunReport fsync = sim::Run(WithCycles(scenario, {}, 1, 0), sim_options, 0);
  EXPECT_TRUE(ViolationsOf(fsync.metrics, false).empty());
}

// The counts, by hand. One robot over 2 epochs, D = 1, rigid: the cycles
// other than FSYNC's are (0, 2), (1, 1) (2 epochs each) and (1, 2) (3); a
// deviating first look holds the second epoch, so the robot has 1 + 3 + 3
// = 7 schedules (the FSYNC one, a deviating first look, a deviating second
// look), one of them with no deviation and none with two: 3 robots,
// (1 + 6x)^3 = 1 + 18x + 108x^2 + 216x^3, 343 in all (19 with at most one
// deviation, 127 with at most two). With cuts (min_move_m > 0) there are 7
// choices, (0, 1, cut) of 1 epoch, four of 2, two of 3: from the second
// look on 1 + 7x, from the first (1 + 7x) + x ((1 + 7x) + 6) = 1 + 14x +
// 7x^2 (FSYNC's first cycle; a cut one-epoch one, then any second; one of
// 2 epochs or more), 22 a robot, 22^3 = 10,648.
TEST(AsyncSearchTest, ScheduleCountsMatchTheHandCount) {
  std::vector<WindowEpoch> two{{1, 0, {0, 1, 2}}, {2, 20, {0, 1, 2}}};
  EXPECT_EQ(AsyncChoices(1, false).size(), 3u);
  EXPECT_EQ(AsyncChoices(1, true).size(), 7u);
  EXPECT_EQ(AsyncChoices(2, true).size(), 17u);  // 3 delays x 3 moves x 2 - 1
  EXPECT_EQ(AsyncScheduleCount(two, 1, false, 6), 343);
  EXPECT_EQ(AsyncScheduleCount(two, 1, false, 1), 19);
  EXPECT_EQ(AsyncScheduleCount(two, 1, false, 2), 127);
  EXPECT_EQ(AsyncScheduleCount(two, 1, true, 6), 10648);
  const std::vector<WindowEpoch> one{{1, 0, {0, 1, 2}}};
  EXPECT_EQ(AsyncScheduleCount(one, 2, true, 6), 18 * 18 * 18);
  // The shortest first: a cut one-epoch move, then (0, 2), (0, 2, cut), (1, 1), ...
  const std::vector<sync::AsyncCycle> choices = AsyncChoices(1, true);
  EXPECT_TRUE(choices[0].cut && choices[0].start_delay == 0 && choices[0].move_epochs == 1);
  EXPECT_TRUE(!choices[1].cut && choices[1].start_delay == 0 && choices[1].move_epochs == 2);
  EXPECT_TRUE(choices[6].cut && choices[6].start_delay == 1 && choices[6].move_epochs == 2);
}

// Every schedule of 3 robots over 2 epochs, D = 1 rigid: the 343 counted
// above, each run once; an app following the epoch survives them.
TEST(AsyncSearchTest, AnAppFollowingTheEpochSurvivesEveryScheduleOfThreeRobotsOverTwoEpochs) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  const SearchResult result = Search(scenario, AsyncOptions(EpochFollowing, 2, 2));
  ASSERT_TRUE(result.error.empty()) << result.error;
  EXPECT_FALSE(result.counterexample.has_value()) << result.counterexample->violations.front().detail;
  EXPECT_EQ(result.slots, 6);
  EXPECT_EQ(result.patterns_in_all, 343);
  EXPECT_EQ(result.runs, 343);
  EXPECT_EQ(result.complete_losses, 6);
  EXPECT_EQ(result.skipped + result.stopped_early + result.round_starts, 0);  // nothing pruned
}

// Each schedule the walk lists is a run of its own: every cycle it names
// falls on a look the robot makes (else two schedules would run alike).
// The built-in moving apps on gather3.yaml's swarm move in every epoch, so
// their metrics.json tells every two of the 343 schedules of 2 epochs
// apart; and they survive them (`syrof apps` gives the longer searches).
TEST(AsyncSearchTest, EveryScheduleIsARunOfItsOwnAndTheBuiltInMovingAppsSurviveThem) {
  for (const char* app : {"gather", "circle", "leader_follow"}) {
    const scenario::Scenario scenario = LoadText(
        std::string("seed: 5\nrobots: {count: 3, placement: circle, radius_m: 0.8}\ntiming: {duration_s: 8}\napp: builtin:") +
        app + "\n");
    SearchOptions options;
    options.activations = true;
    options.activation_model = sync::ActivationModel::kAsync;
    options.max_delay_epochs = 1;
    options.epochs = 2;
    options.jobs = 2;
    const SearchResult result = Search(scenario, options);
    ASSERT_TRUE(result.error.empty()) << result.error;
    EXPECT_FALSE(result.counterexample.has_value()) << app << ": " << result.counterexample->violations.front().detail;
    EXPECT_EQ(result.runs, 343) << app;
    EXPECT_EQ(result.distinct_outcomes, 343) << app;
  }
}

// Non-rigid moves add the cut; a deviation bound stops the search early:
// one epoch, at most one deviating cycle, 1 + 3 robots x 7 choices.
TEST(AsyncSearchTest, CutsAreChoicesWhereMovesAreNonRigid) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  SearchOptions options = AsyncOptions(EpochFollowing, 1, 1);
  options.max_deviations = 1;
  options.min_move_m = 0.05;
  const SearchResult result = Search(scenario, options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  EXPECT_FALSE(result.counterexample.has_value());
  EXPECT_EQ(result.patterns_in_all, 22);
  EXPECT_EQ(result.runs, 22);
  options.min_move_m = 0;  // rigid: 1 + 3 x 3
  EXPECT_EQ(Search(scenario, options).runs, 10);
}

// The bound comes from the options or an ASYNC scenario; without either
// the search does not start.
TEST(AsyncSearchTest, ADelayBoundIsNeeded) {
  const scenario::Scenario scenario = LoadText(kThreeClean);
  SearchOptions options = AsyncOptions(EpochFollowing, 1, 1);
  options.max_delay_epochs = 0;
  const SearchResult refused = Search(scenario, options);
  EXPECT_NE(refused.error.find("delay bound"), std::string::npos) << refused.error;
  EXPECT_EQ(refused.runs, 0);
  const scenario::Scenario async = LoadText(std::string(kThreeClean) +
                                            "activation: {model: async, schedule: random, max_delay_epochs: 2}\n");
  options.max_deviations = 1;
  const SearchResult result = Search(async, options);
  ASSERT_TRUE(result.error.empty()) << result.error;
  EXPECT_EQ(result.runs, 1 + 3 * 8);  // D = 2, rigid: 3 x 3 - 1 choices
}

}  // namespace
}  // namespace syrof::lab::search
