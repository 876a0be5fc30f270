// The platform safety layer end to end (docs/safety.md): the built-in apps
// keep clear of every body in the adversarial scenarios, the filter is what
// does it, presence beacons leave the synchronizer alone, and interventions
// and join waits reach metrics.json and the replay.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/lab/replay/reader.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::sim {
namespace {

using nlohmann::json;

scenario::Scenario LoadFile(const std::string& file, const scenario::Overrides& overrides = {}) {
  const scenario::LoadResult loaded =
      scenario::LoadScenarioFile(std::string(SYROF_SCENARIOS_DIR) + "/" + file, overrides);
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

struct Outcome {
  json metrics;
  std::vector<replay::Round> rounds;
};

Outcome RunWithReplay(const scenario::Scenario& scenario) {
  std::ostringstream replay_bytes;
  SimulationOptions options;
  options.replay = &replay_bytes;
  Outcome outcome;
  outcome.metrics = json::parse(sim::Run(scenario, options, 0.0).metrics_json);
  std::istringstream in(replay_bytes.str());
  replay::Reader reader(in);
  replay::Header header;
  EXPECT_TRUE(reader.ReadHeader(header)) << reader.error();
  replay::Round round;
  while (reader.Next(round)) outcome.rounds.push_back(round);
  EXPECT_TRUE(reader.complete()) << reader.error();
  return outcome;
}

json Metrics(const scenario::Scenario& scenario) {
  return json::parse(sim::Run(scenario, SimulationOptions{}, 0.0).metrics_json);
}

struct Case {
  const char* file;
  bool goal;  // the app's goal is reached at the end (with the filter on)
  double duration_s;  // 0: the file's; else a CI-sized run
};

class AdversarialScenario : public ::testing::TestWithParam<Case> {};

// Each of these collided with the built-in apps before the filter (9 of 26
// adversarial runs did); with it on, none does, P3 holds, and the goal is
// reached where the app has one.
TEST_P(AdversarialScenario, HasNoCollisionAndKeepsCommonKnowledge) {
  const Case& c = GetParam();
  scenario::Overrides overrides;
  if (c.duration_s > 0) overrides.duration_s = c.duration_s;
  const json metrics = Metrics(LoadFile(c.file, overrides));

  EXPECT_EQ(metrics["collisions"]["count"], 0) << metrics["collisions"].dump();
  EXPECT_EQ(metrics["common_knowledge"]["violations"], 0);
  EXPECT_TRUE(metrics["safety"]["enabled"].get<bool>());
  if (c.goal) {
    EXPECT_TRUE(metrics["goal"]["reached"].get<bool>()) << metrics["goal"].dump();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Safety, AdversarialScenario,
    ::testing::Values(Case{"adversarial/partitions_4_3.yaml", true, 0}, Case{"adversarial/split_5_5.yaml", true, 0},
                      Case{"adversarial/pause_boundaries.yaml", true, 0},
                      Case{"adversarial/join_storm.yaml", true, 0},
                      Case{"adversarial/rover_leader_follow.yaml", true, 0},
                      Case{"adversarial/mixed_gather.yaml", true, 0},
                      // A crashed body stands where gather packs: the goal cannot be reached.
                      Case{"adversarial/ramming.yaml", false, 0},
                      // The same, the crashed body between a robot that heard it and a joiner.
                      Case{"adversarial/join_after_crash.yaml", false, 0},
                      // CI-sized: 8 s with crashes and joins; the 30 s crowd_200.yaml
                      // is measured in docs/safety.md.
                      Case{"adversarial/crowd_200_short.yaml", false, 0}),
    [](const ::testing::TestParamInfo<Case>& param) {
      std::string name = param.param.file;
      name = name.substr(name.find('/') + 1);
      name = name.substr(0, name.find('.'));
      for (char& ch : name) {
        if (ch == '_') ch = 'x';
      }
      return name;
    });

// Mixed kinds and partial connectivity, twenty seeds each: mixed_gather had
// 6 collisions in 20 seeds (parked robots whose heading estimate had
// drifted up to 2.2 rad) and the link scenarios 3; none now. Every other
// example and adversarial file over twenty seeds is measured in
// docs/safety.md ("Twenty seeds"); the mixed/ files in
// margin_coverage_test.cpp, except the two with drones, here (omni,
// rover and drone together, with a join and a crash: a drone brakes on its
// lagged curve and holds against its drift, docs/safety.md "Drones"), with
// eight drones gathering (drones.yaml: 1 collision in the 20 seeds without
// the drone's lagged braking, hold and own sigmas). Not under the
// sanitizers (ASAN_EXCLUDE): 160 runs.
class TwentySeeds : public ::testing::TestWithParam<const char*> {};

TEST_P(TwentySeeds, NoCollisionAndNoP3Violation) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    scenario::Overrides overrides;
    overrides.seed = seed;
    const json metrics = Metrics(LoadFile(GetParam(), overrides));
    EXPECT_EQ(metrics["collisions"]["count"], 0) << "seed " << seed << ": " << metrics["collisions"].dump();
    EXPECT_EQ(metrics["common_knowledge"]["violations"], 0) << "seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Safety, TwentySeeds,
                         ::testing::Values("adversarial/mixed_gather.yaml", "adversarial/rover_leader_follow.yaml",
                                           "rovers.yaml", "links/two_dead_links.yaml", "links/deaf_mute_flaky.yaml",
                                           "mixed/gather_three_kinds.yaml", "mixed/circle_three_kinds.yaml",
                                           "drones.yaml"),
                         [](const ::testing::TestParamInfo<const char*>& param) {
                           std::string name = param.param;
                           name = name.substr(name.find('/') + 1);
                           name = name.substr(0, name.find('.'));
                           for (char& ch : name) {
                             if (ch == '_') ch = 'x';
                           }
                           return name;
                         });

// A joiner's start disc counts the stopping distance of every robot driving
// at it: in crowd_200_short seed 2 robot 41 was switched on 7.5 cm beyond
// robot 116's disc while 116 drove at 0.45 m/s, and they collided. Not under
// the sanitizers (ASAN_EXCLUDE): 200 robots.
TEST(SafetyTest, AJoinerWaitsForARobotThatCouldNotStop) {
  scenario::Overrides overrides;
  overrides.seed = 2;
  const json metrics = Metrics(LoadFile("adversarial/crowd_200_short.yaml", overrides));
  EXPECT_EQ(metrics["collisions"]["count"], 0) << metrics["collisions"].dump();
  EXPECT_GT(metrics["safety"]["join_waits"].get<int>(), 0);
}

// Robot 1 is paused from 3 to 9 s; robot 6 drives on and pauses from 8 to
// 16 s. Robot 1's report of robot 6 is from before its own pause: with a
// disc capped at the horizon it drove into robot 6 at 15.5 s. The disc now
// also grows for robot 1's pause (SafetyReports::MarkListeningGap).
TEST(SafetyTest, ARobotBackFromAPauseKeepsOffWhereASilentRobotMayHaveGone) {
  scenario::Overrides overrides;
  overrides.seed = 16;
  const json metrics = Metrics(LoadFile("adversarial/pause_boundaries.yaml", overrides));
  EXPECT_EQ(metrics["collisions"]["count"], 0) << metrics["collisions"].dump();
  EXPECT_TRUE(metrics["goal"]["reached"].get<bool>()) << metrics["goal"].dump();
}

// Robot 2 is switched on after robot 1 crashed between it and robot 0, so
// it never hears robot 1; before relays it drove into the body in every one
// of seeds 1 to 5. Robot 0's beacons relay robot 1's last position
// (docs/beacon.md, "Relays"), robot 2 records it, and keeps off.
TEST(SafetyTest, AJoinerHearsOfACrashedRobotFromTheOthersRelays) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    scenario::Overrides overrides;
    overrides.seed = seed;
    const scenario::Scenario scenario = LoadFile("adversarial/join_after_crash.yaml", overrides);
    Simulation simulation(scenario, SimulationOptions{});
    simulation.RunUntil(scenario.timing.duration_s);
    const json metrics = json::parse(simulation.Finish(0.0).metrics_json);

    EXPECT_EQ(metrics["collisions"]["count"], 0) << "seed " << seed << ": " << metrics["collisions"].dump();
    EXPECT_GT(simulation.robot(0).counters().relays_sent, 0u) << "seed " << seed;
    EXPECT_EQ(simulation.robot(2).counters().relays_taken, 1u) << "seed " << seed;  // robot 1, once
    EXPECT_EQ(simulation.robot(0).counters().relays_taken, 0u) << "seed " << seed;  // it heard robot 1 itself
  }
}

// The filter is what prevents the ramming: switched off, the gatherers drive
// into the crashed body no map shows.
TEST(SafetyTest, TheRammingCaseCollidesWithSafetyOff) {
  scenario::Scenario scenario = LoadFile("adversarial/ramming.yaml");
  scenario.safety = false;

  const json metrics = Metrics(scenario);

  EXPECT_GT(metrics["collisions"]["count"].get<int>(), 0);
  EXPECT_FALSE(metrics["safety"]["enabled"].get<bool>());
  EXPECT_EQ(metrics["safety"]["interventions"], 0);
}

// Presence-only beacons go to the safety filter only: every robot's
// synchronizer state is identical, round by round, with and without them
// (the filter is off in both runs, so the bodies move the same).
TEST(SafetyTest, PresenceBeaconsLeaveEverySynchronizerUnchanged) {
  scenario::Scenario scenario = LoadFile("adversarial/join_storm.yaml");
  scenario.safety = false;
  auto with_presence = [](bool announce) {
    SimulationOptions options;
    options.configure_robot = [announce](runtime::RobotConfig& config) {
      config.safety.enabled = false;
      config.announce_presence = announce;
    };
    return options;
  };
  Simulation announcing(scenario, with_presence(true));
  Simulation silent(scenario, with_presence(false));

  const double round_s = scenario.timing.radio_round_s;
  for (int round = 1; round * round_s <= scenario.timing.duration_s; ++round) {
    announcing.RunUntil(round * round_s);
    silent.RunUntil(round * round_s);
    for (uint16_t id = 0; id < announcing.robot_count(); ++id) {
      ASSERT_EQ(announcing.robot(id).sync_state(), silent.robot(id).sync_state())
          << "robot " << id << " round " << round;
    }
  }
  uint32_t sent = 0;
  uint32_t heard = 0;
  for (uint16_t id = 0; id < announcing.robot_count(); ++id) {
    sent += announcing.robot(id).counters().presence_sent;
    heard += announcing.robot(id).counters().presence_received;
    EXPECT_EQ(silent.robot(id).counters().presence_sent, 0u);
  }
  EXPECT_GT(sent, 0u);  // the joiners did announce themselves
  EXPECT_GT(heard, 0u);
}

// Every intervention start is one SAFETY_INTERVENTION event and one count;
// every joiner that waited has one JOIN_WAIT before its JOIN.
TEST(SafetyTest, InterventionsAndJoinWaitsReachMetricsAndReplay) {
  const Outcome run = RunWithReplay(LoadFile("adversarial/join_storm.yaml"));
  std::map<uint16_t, int64_t> interventions;
  std::map<uint16_t, int> waits;
  std::map<uint16_t, int> joins_after_wait;
  for (const replay::Round& round : run.rounds) {
    for (const replay::Event& event : round.events) {
      if (event.kind == replay::EventKind::kSafetyIntervention) {
        ++interventions[event.robot];
        EXPECT_NE(event.robot, event.other);
      } else if (event.kind == replay::EventKind::kJoinWait) {
        ++waits[event.robot];
      } else if (event.kind == replay::EventKind::kJoin && waits.count(event.robot) != 0) {
        ++joins_after_wait[event.robot];
      }
    }
  }
  const json& safety = run.metrics["safety"];

  int64_t total = 0;
  for (const auto& [robot, count] : interventions) total += count;
  EXPECT_GT(total, 0);
  EXPECT_EQ(safety["interventions"], total);
  ASSERT_EQ(safety["per_robot"].size(), interventions.size());
  for (const json& entry : safety["per_robot"]) {
    EXPECT_EQ(entry["interventions"], interventions[entry["robot"].get<uint16_t>()]);
  }
  EXPECT_LE(safety["first_interventions"].size(), 10u);
  EXPECT_GT(safety["join_waits"].get<int>(), 0);
  EXPECT_EQ(safety["join_waits"].get<size_t>(), waits.size());
  // A waiter is switched on once its disc clears, or stays absent: here the
  // packing forms on the joiners' marks, so those stay out to the end.
  ASSERT_FALSE(run.rounds.empty());
  for (const auto& [robot, count] : waits) {
    EXPECT_EQ(count, 1) << "robot " << robot;
    const bool absent_at_end = run.rounds.back().robots[robot].presence == replay::Presence::kAbsent;
    EXPECT_EQ(joins_after_wait[robot] + (absent_at_end ? 1 : 0), 1) << "robot " << robot;
  }
}

// With safety off nothing waits: the joiners are switched on at once, as
// before the filter.
TEST(SafetyTest, WithSafetyOffJoinersDoNotWait) {
  scenario::Scenario scenario = LoadFile("adversarial/join_storm.yaml");
  scenario.safety = false;

  const json metrics = Metrics(scenario);

  EXPECT_EQ(metrics["safety"]["join_waits"], 0);
}

}  // namespace
}  // namespace syrof::lab::sim
