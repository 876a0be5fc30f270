// Simulation::StateDigest (simulation.h), the fingerprint a search prunes
// by (lab/search): the same run gives the same fingerprints round by round;
// a lost beacon changes the state, and one the protocol masks leaves, a few
// rounds later, the state of the run that lost nothing; and runs that went
// apart for good (a robot that moved elsewhere) stay apart.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/lab/world/channel.h"

namespace syrof::lab::sim {
namespace {

using Digest = base::StateDigest::Value;

scenario::Scenario Load(const std::string& app, const std::string& lost) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(
      "seed: 3\narena: { width_m: 4, height_m: 4 }\nrobots: { count: 3, placement: circle, radius_m: 0.7 }\n"
      "timing: { duration_s: 6 }\nchannel: { model: scripted, lost: [" +
          lost + "] }\napp: " + app + "\n",
      "digest.yaml", {});
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

// The fingerprint at the start of each of the first `rounds` radio rounds.
std::vector<Digest> Digests(const scenario::Scenario& scenario, int64_t rounds) {
  SimulationOptions options;
  options.state_digests = true;
  Simulation simulation(scenario, options);
  std::vector<Digest> digests;
  for (int64_t round = 1; round <= rounds; ++round) {
    simulation.RunThroughRoundStart(round);
    const std::optional<Digest> digest = simulation.StateDigest();
    EXPECT_TRUE(digest.has_value());
    digests.push_back(digest.value_or(Digest{}));
  }
  return digests;
}

TEST(StateDigestTest, TheSameRunGivesTheSameDigestsRoundByRound) {
  const scenario::Scenario scenario = Load("builtin:gather", "[20, 0, 1]");
  EXPECT_EQ(Digests(scenario, 80), Digests(scenario, 80));
}

TEST(StateDigestTest, ALostBeaconChangesTheStateAndAMaskedOneIsForgotten) {
  const std::vector<Digest> none = Digests(Load("builtin:idle", ""), 80);
  const std::vector<Digest> one = Digests(Load("builtin:idle", "[30, 2, 0]"), 80);
  // Before round 31 robot 0 has not missed the beacon of round 30.
  for (size_t round = 1; round <= 30; ++round) EXPECT_EQ(none[round - 1], one[round - 1]) << "round " << round;
  EXPECT_NE(none[30], one[30]) << "the loss is in the state at round 31's start";
  size_t same_from = 0;
  for (size_t round = 80; round > 31 && none[round - 1] == one[round - 1]; --round) same_from = round;
  EXPECT_GT(same_from, 31u) << "the idle swarm forgets a lost beacon once it is heard again";
  EXPECT_LE(same_from, 40u);
}

TEST(StateDigestTest, AStateReachedTwoWaysHasOneDigest) {
  // Two different single losses that the protocol masks both come back to
  // the loss-free state.
  const std::vector<Digest> none = Digests(Load("builtin:idle", ""), 80);
  const std::vector<Digest> a = Digests(Load("builtin:idle", "[30, 2, 0]"), 80);
  const std::vector<Digest> b = Digests(Load("builtin:idle", "[31, 1, 2]"), 80);
  EXPECT_NE(a[31], b[31]);
  EXPECT_EQ(a[79], none[79]);
  EXPECT_EQ(b[79], none[79]);
}

TEST(StateDigestTest, RunsWithClocksHaveNone) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(
      "seed: 3\nrobots: { count: 3, placement: circle, radius_m: 0.7 }\ntiming: { duration_s: 2 }\n"
      "clocks: { drift_ppm: [0, 20, -20] }\napp: builtin:idle\n",
      "clocks.yaml", {});
  ASSERT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  SimulationOptions options;
  options.state_digests = true;
  Simulation simulation(*loaded.scenario, options);
  simulation.RunThroughRoundStart(3);
  EXPECT_FALSE(simulation.StateDigest().has_value());
}

TEST(StateDigestTest, ARunNotAskedForDigestsRefusesToGiveOne) {
  // Without state_digests the apps' call histories are not kept, so a
  // digest would miss them: a caller's mistake, which stops the program.
  const scenario::Scenario scenario = Load("builtin:idle", "");
  EXPECT_DEATH(
      {
        Simulation simulation(scenario);
        simulation.RunThroughRoundStart(3);
        (void)simulation.StateDigest();
      },
      "state_digests");
}

}  // namespace
}  // namespace syrof::lab::sim
