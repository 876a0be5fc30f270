// A scripted channel (lab/world/channel.h, docs/scenarios.md "channel")
// replays a run loss by loss: the beacons an i.i.d. channel lost, listed,
// give the same replay, bit for bit; one beacon more or less changes the
// run. The ground the search tests stand on (a counterexample is a list).
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/lab/world/channel.h"

namespace syrof::lab::sim {
namespace {

scenario::Scenario Load(const std::string& channel) {
  const scenario::LoadResult loaded = scenario::LoadScenarioText(
      "seed: 4\nrobots: { count: 5, placement: grid, spacing_m: 0.7 }\ntiming: { duration_s: 8 }\n" + channel +
          "app: builtin:circle\n",
      "scripted.yaml", {});
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return *loaded.scenario;
}

std::string ReplayOf(const scenario::Scenario& scenario) {
  std::ostringstream replay;
  SimulationOptions options;
  options.replay = &replay;
  (void)sim::Run(scenario, options, 0.0);
  return replay.str();
}

TEST(ScriptedChannelTest, TheBeaconsAnIidChannelLostReplayItsRunBitForBit) {
  const scenario::Scenario iid = Load("channel: { model: iid, loss: 0.2 }\n");
  // Every beacon the run's channel loses: the same channel, asked about
  // every round and link of the run (it answers the same whatever the order).
  world::Channel channel(iid.channel, 5, ChannelSeed(iid.seed));
  scenario::Scenario scripted = Load("channel: { model: scripted }\n");
  const int64_t rounds = static_cast<int64_t>(iid.timing.duration_s / iid.timing.radio_round_s) + 1;
  for (int64_t round = 0; round < rounds; ++round) {
    for (uint16_t from = 0; from < 5; ++from) {
      for (uint16_t to = 0; to < 5; ++to) {
        const double sent_s = static_cast<double>(round) * iid.timing.radio_round_s;
        if (from != to && !channel.Delivers(from, to, round, sent_s)) scripted.channel.lost.push_back({round, from, to});
      }
    }
  }
  ASSERT_GT(scripted.channel.lost.size(), 300u);

  const std::string replay = ReplayOf(iid);
  EXPECT_TRUE(ReplayOf(scripted) == replay);  // (not EXPECT_EQ: the replays are binary and long)
  EXPECT_FALSE(ReplayOf(Load("channel: { model: scripted }\n")) == replay);
  // One loss fewer, in a round where it mattered, gives another run.
  int changed = 0;
  for (size_t drop = 0; drop < 40 && changed == 0; ++drop) {
    scenario::Scenario one_fewer = scripted;
    one_fewer.channel.lost.erase(one_fewer.channel.lost.begin() + static_cast<std::ptrdiff_t>(drop * 7));
    if (!(ReplayOf(one_fewer) == replay)) ++changed;
  }
  EXPECT_EQ(changed, 1);
}

}  // namespace
}  // namespace syrof::lab::sim
