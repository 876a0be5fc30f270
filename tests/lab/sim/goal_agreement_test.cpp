// The engine's goal checks (scenario `goal:`) and app-level agreement, end to
// end: apps whose global state comes from the map agree in every
// COOPERATIVE epoch; apps that put their id or a per-robot random number in
// it are caught at the first COOPERATIVE epoch; declared checks give a
// verdict for any app, built in or supplied.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::sim {
namespace {

using nlohmann::json;

scenario::Scenario LoadText(const std::string& text) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(text, "test.yaml");
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// How a test app computes its global state.
enum class StateRule { kFromMap, kOwnId, kSeededRandom };

// Holds still; its global state follows `rule`.
class StateApp final : public app::App {
 public:
  explicit StateApp(StateRule rule) : rule_(rule) {}
  const char* name() const override { return "state_test"; }
  app::CallStatus Init(const syrof_app_info& info, app::Platform&, uint8_t& global_state) override {
    random_.seed(info.self_id + 1);  // rand() seeded per robot
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command&, const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t) override {
    global_state = Decide(ldmap, global_state);
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t) override {
    global_state = static_cast<uint8_t>(Decide(ldmap, global_state) + 1);
    return app::CallStatus::Ok();
  }

 private:
  uint8_t Decide(const syrof_ldmap& ldmap, uint8_t) {
    switch (rule_) {
      case StateRule::kFromMap: {
        unsigned sum = ldmap.epoch;
        for (uint16_t i = 0; i < ldmap.member_count; ++i) sum += ldmap.members[i].id * 7u + ldmap.members[i].x_mm;
        return static_cast<uint8_t>(sum);
      }
      case StateRule::kOwnId:
        return static_cast<uint8_t>(ldmap.self_id);
      case StateRule::kSeededRandom:
        return static_cast<uint8_t>(random_());
    }
    return 0;
  }
  StateRule rule_;
  std::minstd_rand random_;
};

json RunWith(const scenario::Scenario& scenario, StateRule rule) {
  SimulationOptions options;
  options.apps.factory = [rule](uint16_t) { return std::make_unique<StateApp>(rule); };
  options.apps.source = "test:state_app";
  return json::parse(sim::Run(scenario, options).metrics_json);
}

const char* const kStill =
    "seed: 5\nrobots: {count: 4, placement: grid, spacing_m: 0.6}\ntiming: {duration_s: 10}\napp: builtin:idle\n";

TEST(AgreementEndToEnd, AnAppDecidingFromTheMapAgreesInEveryCooperativeEpoch) {
  const json agreement = RunWith(LoadText(kStill), StateRule::kFromMap)["agreement"];

  EXPECT_GE(agreement["cooperative_epochs"].get<int>(), 5);
  EXPECT_EQ(agreement["agreed_epochs"], agreement["cooperative_epochs"]);
  EXPECT_EQ(agreement["agreed_fraction"], 1.0);
  EXPECT_GT(agreement["end_of_round_calls"].get<int>(), 0);
  EXPECT_TRUE(agreement["first_disagreement"].is_null());
}

TEST(AgreementEndToEnd, AnAppReadingItsIdIntoItsStateIsCaught) {
  const json agreement = RunWith(LoadText(kStill), StateRule::kOwnId)["agreement"];

  EXPECT_EQ(agreement["agreed_epochs"], 0);
  const json& first = agreement["first_disagreement"];
  ASSERT_FALSE(first.is_null());
  EXPECT_EQ(first["callback"], "new_round");
  EXPECT_EQ(first["reference_robot"], 0);
  EXPECT_EQ(first["reference_state"], 0);
  EXPECT_EQ(first["robot"], 1);
  EXPECT_EQ(first["state"], 1);
}

TEST(AgreementEndToEnd, AnAppUsingRandomNumbersIsCaughtAndTheRunStaysDeterministic) {
  const scenario::Scenario scenario = LoadText(kStill);
  const json first = RunWith(scenario, StateRule::kSeededRandom);
  const json second = RunWith(scenario, StateRule::kSeededRandom);

  EXPECT_FALSE(first["agreement"]["first_disagreement"].is_null());
  EXPECT_LT(first["agreement"]["agreed_fraction"].get<double>(), 0.5);
  EXPECT_EQ(first["agreement"], second["agreement"]);
}

TEST(GoalEndToEnd, DeclaredChecksJudgeAnyApp) {
  // A 2 x 2 grid 0.6 m apart around the arena's centre (2, 2), held still.
  const scenario::Scenario scenario = LoadText(std::string(kStill) +
                                           "goal:\n"
                                           "  - check: slots\n"
                                           "    assign: by_id\n"
                                           "    points: [{x_m: 1.7, y_m: 1.7}, {x_m: 2.3, y_m: 1.7}, {x_m: 1.7, y_m: 2.3}, {x_m: 2.3, y_m: 2.3}]\n"
                                           "    tolerance_m: 0.05\n"
                                           "  - {check: gathered, radius_m: 0.3, when: every_epoch, from_s: 2}\n"
                                           "  - {check: shape, points: [{x_m: 0, y_m: 0}, {x_m: 0, y_m: 0.6}, {x_m: 0.6, y_m: 0}, {x_m: 0.6, y_m: 0.6}], tolerance_m: 0.05, deadline_s: 5}\n");

  const json goal = RunWith(scenario, StateRule::kFromMap)["goal"];

  EXPECT_EQ(goal["source"], "scenario");
  EXPECT_FALSE(goal["reached"]);
  ASSERT_EQ(goal["checks"].size(), 3u);
  EXPECT_TRUE(goal["checks"][0]["passed"]) << goal["checks"][0]["reason"];
  EXPECT_FALSE(goal["checks"][1]["passed"]);
  EXPECT_GT(goal["checks"][1]["samples"].get<int>(), 3);
  EXPECT_NE(goal["checks"][1]["reason"].get<std::string>().find("at epoch"), std::string::npos);
  EXPECT_TRUE(goal["checks"][2]["passed"]) << goal["checks"][2]["reason"];
  EXPECT_FALSE(goal["checks"][2]["held_from_epoch"].is_null());
  EXPECT_LE(goal["checks"][2]["held_from_s"].get<double>(), 5.0);
  EXPECT_EQ(goal["detail"].get<std::string>().rfind("2 of 3 checks passed; gathered: ", 0), 0u) << goal["detail"];
}

TEST(GoalEndToEnd, TheBuiltinAppsGatherMeetsADeclaredDeadline) {
  const scenario::Scenario scenario = LoadText(
      "seed: 2\nrobots: {count: 6, placement: random}\ntiming: {duration_s: 60}\napp: builtin:gather\n"
      "goal:\n  - {check: gathered, radius_m: 0.8, deadline_s: 50}\n  - {check: coverage, min_fraction: 0.05}\n");
  SimulationOptions options;
  const json metrics = json::parse(sim::Run(scenario, options).metrics_json);
  const json& goal = metrics["goal"];

  EXPECT_TRUE(goal["reached"]) << goal["detail"];
  EXPECT_FALSE(goal["checks"][0]["held_from_epoch"].is_null());
  EXPECT_GT(goal["checks"][1]["value"].get<double>(), 0.05);
  EXPECT_EQ(metrics["agreement"]["agreed_fraction"], 1.0);
}

}  // namespace
}  // namespace syrof::lab::sim
