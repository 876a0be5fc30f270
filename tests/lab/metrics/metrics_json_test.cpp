// metrics.json read back with nlohmann: fields, types, order, determinism,
// no NaN, and every field documented in docs/metrics.md.
#include <algorithm>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/metrics/metrics.h"

namespace syrof::lab::metrics {
namespace {

using Json = nlohmann::ordered_json;
using wire::Mode;

// A short run touching every metric: two epochs (one with skew 1), a P3
// violation, a mode disagreement, estimates, contacts, a removal and a join,
// an app fault, invalid commands and a refused payload.
Collector ObservedRun() {
  Collector collector(CollectorConfig{3, 50'000'000});
  sync::LDMap map;
  map.epoch = 1;
  map.mode = Mode::kCooperative;
  map.members.set(0);
  map.members.set(1);
  collector.OnEpochStart(0, 20, map);
  map.snapshots[1].x_mm = 3;
  collector.OnEpochStart(1, 21, map);
  map.mode = Mode::kAutonomous;
  collector.OnEpochStart(2, 21, map);

  for (int64_t round = 0; round < 30; ++round) {
    std::vector<RobotRound> robots(3);
    for (uint16_t id = 0; id < 3; ++id) {
      RobotRound& robot = robots[id];
      robot.id = id;
      robot.running = !(id == 2 && round >= 25);
      robot.member = robot.running;
      robot.epoch_mode = (id == 1 && round % 7 == 0) ? Mode::kAutonomous : Mode::kCooperative;
      robot.estimate_valid = round >= 5;
      robot.true_x_m = 0.1 * round;
      robot.est_x_m = 0.1 * round + 0.01 * id;
      robot.est_y_m = 0.003 * round;
    }
    collector.OnRoundEnd(round, robots);
  }
  wire::MemberSet gone;
  gone.set(2);
  collector.OnMembership(0, 29, gone, wire::MemberSet{});
  collector.OnCollision(1'234'567'890, 1, 0);
  collector.OnWallContact(2'000'000'000, 2);
  collector.OnAppFault(AppFault{2, "new_round", 1, 1'250'000'000, "crashed", "SIGSEGV"});
  collector.OnInvalidCommand(1, 1, "MOVE_TO x_m is not finite");
  collector.OnInvalidCommand(0, 2, "kind 7 is unknown");
  collector.OnPayloadRefused(0, 1, "10 bytes");
  collector.OnJoinWait(1, 500'000'000);
  collector.OnJoinWait(2, 700'000'000);
  collector.OnJoinWaitEnd(1, 900'000'000);
  return collector;
}

RunFacts Facts() {
  RunFacts facts;
  facts.seed = 18'446'744'073'709'551'615u;  // the largest seed must survive exactly
  facts.robots = 3;
  facts.sim_seconds = 1.5;
  facts.wall_seconds = 0.25;
  facts.radio_rounds = 30;
  facts.min_separation_m = 0.042;
  facts.goal = GoalResult{"builtin:circle", false, 0.75, "2 of 3 robots on the circle"};
  facts.app_name = "circle";
  facts.app_source = "builtin:circle";
  facts.scenario = "circle-3";
  return facts;
}

Json Parse(const std::string& text) { return Json::parse(text); }

// The value at a dotted path, or a discarded value when a step is missing.
Json At(const Json& root, const std::string& path) {
  const Json* node = &root;
  std::stringstream steps(path);
  std::string step;
  while (std::getline(steps, step, '.')) {
    if (!node->is_object() || !node->contains(step)) return Json(Json::value_t::discarded);
    node = &(*node)[step];
  }
  return *node;
}

TEST(MetricsJson, HasEveryRequiredFieldWithTheRightType) {
  const Json json = Parse(ToJson(ObservedRun().Finish(Facts())));

  const std::vector<std::string> unsigned_integers = {"seed", "robots"};
  const std::vector<std::string> integers = {
      "radio_rounds", "epochs_started", "epoch_starts", "synchrony.max_start_skew_rounds",
      "common_knowledge.violations", "common_knowledge.max_mode_disagreement_rounds",
      "collisions.count", "walls.contacts", "membership.removals", "membership.joins",
      "membership.robots_removed"};
  const std::vector<std::string> numbers = {
      "sim_seconds", "wall_seconds", "common_knowledge.cooperative_fraction",
      "collisions.min_separation_m", "estimation.position_rmse_m", "estimation.max_error_m",
      "goal.error_m"};
  for (const std::string& path : unsigned_integers) {
    EXPECT_TRUE(At(json, path).is_number_unsigned()) << path;
  }
  for (const std::string& path : integers) EXPECT_TRUE(At(json, path).is_number_integer()) << path;
  for (const std::string& path : numbers) EXPECT_TRUE(At(json, path).is_number()) << path;
  for (const char* path : {"scenario", "app.name", "app.source", "goal.app", "goal.detail"}) {
    EXPECT_TRUE(At(json, path).is_string()) << path;
  }
  EXPECT_TRUE(At(json, "goal.reached").is_boolean());
  EXPECT_TRUE(At(json, "synchrony.skew_histogram").is_array());
  EXPECT_EQ(At(json, "synchrony.skew_histogram").size(), kSkewHistogramBins);
  EXPECT_TRUE(At(json, "collisions.pairs").is_array());
  EXPECT_TRUE(At(json, "common_knowledge.first_violations").is_array());
}

TEST(MetricsJson, ValuesReadBackAsComputed) {
  const Json json = Parse(ToJson(ObservedRun().Finish(Facts())));

  EXPECT_EQ(json["seed"].get<uint64_t>(), 18'446'744'073'709'551'615u);
  EXPECT_EQ(json["synchrony"]["max_start_skew_rounds"], 1);
  EXPECT_EQ(json["common_knowledge"]["violations"], 1);
  EXPECT_EQ(json["common_knowledge"]["first_violations"][0]["robot"], 1);
  EXPECT_DOUBLE_EQ(json["common_knowledge"]["cooperative_fraction"].get<double>(), 2.0 / 3.0);
  EXPECT_EQ(json["common_knowledge"]["max_mode_disagreement_rounds"], 1);
  EXPECT_EQ(json["collisions"]["pairs"][0]["a"], 0);
  EXPECT_EQ(json["collisions"]["pairs"][0]["b"], 1);
  EXPECT_EQ(json["collisions"]["pairs"][0]["round"], 24);
  EXPECT_DOUBLE_EQ(json["collisions"]["pairs"][0]["time_s"].get<double>(), 1.23456789);
  EXPECT_EQ(json["collisions"]["min_separation_m"].get<double>(), 0.042);
  EXPECT_EQ(json["membership"]["removals"], 1);
  EXPECT_EQ(json["membership"]["max_removal_latency_rounds"], 4);
  EXPECT_EQ(json["radio_round_s"].get<double>(), 0.05);
}

// Each wait with its start and its end; a joiner that never joined has a
// null end, and UnjoinedJoiners names it as the grade and summary do.
TEST(MetricsJson, JoinerWaitsListEachWaitAndWhetherItEnded) {
  const Metrics metrics = ObservedRun().Finish(Facts());
  const Json json = Parse(ToJson(metrics));

  const Json& safety = json["safety"];
  EXPECT_EQ(safety["join_waits"], 2);
  ASSERT_EQ(safety["joiner_waits"].size(), 2u);
  EXPECT_EQ(safety["joiner_waits"][0]["robot"], 1);
  EXPECT_DOUBLE_EQ(safety["joiner_waits"][0]["from_s"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(safety["joiner_waits"][0]["joined_s"].get<double>(), 0.9);
  EXPECT_EQ(safety["joiner_waits"][1]["robot"], 2);
  EXPECT_TRUE(safety["joiner_waits"][1]["joined_s"].is_null());
  EXPECT_EQ(UnjoinedJoiners(metrics),
            std::vector<std::string>{
                "robot 2 never joined: it waited 0.8 s for a clear start disc (from 0.7 s to the end)"});
}

TEST(MetricsJson, TheAppObjectNamesTheAppItsFaultsAndTheFirstIncidents) {
  const Json json = Parse(ToJson(ObservedRun().Finish(Facts())));
  const Json& app = json["app"];

  EXPECT_EQ(app["name"], "circle");
  EXPECT_EQ(app["source"], "builtin:circle");
  ASSERT_EQ(app["faults"].size(), 1u);
  EXPECT_EQ(app["faults"][0],
            Json::parse(R"({"robot": 2, "callback": "new_round", "epoch": 1, "time_s": 1.25,)"
                        R"( "verdict": "crashed", "detail": "SIGSEGV"})"));
  EXPECT_EQ(app["invalid_commands"],
            Json::parse(R"({"count": 2, "first": {"robot": 1, "epoch": 1, "what": "MOVE_TO x_m is not finite"}})"));
  EXPECT_EQ(app["payload_refused"], Json::parse(R"({"count": 1, "first": {"robot": 0, "epoch": 1, "what": "10 bytes"}})"));
}

TEST(MetricsJson, AWellBehavedAppHasNoFaultsAndNullFirsts) {
  const Collector collector(CollectorConfig{2, 50'000'000});

  const Json json = Parse(ToJson(collector.Finish(Facts())));

  EXPECT_EQ(json["app"]["faults"], Json::array());
  EXPECT_EQ(json["app"]["invalid_commands"], Json::parse(R"({"count": 0, "first": null})"));
  EXPECT_EQ(json["app"]["payload_refused"], Json::parse(R"({"count": 0, "first": null})"));
}

TEST(MetricsJson, SandboxNotesAreNullForABuiltinAppAndListedForALibrary) {
  const Collector collector(CollectorConfig{2, 50'000'000});
  RunFacts facts = Facts();
  EXPECT_EQ(Parse(ToJson(collector.Finish(facts)))["app"]["sandbox"], nullptr);

  facts.app_sandbox = std::vector<std::string>{"user namespaces unavailable: EPERM"};
  EXPECT_EQ(Parse(ToJson(collector.Finish(facts)))["app"]["sandbox"],
            Json::parse(R"(["user namespaces unavailable: EPERM"])"));
}

TEST(MetricsJson, FieldsKeepTheDocumentedOrder) {
  const Json json = Parse(ToJson(ObservedRun().Finish(Facts())));
  const std::vector<std::string> expected = {
      "schema_version", "runtime", "scenario", "app", "seed", "robots", "sim_seconds", "wall_seconds",
      "radio_rounds", "radio_round_s", "epochs_started", "epoch_starts", "goal", "synchrony",
      "round_phase", "common_knowledge", "agreement", "collisions", "walls", "safety", "estimation", "membership", "diagnostics"};

  std::vector<std::string> keys;
  for (const auto& item : json.items()) keys.push_back(item.key());

  EXPECT_EQ(keys, expected);
}

TEST(MetricsJson, DeclaredGoalChecksPrintEveryField) {
  RunFacts facts = Facts();
  facts.goal.source = "scenario";
  GoalCheckResult check;
  check.name = "together";
  check.check = "gathered";
  check.when = "final";
  check.passed = false;
  check.value = 0.62;
  check.limit = 0.5;
  check.unit = "m";
  check.reason = "held only from epoch 40 (45.00 s) on; the deadline is 30.00 s";
  check.samples = 60;
  check.deadline_s = 30.0;
  check.held_from_epoch = 40;
  check.held_from_s = 45.0;
  facts.goal.checks.push_back(check);
  check.name = "unjudged";
  check.value = std::numeric_limits<double>::quiet_NaN();
  check.deadline_s.reset();
  check.held_from_epoch.reset();
  check.held_from_s.reset();
  facts.goal.checks.push_back(check);

  const Json goal = Parse(ToJson(ObservedRun().Finish(facts)))["goal"];

  EXPECT_EQ(goal["source"], "scenario");
  ASSERT_EQ(goal["checks"].size(), 2u);
  EXPECT_EQ(goal["checks"][0], Json::parse(R"({"name": "together", "check": "gathered", "when": "final",
      "passed": false, "value": 0.62, "limit": 0.5, "unit": "m",
      "reason": "held only from epoch 40 (45.00 s) on; the deadline is 30.00 s", "samples": 60,
      "deadline_s": 30.0, "held_from_epoch": 40, "held_from_s": 45.0})"));
  EXPECT_TRUE(goal["checks"][1]["value"].is_null());
  EXPECT_TRUE(goal["checks"][1]["held_from_epoch"].is_null());
}

TEST(MetricsJson, AgreementPrintsTheFirstDisagreement) {
  Metrics metrics = ObservedRun().Finish(Facts());
  metrics.agreement = AgreementMetrics{};
  EXPECT_TRUE(Parse(ToJson(metrics))["agreement"]["first_disagreement"].is_null());
  EXPECT_TRUE(Parse(ToJson(metrics))["agreement"]["agreed_fraction"].is_null());
  metrics.agreement->cooperative_epochs = 4;
  metrics.agreement->agreed_epochs = 3;
  metrics.agreement->agreed_fraction = 0.75;
  metrics.agreement->first_disagreement = Disagreement{12, 250, "new_round", 3, 7, 0, 2};

  const Json agreement = Parse(ToJson(metrics))["agreement"];

  EXPECT_EQ(agreement["agreed_fraction"], 0.75);
  EXPECT_EQ(agreement["first_disagreement"], Json::parse(R"({"epoch": 12, "round": 250, "callback": "new_round",
      "robot": 3, "state": 7, "reference_robot": 0, "reference_state": 2})"));
}

// A runtime that cannot see the app's returns (the firmware) leaves
// agreement unset: the file says null rather than zeros that read like a
// measurement.
TEST(MetricsJson, AgreementNotMeasuredIsNull) {
  Metrics metrics = ObservedRun().Finish(Facts());
  metrics.runtime = "firmware";

  const Json json = Parse(ToJson(metrics));

  EXPECT_EQ(json["runtime"], "firmware");
  EXPECT_TRUE(json["agreement"].is_null());
  EXPECT_FALSE(json.contains("dds"));
}

TEST(MetricsJson, DdsObjectLastWithEveryField) {
  Metrics metrics = ObservedRun().Finish(Facts());
  metrics.runtime = "dds";
  DdsMetrics dds;
  dds.domain_id = 17;
  dds.delivery_ratio = 0.999;
  dds.cpu_seconds_per_robot = {0.5, 0.0};
  dds.reports_rejected = 1;
  dds.reports_late = 2;
  dds.reports_other_runs = 3;
  dds.drives_other_runs = 4;
  dds.stopped_early = true;
  dds.robot_exits = {0, std::nullopt, -9};
  metrics.dds = dds;
  metrics.round_start_skew = SkewStats{200, 40, 900, 2500};

  const Json json = Parse(ToJson(metrics));

  EXPECT_EQ(std::prev(json.end()).key(), "dds");
  // The skew where layout version 2 has it too, the same figure as the top level's.
  EXPECT_EQ(json["dds"], Json::parse(R"({"domain_id": 17, "delivery_ratio": 0.999,
      "round_start_skew_us": {"rounds": 200, "p50": 40.0, "p99": 900.0, "max": 2500.0},
      "cpu_seconds_per_robot": [0.5, 0.0], "reports_rejected": 1, "reports_late": 2, "reports_other_runs": 3,
      "drives_other_runs": 4, "stopped_early": true, "robot_exits": [0, null, -9]})"));
  EXPECT_EQ(json["dds"]["round_start_skew_us"], json["round_start_skew_us"]);
}

// Outside the lab (DDS, the emulated firmware) the round-start skew is one
// top-level object, after round_phase, in the same unit for both runtimes;
// each of its keys is documented.
TEST(MetricsJson, RoundStartSkewFollowsRoundPhaseOutsideTheLab) {
  Metrics metrics = ObservedRun().Finish(Facts());
  metrics.runtime = "firmware";
  metrics.round_start_skew = SkewStats{200, 40, 900, 2500};

  const Json json = Parse(ToJson(metrics));

  std::vector<std::string> keys;
  for (const auto& item : json.items()) keys.push_back(item.key());
  const auto phase = std::find(keys.begin(), keys.end(), "round_phase");
  ASSERT_NE(phase, keys.end());
  ASSERT_NE(std::next(phase), keys.end());
  EXPECT_EQ(*std::next(phase), "round_start_skew_us");
  EXPECT_EQ(json["round_start_skew_us"], Json::parse(R"({"rounds": 200, "p50": 40.0, "p99": 900.0, "max": 2500.0})"));
  std::ifstream file(SYROF_METRICS_DOC);
  std::stringstream document;
  document << file.rdbuf();
  for (const auto& item : json.at("round_start_skew_us").items()) {
    EXPECT_NE(document.str().find("`round_start_skew_us." + item.key() + "`"), std::string::npos) << item.key();
  }
}

TEST(MetricsJson, IdenticalObservationsGiveIdenticalBytes) {
  const std::string first = ToJson(ObservedRun().Finish(Facts()));
  const std::string second = ToJson(ObservedRun().Finish(Facts()));
  RunFacts other_facts = Facts();
  other_facts.seed = 7;

  const std::string other = ToJson(ObservedRun().Finish(other_facts));

  EXPECT_EQ(first, second);
  EXPECT_NE(first, other);
}

TEST(MetricsJson, PrettyWithTwoSpacesAndATrailingNewline) {
  const std::string text = ToJson(ObservedRun().Finish(Facts()));

  EXPECT_EQ(text.rfind("{\n  \"schema_version\": 2,\n", 0), 0u);
  ASSERT_GE(text.size(), 2u);
  EXPECT_EQ(text.substr(text.size() - 2), "}\n");
}

TEST(MetricsJson, NonFiniteValuesBecomeNull) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double infinity = std::numeric_limits<double>::infinity();
  Collector collector(CollectorConfig{2, 0});
  RobotRound robot;
  robot.running = true;
  robot.estimate_valid = true;
  robot.est_x_m = infinity;
  collector.OnRoundEnd(0, std::vector<RobotRound>{robot});
  collector.OnCollision(5, 0, 1);
  RunFacts facts;
  facts.sim_seconds = nan;
  facts.wall_seconds = -infinity;
  facts.min_separation_m = infinity;
  facts.goal.error_m = nan;

  const std::string text = ToJson(collector.Finish(facts));
  const Json json = Parse(text);

  for (const char* bad : {"nan", "NaN", "inf", "Inf"}) EXPECT_EQ(text.find(bad), std::string::npos) << bad;
  EXPECT_TRUE(json["sim_seconds"].is_null());
  EXPECT_TRUE(json["wall_seconds"].is_null());
  EXPECT_TRUE(json["collisions"]["min_separation_m"].is_null());
  EXPECT_TRUE(json["goal"]["error_m"].is_null());
  EXPECT_TRUE(json["estimation"]["position_rmse_m"].is_null());
  EXPECT_EQ(json["estimation"]["non_finite_samples"], 1);
  EXPECT_TRUE(json["radio_round_s"].is_null());
  EXPECT_TRUE(json["collisions"]["pairs"][0]["round"].is_null());
}

TEST(MetricsJson, EmptyRunHasNullsWhereNothingWasMeasured) {
  const Collector collector(CollectorConfig{4, 50'000'000});

  const Json json = Parse(ToJson(collector.Finish(RunFacts{})));

  EXPECT_TRUE(json["common_knowledge"]["cooperative_fraction"].is_null());
  EXPECT_TRUE(json["synchrony"]["max_skew_epoch"].is_null());
  EXPECT_TRUE(json["synchrony"]["mean_start_skew_rounds"].is_null());
  EXPECT_TRUE(json["estimation"]["max_error_m"].is_null());
  EXPECT_TRUE(json["membership"]["max_join_latency_rounds"].is_null());
  EXPECT_EQ(json["synchrony"]["max_start_skew_rounds"], 0);
  EXPECT_EQ(json["epochs_started"], 0);
}

TEST(MetricsJson, InvalidUtf8InStringsIsReplacedNotFatal) {
  RunFacts facts = Facts();
  facts.goal.detail = std::string("bad \xff byte");
  const Collector collector(CollectorConfig{1, 50'000'000});

  const std::string text = ToJson(collector.Finish(facts));

  EXPECT_NO_THROW(Parse(text));
  EXPECT_EQ(Parse(text)["goal"]["detail"], "bad \xEF\xBF\xBD byte");
}

// Collects the dotted path of every object member, e.g. "synchrony.skew_histogram".
void Paths(const Json& node, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& item : node.items()) {
    const std::string path = prefix.empty() ? item.key() : prefix + "." + item.key();
    out.push_back(path);
    if (item.value().is_object()) Paths(item.value(), path, out);
    if (item.value().is_array() && !item.value().empty() && item.value()[0].is_object()) {
      Paths(item.value()[0], path + "[]", out);
    }
  }
}

TEST(MetricsJson, EveryFieldIsDocumented) {
  std::ifstream file(SYROF_METRICS_DOC);
  ASSERT_TRUE(file.good()) << SYROF_METRICS_DOC;
  std::stringstream document;
  document << file.rdbuf();
  const Json json = Parse(ToJson(ObservedRun().Finish(Facts())));
  std::vector<std::string> paths;

  Paths(json, "", paths);

  for (const std::string& path : paths) {
    EXPECT_NE(document.str().find("`" + path + "`"), std::string::npos) << path << " is not in docs/metrics.md";
  }
}

// Under SSYNC each start is counted active or inactive by the robots' own
// schedule; round-robin over two members alternates them.
TEST(MetricsJson, SsyncCountsActivationsAndDocumentsThem) {
  CollectorConfig config{2, 50'000'000};
  config.activation.model = sync::ActivationModel::kSsync;
  config.activation.schedule = sync::ActivationSchedule::kRoundRobin;
  Collector collector(config);
  sync::LDMap map;
  map.mode = Mode::kCooperative;
  map.members.set(0);
  map.members.set(1);
  for (uint16_t epoch = 1; epoch <= 4; ++epoch) {
    map.epoch = epoch;
    collector.OnEpochStart(0, 20 * epoch, map);
    collector.OnEpochStart(1, 20 * epoch, map);
  }

  const Metrics metrics = collector.Finish(Facts());

  ASSERT_TRUE(metrics.activation.has_value());
  EXPECT_EQ(metrics.activation->schedule, "round_robin");
  EXPECT_EQ(metrics.activation->active_starts, 4);
  EXPECT_EQ(metrics.activation->inactive_starts, 4);
  EXPECT_EQ(metrics.activation->fair_within_achieved, 2);
  const Json json = Parse(ToJson(metrics));
  EXPECT_TRUE(json.at("activation").at("fair_within").is_null());
  std::ifstream file(SYROF_METRICS_DOC);
  std::stringstream document;
  document << file.rdbuf();
  for (const auto& item : json.at("activation").items()) {
    EXPECT_NE(document.str().find("`activation." + item.key() + "`"), std::string::npos) << item.key();
  }
}

TEST(MetricsJson, FsyncHasNoActivationSection) {
  const Json json = Parse(ToJson(ObservedRun().Finish(Facts())));
  EXPECT_FALSE(json.contains("activation"));
}

}  // namespace
}  // namespace syrof::lab::metrics
