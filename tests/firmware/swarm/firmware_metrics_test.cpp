// FirmwareMetrics: firmware-swarm.json holds every figure the host measured,
// under its key, in the file's layout.
#include "syrof/firmware/swarm/firmware_metrics.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace syrof::firmware::swarm {
namespace {

using Json = nlohmann::ordered_json;

FaultOutcome Outcome(HostAction::Kind kind, uint16_t robot, int64_t at_ns, std::optional<int64_t> done_ns) {
  FaultOutcome outcome;
  outcome.kind = kind;
  outcome.robot = robot;
  outcome.at_ns = at_ns;
  outcome.ok = done_ns.has_value();
  outcome.done_ns = done_ns;
  return outcome;
}

// The figures of a run of firmware_faults.yaml (14 s, --icount -1), as
// syrof-firmware-swarm wrote them before the report was typed, less the
// round-start skew (now metrics.json's round_start_skew_us, as DDS's).
FirmwareMetrics FaultsRun() {
  FirmwareMetrics metrics;
  metrics.robots = 4;
  metrics.seconds = 14;
  metrics.loss = 0;
  metrics.seed = 3;
  metrics.align = false;
  metrics.latency_ms = 25;
  metrics.timing = "host clock (no -icount)";
  metrics.wall_seconds = 19.7317;
  metrics.p3_violations = 0;
  metrics.cooperative_starts = 4;
  metrics.beacons = BeaconCounts{1470, 1322, 0, 49, 0};
  metrics.sensor_link = SensorLinkCounts{4837, 2421, 486, 0, 2456, 0};
  metrics.scenario = "firmware_faults";
  metrics.replay_rounds = 281;
  metrics.estimation = EstimationFigures{568, 0.208378, 0.559153};
  metrics.exit_statuses = {0, 137, 0, 0};
  metrics.partitioned_beacons = 148;
  metrics.faults.push_back(Outcome(HostAction::Kind::kSwitchOn, 3, 1'300'000'000, 5'760'000'000));
  FaultOutcome pause = Outcome(HostAction::Kind::kStop, 2, 3'000'000'000, 12'450'000'000);
  pause.guest_gap_ms = 3250;
  pause.world_gap_ms = 3320;
  pause.rejoined_as_joiner = true;
  metrics.faults.push_back(pause);
  metrics.faults.push_back(Outcome(HostAction::Kind::kKill, 1, 9'500'000'000, 13'050'000'000));
  return metrics;
}

TEST(FirmwareMetricsTest, WritesTheLayoutTheHostWroteBeforeTheReportWasTyped) {
  EXPECT_EQ(ToJson(FaultsRun()),
            "{\n"
            "  \"robots\": 4,\n"
            "  \"seconds\": 14,\n"
            "  \"loss\": 0,\n"
            "  \"seed\": 3,\n"
            "  \"align\": false,\n"
            "  \"latency_ms\": 25,\n"
            "  \"timing\": \"host clock (no -icount)\",\n"
            "  \"wall_seconds\": 19.7317,\n"
            "  \"all_cooperative_s\": null,\n"
            "  \"p3_violations\": 0,\n"
            "  \"cooperative_starts\": 4,\n"
            "  \"beacons\": {\"offered\": 1470, \"delivered\": 1322, \"link_errors\": 0, \"late\": 49, \"past_their_round\": 0},\n"
            "  \"sensor_link\": {\"imu\": 4837, \"flow\": 2421, \"uwb\": 486, \"not_encoded\": 0, \"drives\": 2456, "
            "\"rejected_from_robots\": 0},\n"
            "  \"scenario\": \"firmware_faults\", \"replay_rounds\": 281,\n"
            "  \"estimation\": {\"samples\": 568, \"rmse_m\": 0.208378, \"max_m\": 0.559153},\n"
            "  \"exit_statuses\": [0, 137, 0, 0],\n"
            "  \"partitioned_beacons\": 148,\n"
            "  \"stress\": null,\n"
            "  \"faults\": [\n"
            "    {\"kind\": \"join\", \"robot\": 3, \"at_s\": 1.3, \"ok\": true, \"done_s\": 5.760000},\n"
            "    {\"kind\": \"pause\", \"robot\": 2, \"at_s\": 3, \"ok\": true, \"done_s\": 12.450000, \"guest_gap_ms\": 3250, "
            "\"world_gap_ms\": 3320, \"rejoined_as_joiner\": true},\n"
            "    {\"kind\": \"crash\", \"robot\": 1, \"at_s\": 9.5, \"ok\": true, \"done_s\": 13.050000}\n"
            "  ],\n"
            "  \"activation\": {\"model\": \"fsync\", \"starts\": 0, \"looked\": 0, \"against_schedule\": 0}\n"
            "}\n");
}

// Every field reaches its own key: each figure differs from every other.
TEST(FirmwareMetricsTest, EveryFigureIsUnderItsKeyInOrder) {
  FirmwareMetrics metrics;
  metrics.robots = 5;
  metrics.seconds = 6;
  metrics.loss = 0.25;
  metrics.seed = 7;
  metrics.align = true;
  metrics.latency_ms = 8.5;
  metrics.timing = "-icount shift=4";
  metrics.wall_seconds = 9.5;
  metrics.all_cooperative_s = 10.5;
  metrics.p3_violations = 11;
  metrics.cooperative_starts = 12;
  metrics.beacons = BeaconCounts{17, 18, 19, 20, 21};
  metrics.sensor_link = SensorLinkCounts{22, 23, 24, 25, 26, 27};
  metrics.scenario = "gather-3.b";
  metrics.replay_rounds = 28;
  metrics.estimation = EstimationFigures{29, 0.5, 0.75};
  metrics.exit_statuses = {0, 137, -1};
  metrics.partitioned_beacons = 30;
  metrics.stress = StressFigures{31, 32.5, 33, 34, 0.125, 35, 36};
  FaultOutcome pause = Outcome(HostAction::Kind::kStop, 4, 2'500'000'000, std::nullopt);
  pause.world_gap_ms = 37;
  metrics.faults.push_back(pause);
  metrics.activation = ActivationFigures{"ssync", 38, 39, 40, "not written"};

  const Json json = Json::parse(ToJson(metrics));

  std::vector<std::string> keys;
  for (const auto& [key, value] : json.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"robots", "seconds", "loss", "seed", "align", "latency_ms", "timing",
                                            "wall_seconds", "all_cooperative_s", "p3_violations", "cooperative_starts",
                                            "beacons", "sensor_link", "scenario", "replay_rounds",
                                            "estimation", "exit_statuses", "partitioned_beacons", "stress", "faults",
                                            "activation"}));
  EXPECT_EQ(json["robots"], 5);
  EXPECT_EQ(json["seconds"], 6);
  EXPECT_EQ(json["loss"], 0.25);
  EXPECT_EQ(json["seed"], 7);
  EXPECT_EQ(json["align"], true);
  EXPECT_EQ(json["latency_ms"], 8.5);
  EXPECT_EQ(json["timing"], "-icount shift=4");
  EXPECT_EQ(json["wall_seconds"], 9.5);
  EXPECT_EQ(json["all_cooperative_s"], 10.5);
  EXPECT_EQ(json["p3_violations"], 11);
  EXPECT_EQ(json["cooperative_starts"], 12);
  EXPECT_EQ(json["beacons"], Json::parse(R"({"offered": 17, "delivered": 18, "link_errors": 19, "late": 20,
                                             "past_their_round": 21})"));
  EXPECT_EQ(json["sensor_link"], Json::parse(R"({"imu": 22, "flow": 23, "uwb": 24, "not_encoded": 25, "drives": 26,
                                                 "rejected_from_robots": 27})"));
  EXPECT_EQ(json["scenario"], "gather-3.b");
  EXPECT_EQ(json["replay_rounds"], 28);
  EXPECT_EQ(json["estimation"], Json::parse(R"({"samples": 29, "rmse_m": 0.5, "max_m": 0.75})"));
  EXPECT_EQ(json["exit_statuses"], Json::parse("[0, 137, -1]"));
  EXPECT_EQ(json["partitioned_beacons"], 30);
  EXPECT_EQ(json["stress"], Json::parse(R"({"seed": 31, "stalls_per_second": 32.5, "qemu_stalls": 33, "host_stalls": 34,
                                            "late_fraction": 0.125, "late_beacons": 35, "cpu_quota_permille": 36})"));
  EXPECT_EQ(json["faults"], Json::parse(R"([{"kind": "pause", "robot": 4, "at_s": 2.5, "ok": false, "done_s": null,
                                             "guest_gap_ms": null, "world_gap_ms": 37,
                                             "rejoined_as_joiner": false}])"));
  EXPECT_EQ(json["activation"], Json::parse(R"({"model": "ssync", "starts": 38, "looked": 39, "against_schedule": 40})"));
}

TEST(FirmwareMetricsTest, WhatWasNotMeasuredIsNull) {
  const Json json = Json::parse(ToJson(FirmwareMetrics{}));
  EXPECT_TRUE(json["all_cooperative_s"].is_null());
  EXPECT_TRUE(json["estimation"]["rmse_m"].is_null());
  EXPECT_TRUE(json["estimation"]["max_m"].is_null());
  EXPECT_TRUE(json["stress"].is_null());
  EXPECT_EQ(json["faults"], Json::array());
  EXPECT_EQ(json["exit_statuses"], Json::array());
}

}  // namespace
}  // namespace syrof::firmware::swarm
