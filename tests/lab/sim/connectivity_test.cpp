// Partial connectivity in the lab (docs/protocol.md, "Connectivity"): the
// scenarios of lab/scenarios/links, over ten seeds each. The robots the
// connectivity rule keeps (those that hear each other both ways) start at
// least 90 % of their epochs COOPERATIVE, P3 is never violated, and a robot
// left out is back in the COOPERATIVE maps within two epochs of its links
// coming back.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::sim {
namespace {

using nlohmann::json;

scenario::Scenario LoadFile(const std::string& name, uint64_t seed) {
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(std::string(SYROF_SCENARIOS_DIR) + "/" + name);
  if (!loaded.ok()) {
    ADD_FAILURE() << name << ": " << loaded.error->ToString();
    return scenario::Scenario{};
  }
  scenario::Scenario scenario = *loaded.scenario;
  scenario.seed = seed;
  return scenario;
}

struct Case {
  const char* file;
  std::vector<uint16_t> kept;  // the robots that hear each other both ways
};

class ConnectivityTest : public ::testing::TestWithParam<Case> {};

TEST_P(ConnectivityTest, TheRobotsThatHearEachOtherCooperateOnEverySeed) {
  const Case& param = GetParam();
  int64_t kept_starts = 0;
  int64_t kept_cooperative = 0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const RunReport report = sim::Run(LoadFile(param.file, seed), SimulationOptions{}, 0.0);
    const json metrics = json::parse(report.metrics_json);
    const json& knowledge = metrics["common_knowledge"];
    EXPECT_EQ(knowledge["violations"].get<int64_t>(), 0) << param.file << " seed " << seed;
    int64_t starts = 0;
    int64_t cooperative = 0;
    for (const uint16_t robot : param.kept) {
      starts += knowledge["starts_by_robot"][robot].get<int64_t>();
      cooperative += knowledge["cooperative_starts_by_robot"][robot].get<int64_t>();
    }
    EXPECT_GE(static_cast<double>(cooperative), 0.8 * static_cast<double>(starts))
        << param.file << " seed " << seed << ": no seed far below the pooled bar";
    kept_starts += starts;
    kept_cooperative += cooperative;
  }
  ASSERT_GT(kept_starts, 0);
  const double fraction = static_cast<double>(kept_cooperative) / static_cast<double>(kept_starts);
  EXPECT_GE(fraction, 0.9) << param.file;
  std::printf("[ links ] %-28s COOPERATIVE starts of the kept robots over 10 seeds: %.1f %%\n", param.file,
              100.0 * fraction);
}

INSTANTIATE_TEST_SUITE_P(
    Scenarios, ConnectivityTest,
    ::testing::Values(Case{"links/one_dead_link.yaml", {0, 1, 2, 3, 4, 6, 7}},
                      Case{"links/two_dead_links.yaml", {0, 1, 2, 3, 4, 5, 7, 9}},
                      Case{"links/deaf_mute_flaky.yaml", {0, 1, 3, 5, 7}},
                      Case{"links/leader_mute.yaml", {1, 2, 3, 4, 5}}),
    [](const ::testing::TestParamInfo<Case>& case_info) {
      std::string name = case_info.param.file;
      name = name.substr(name.find('/') + 1);
      name = name.substr(0, name.find('.'));
      std::string camel;
      bool upper = true;
      for (const char c : name) {
        if (c == '_') {
          upper = true;
        } else {
          camel += upper ? static_cast<char>(c - 'a' + 'A') : c;
          upper = false;
        }
      }
      return camel;
    });

// Whether `robot` is back: it starts a COOPERATIVE epoch on every robot
// (itself included), as robot 0 does. Any robot's own AUTONOMOUS start from
// a lost vote would not say anything about `robot`, so only robot 0's map and
// `robot`'s are read.
bool BackInTheGroup(const Simulation& simulation, uint16_t robot, uint16_t robots) {
  const sync::LDMap& own = simulation.robot(robot).ldmap();
  const sync::LDMap& reference = simulation.robot(0).ldmap();
  return own.mode == wire::Mode::kCooperative && own.members.count() == robots &&
         (reference.mode != wire::Mode::kCooperative || reference.members == own.members);
}

// How many epochs robot 0 starts after `from_s` until `robot` is back in
// the group; -1 if not by `until_s`.
int EpochsUntilBack(Simulation& simulation, uint16_t robot, uint16_t robots, double from_s, double until_s) {
  simulation.RunUntil(from_s);
  uint16_t epoch = simulation.robot(0).ldmap().epoch;
  int epochs = 0;
  for (double t = from_s + 0.05; t < until_s; t += 0.05) {
    simulation.RunUntil(t);
    if (simulation.robot(0).ldmap().epoch == epoch) continue;
    epoch = simulation.robot(0).ldmap().epoch;
    ++epochs;
    if (BackInTheGroup(simulation, robot, robots)) return epochs;
  }
  return -1;
}

TEST(ConnectivityTest, RobotsCutOffRejoinWithinTwoEpochsOfTheirLinksComingBack) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    Simulation simulation(LoadFile("links/cuts.yaml", seed));
    simulation.RunUntil(25);
    // During the one-way cut: 5 is left out; the others cooperate without it.
    const sync::LDMap& during = simulation.robot(0).ldmap();
    EXPECT_FALSE(during.members.test(5) && during.mode == wire::Mode::kCooperative) << "seed " << seed;
    EXPECT_TRUE(simulation.robot(0).sync_state().pruned.test(5)) << "seed " << seed;
    const int first = EpochsUntilBack(simulation, 5, 8, 30, 34);
    EXPECT_GE(first, 1) << "seed " << seed;
    EXPECT_LE(first, 2) << "seed " << seed << ": robot 5 back after the cut of 3 -> 5 ended at 30 s";
    simulation.RunUntil(45);
    EXPECT_TRUE(simulation.robot(0).sync_state().pruned.test(6)) << "seed " << seed;
    const int second = EpochsUntilBack(simulation, 6, 8, 50, 54);
    EXPECT_GE(second, 1) << "seed " << seed;
    EXPECT_LE(second, 2) << "seed " << seed << ": robot 6 back after the cut of 1 <-> 6 ended at 50 s";
    const json metrics = json::parse(simulation.Finish(0).metrics_json);
    EXPECT_EQ(metrics["common_knowledge"]["violations"].get<int64_t>(), 0) << "seed " << seed;
  }
}

}  // namespace
}  // namespace syrof::lab::sim
