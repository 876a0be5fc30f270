// A scripted channel (lab/world/channel.h, docs/scenarios.md "channel")
// replays a run loss by loss: the beacons an i.i.d. channel lost, listed,
// give the same replay, bit for bit; one beacon more or less changes the
// run. The ground the search tests stand on (a counterexample is a list).
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/lab/replay/reader.h"
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

std::vector<replay::Round> RoundsOf(const std::string& bytes) {
  std::istringstream in(bytes);
  replay::Reader reader(in);
  replay::Header header;
  EXPECT_TRUE(reader.ReadHeader(header)) << reader.error();
  std::vector<replay::Round> rounds;
  for (replay::Round round; reader.Next(round);) rounds.push_back(round);
  EXPECT_TRUE(reader.complete()) << reader.error();
  return rounds;
}

bool IsLostBeacon(const replay::Event& event) { return event.kind == replay::EventKind::kBeaconLost; }

// The replay's rounds without the BEACON_LOST events a scripted channel
// adds (the run itself, as an i.i.d. channel's replay records it).
std::vector<replay::Round> RunOf(const std::string& bytes) {
  std::vector<replay::Round> rounds = RoundsOf(bytes);
  for (replay::Round& round : rounds) std::erase_if(round.events, IsLostBeacon);
  return rounds;
}

std::vector<replay::Event> LostBeaconEvents(const std::string& bytes) {
  std::vector<replay::Event> lost;
  for (const replay::Round& round : RoundsOf(bytes)) {
    std::copy_if(round.events.begin(), round.events.end(), std::back_inserter(lost), IsLostBeacon);
  }
  return lost;
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

  const std::vector<replay::Round> replay = RunOf(ReplayOf(iid));
  EXPECT_TRUE(RunOf(ReplayOf(scripted)) == replay);  // (not EXPECT_EQ: the replays are long)
  EXPECT_FALSE(RunOf(ReplayOf(Load("channel: { model: scripted }\n"))) == replay);
  // One loss fewer, in a round where it mattered, gives another run.
  int changed = 0;
  for (size_t drop = 0; drop < 40 && changed == 0; ++drop) {
    scenario::Scenario one_fewer = scripted;
    one_fewer.channel.lost.erase(one_fewer.channel.lost.begin() + static_cast<std::ptrdiff_t>(drop * 7));
    if (!(RunOf(ReplayOf(one_fewer)) == replay)) ++changed;
  }
  EXPECT_EQ(changed, 1);
}

// Each lost beacon between two running robots is a BEACON_LOST event in
// its round (the viewer draws it); one from or to a crashed robot is not.
TEST(ScriptedChannelTest, TheReplayMarksEachLostBeacon) {
  const std::string replay = ReplayOf(Load(
      "channel: { model: scripted, lost: [[40, 2, 0], [3, 0, 1], [3, 4, 1], [100, 1, 3]] }\n"
      "faults: [{crash: 1, at_s: 2.0}]\n"));
  const std::vector<replay::Event> lost = LostBeaconEvents(replay);
  ASSERT_EQ(lost.size(), 3u);  // [100, 1, 3]: robot 1 crashed at round 40
  const int64_t round_ns = 50'000'000;
  EXPECT_EQ(lost[0].robot, 0);
  EXPECT_EQ(lost[0].other, 1);
  EXPECT_EQ(lost[0].time_ns, 3 * round_ns);
  EXPECT_EQ(lost[1].robot, 4);
  EXPECT_EQ(lost[1].other, 1);
  EXPECT_EQ(lost[2].robot, 2);
  EXPECT_EQ(lost[2].other, 0);
  EXPECT_EQ(lost[2].time_ns, 40 * round_ns);
  // An i.i.d. channel's losses are not recorded beacon by beacon.
  EXPECT_TRUE(LostBeaconEvents(ReplayOf(Load("channel: { model: iid, loss: 0.3 }\n"))).empty());
}

}  // namespace
}  // namespace syrof::lab::sim
