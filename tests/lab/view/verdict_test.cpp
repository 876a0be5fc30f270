// lab/view's verdict without a browser: what the banner says of a run's
// metrics, the metrics.json it reads (untrusted), and the goal's target.
#include "syrof/lab/view/verdict.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::view {
namespace {

using nlohmann::json;

metrics::Metrics GoalMet() {
  metrics::Metrics m;
  m.seed = 5;
  m.goal.reached = true;
  m.goal.app = "builtin:circle";
  m.goal.detail = "10 robots on the circle";
  m.agreement.emplace();
  return m;
}

TEST(Verdict, EachBrokenPropertyMakesItBrokenAndIsNamedFirst) {
  metrics::Metrics p3 = GoalMet();
  p3.common_knowledge.violations = 2;
  p3.common_knowledge.first_violations = {{.epoch = 4, .robot = 3, .round = 80, .first_robot = 0}};
  metrics::Metrics collided = GoalMet();
  collided.collisions.count = 1;
  collided.collisions.pairs = {{.time_ns = 4'200'000'000, .a = 1, .b = 2}};
  metrics::Metrics faulted = GoalMet();
  faulted.app.faults = {{.robot = 2, .callback = "new_round", .epoch = 7, .verdict = "timeout", .detail = ""}};

  EXPECT_EQ(VerdictOf(GoalMet(), {}).state, VerdictState::kOk);
  const Verdict p3_verdict = VerdictOf(p3, {});
  EXPECT_EQ(p3_verdict.state, VerdictState::kBroken);
  EXPECT_EQ(p3_verdict.headline,
            "BROKEN: P3 violated in epoch 4: robot 3 started it COOPERATIVE with another map than robot 0 (round 80; 2 "
            "starts in all)");
  EXPECT_EQ(VerdictOf(collided, {}).headline, "BROKEN: 1 collision, the first robots 1 and 2 at 4.20 s");
  EXPECT_EQ(VerdictOf(faulted, {}).headline, "BROKEN: robot 2's app failed in new_round of epoch 7: timeout");
}

TEST(Verdict, ALibraryWithoutADeclaredGoalIsNotHeldToOne) {
  metrics::Metrics m = GoalMet();
  m.goal.app = "/home/student/libmyapp.so";
  m.goal.reached = false;
  m.goal.detail = "not a built-in app";

  const Verdict verdict = VerdictOf(m, {});

  EXPECT_EQ(verdict.state, VerdictState::kOk);
  EXPECT_EQ(verdict.headline, "Nothing broken (no goal declared): no P3 violation, no collision, no app fault");
  EXPECT_EQ(verdict.lines.front().text, "none declared: the scenario has no `goal:`");
}

TEST(Verdict, AReplayAloneIsUnjudgedUnlessItShowsACollisionOrAFault) {
  ReplayFacts quiet;
  ReplayFacts faulted;
  faulted.app_faults = 2;

  const Verdict unjudged = VerdictOfReplay(quiet);

  EXPECT_EQ(unjudged.state, VerdictState::kUnjudged);
  EXPECT_EQ(unjudged.headline.rfind("Not judged here: without the run's metrics", 0), 0u) << unjudged.headline;
  EXPECT_EQ(VerdictOfReplay(faulted).state, VerdictState::kBroken);
  EXPECT_EQ(VerdictOfReplay(faulted).headline, "BROKEN: 2 app faults in the replay");
}

TEST(Verdict, LostBeaconsAreListedAfterWhatBroke) {
  metrics::Metrics m = GoalMet();
  m.goal.reached = false;
  m.goal.detail = "robot 4 is 0.3 m from its point";
  ReplayFacts facts;
  facts.lost = {{23, 0, 1}, {23, 2, 1}};

  const Verdict verdict = VerdictOf(m, facts);

  EXPECT_EQ(verdict.state, VerdictState::kMissed);
  EXPECT_EQ(verdict.headline, "Goal missed: robot 4 is 0.3 m from its point; 2 lost beacons: round 23, 0 → 1; round "
                              "23, 2 → 1");
}

std::optional<metrics::Metrics> Read(const std::string& text, Error& error) {
  std::istringstream in(text);
  return ReadVerdictMetrics(in, "run/metrics.json", error);
}

// A metrics.json with what the verdict reads, `edit` applied.
std::string MetricsText(const std::function<void(json&)>& edit = {}) {
  json root = json::parse(metrics::ToJson(GoalMet()));
  if (edit) edit(root);
  return root.dump();
}

TEST(VerdictMetrics, ReadsWhatToJsonWrites) {
  metrics::Metrics written = GoalMet();
  written.seed = 18'446'744'073'709'551'615u;
  written.agreement->disagreeing_calls = 3;
  written.agreement->first_disagreement =
      metrics::Disagreement{.epoch = 3, .round = 61, .callback = "end_of_round", .robot = 3, .state = 3,
                            .reference_robot = 0, .reference_state = 1};
  Error error;

  const std::optional<metrics::Metrics> read = Read(metrics::ToJson(written), error);

  ASSERT_TRUE(read) << error;
  EXPECT_EQ(read->seed, written.seed);
  EXPECT_EQ(VerdictOf(*read, {}).headline, VerdictOf(written, {}).headline);
  EXPECT_EQ(VerdictOf(*read, {}).headline,
            "BROKEN: agreement split in epoch 3: robot 3 holds 3, robot 0 holds 1 (endOfRound, round 61)");
}

TEST(VerdictMetrics, AMalformedFileIsAnErrorNamingTheField) {
  struct Case {
    std::string text, message;
  };
  const std::vector<Case> cases = {
      {"{", "not JSON (a metrics.json written by `syrof run` was expected)"},
      {"[]", "the file: expected an object"},
      {MetricsText([](json& m) { m["goal"]["reached"] = "yes"; }), "goal.reached: expected true or false"},
      {MetricsText([](json& m) { m.erase("collisions"); }), "collisions: missing"},
      {MetricsText([](json& m) { m["collisions"]["pairs"] = json::array({{{"time_s", 1.0}, {"a", 70000}, {"b", 1}}}); }),
       "collisions.pairs[0].a: 70000 is out of range (0 to 65535)"},
      {MetricsText([](json& m) { m["agreement"]["first_disagreement"] = 3; }),
       "agreement.first_disagreement: expected an object or null"},
      {MetricsText([](json& m) { m["seed"] = -1; }), "seed: expected a whole number from 0 to 2^64 - 1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text.substr(0, 80));
    Error error;
    EXPECT_FALSE(Read(c.text, error));
    EXPECT_EQ(error.where, "run/metrics.json");
    EXPECT_EQ(error.message, c.message);
  }
}

TEST(GoalTargets, EachGeometricCheckHasItsShape) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(
      "name: t\napp: builtin:idle\narena: { width_m: 4, height_m: 4 }\nrobots: { count: 2 }\n"
      "goal:\n"
      "  - { check: circle, radius_min_m: 1.0, radius_max_m: 1.4, centre: { x_m: 2, y_m: 2 } }\n"
      "  - { check: gathered, radius_m: 0.5 }\n"
      "  - { check: slots, points: [ { x_m: 1, y_m: 1 }, { x_m: 3, y_m: 1 } ], assign: by_id, tolerance_m: 0.2 }\n"
      "  - { check: coverage, min_fraction: 0.5, area_min: { x_m: 0.5, y_m: 0.5 }, area_max: { x_m: 3, y_m: 2 } }\n"
      "  - { check: shape, points: [ { x_m: 0, y_m: 0 }, { x_m: 1, y_m: 0 } ] }\n",
      "t.yaml");
  ASSERT_TRUE(loaded.ok()) << *loaded.error;

  const json targets = GoalTargets(*loaded.scenario, 2);

  ASSERT_EQ(targets.size(), 5u) << targets.dump();
  EXPECT_EQ(targets[0], json::parse(R"({"shape": "ring", "name": "circle", "x": 2.0, "y": 2.0, "r_min": 1.0, "r_max": 1.4})"));
  EXPECT_EQ(targets[1]["shape"], "free_ring");
  EXPECT_EQ(targets[2]["points"], json::parse("[[1.0, 1.0, 0], [3.0, 1.0, 1]]"));
  EXPECT_EQ(targets[2]["r"], 0.2);
  EXPECT_EQ(targets[3]["shape"], "rect");
  EXPECT_EQ(targets[3]["x1"], 3.0);
  EXPECT_EQ(targets[4]["shape"], "none");
}

TEST(GoalTargets, ABuiltinCirclesPointsAreTheApps) {
  const scenario::LoadResult loaded =
      scenario::LoadScenarioText("name: c\narena: { width_m: 4, height_m: 4 }\nrobots: { count: 4 }\napp: builtin:circle\n",
                                 "c.yaml");
  ASSERT_TRUE(loaded.ok()) << *loaded.error;

  const json targets = GoalTargets(*loaded.scenario, 3);

  ASSERT_EQ(targets.size(), 2u) << targets.dump();
  EXPECT_EQ(targets[0]["shape"], "ring");
  EXPECT_EQ(targets[1]["points"].size(), 3u);  // the robots running at the end
}

}  // namespace
}  // namespace syrof::lab::view
