// The radio channel: loss rates within statistical bounds for fixed seeds,
// determinism, independence from call order, overrides, partitions, and
// Gilbert-Elliott burstiness.
#include "syrof/lab/world/channel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace syrof::lab::world {
namespace {

ChannelSpec Iid(double loss) {
  ChannelSpec spec;
  spec.model = ChannelModel::kIid;
  spec.loss = loss;
  return spec;
}

ChannelSpec GilbertElliott(double good_to_bad, double bad_to_good) {
  ChannelSpec spec;
  spec.model = ChannelModel::kGilbertElliott;
  spec.good_to_bad = good_to_bad;
  spec.bad_to_good = bad_to_good;
  spec.loss_good = 0;
  spec.loss_bad = 1;
  return spec;
}

// Every directed link (no self links) for `rounds` rounds, round-major:
// bit i of the result is the i-th answer.
std::vector<bool> AskAll(Channel& channel, int64_t rounds) {
  std::vector<bool> answers;
  for (int64_t round = 0; round < rounds; ++round) {
    for (uint16_t from = 0; from < channel.robots(); ++from) {
      for (uint16_t to = 0; to < channel.robots(); ++to) {
        if (from != to) {
          answers.push_back(channel.Delivers(from, to, round, 0.05 * static_cast<double>(round)));
        }
      }
    }
  }
  return answers;
}

double LossRate(const std::vector<bool>& answers) {
  double lost = 0;
  for (const bool delivered : answers) {
    lost += delivered ? 0 : 1;
  }
  return lost / static_cast<double>(answers.size());
}

TEST(ChannelTest, IidLossRateIsWithinStatisticalBounds) {
  Channel channel(Iid(0.3), 20, 42);

  const std::vector<bool> answers = AskAll(channel, 500);  // 190,000 beacons

  // Standard error sqrt(0.3 * 0.7 / 190000) = 0.00105; allow 5 of them.
  EXPECT_NEAR(LossRate(answers), 0.3, 0.0053);
  EXPECT_EQ(channel.offered(), answers.size());
  EXPECT_EQ(channel.delivered(), static_cast<uint64_t>(std::llround((1 - LossRate(answers)) * answers.size())));
}

TEST(ChannelTest, NoLossDeliversEverythingAndFullLossNothing) {
  Channel perfect(Iid(0.0), 5, 1);
  Channel dead(Iid(1.0), 5, 1);

  EXPECT_EQ(LossRate(AskAll(perfect, 50)), 0.0);
  EXPECT_EQ(LossRate(AskAll(dead, 50)), 1.0);
}

TEST(ChannelTest, SameSeedGivesTheSameAnswersAndAnotherSeedOthers) {
  Channel first(Iid(0.5), 10, 7);
  Channel again(Iid(0.5), 10, 7);
  Channel other(Iid(0.5), 10, 8);

  const std::vector<bool> first_answers = AskAll(first, 100);
  const std::vector<bool> again_answers = AskAll(again, 100);
  const std::vector<bool> other_answers = AskAll(other, 100);

  EXPECT_EQ(first_answers, again_answers);
  size_t differences = 0;
  for (size_t i = 0; i < first_answers.size(); ++i) {
    differences += first_answers[i] != other_answers[i] ? 1 : 0;
  }
  // Independent seeds at loss 0.5 disagree about half the time.
  EXPECT_NEAR(static_cast<double>(differences) / static_cast<double>(first_answers.size()), 0.5, 0.05);
}

// Asks every (round, from, to) of `rounds` x `robots`^2 in reverse order and
// stores the answers in the forward order of AskAll.
std::vector<bool> AskAllBackwards(Channel& channel, int64_t rounds) {
  const uint16_t robots = channel.robots();
  const size_t per_round = static_cast<size_t>(robots) * (robots - 1);
  std::vector<bool> answers(static_cast<size_t>(rounds) * per_round);
  for (int64_t round = rounds - 1; round >= 0; --round) {
    for (int from = robots - 1; from >= 0; --from) {
      for (int to = robots - 1; to >= 0; --to) {
        if (from == to) {
          continue;
        }
        const size_t index = static_cast<size_t>(round) * per_round + static_cast<size_t>(from) * (robots - 1) +
                             static_cast<size_t>(to < from ? to : to - 1);
        answers[index] = channel.Delivers(static_cast<uint16_t>(from), static_cast<uint16_t>(to), round,
                                          0.05 * static_cast<double>(round));
      }
    }
  }
  return answers;
}

TEST(ChannelTest, IidAnswersDoNotDependOnCallOrder) {
  Channel forward(Iid(0.4), 8, 3);
  Channel backward(Iid(0.4), 8, 3);

  EXPECT_EQ(AskAll(forward, 60), AskAllBackwards(backward, 60));
}

TEST(ChannelTest, GilbertElliottAnswersDoNotDependOnCallOrder) {
  Channel forward(GilbertElliott(0.1, 0.3), 8, 3);
  Channel backward(GilbertElliott(0.1, 0.3), 8, 3);

  EXPECT_EQ(AskAll(forward, 60), AskAllBackwards(backward, 60));
}

TEST(ChannelTest, GilbertElliottStateDoesNotDependOnWhichRoundsWereAsked) {
  Channel every_round(GilbertElliott(0.1, 0.3), 4, 9);
  Channel every_fifth(GilbertElliott(0.1, 0.3), 4, 9);
  std::vector<bool> from_every_round;
  std::vector<bool> from_every_fifth;

  for (int64_t round = 0; round < 500; ++round) {
    const bool answer = every_round.Delivers(1, 2, round, 0);
    if (round % 5 == 0) {
      from_every_round.push_back(answer);
      from_every_fifth.push_back(every_fifth.Delivers(1, 2, round, 0));
    }
  }

  EXPECT_EQ(from_every_round, from_every_fifth);
}

TEST(ChannelTest, PerLinkLossReplacesTheModelsInOneDirectionOnly) {
  ChannelSpec spec = Iid(0.0);
  spec.links.push_back(LinkLossSpec{0, 1, 1.0});
  spec.links.push_back(LinkLossSpec{2, 3, 0.5});
  spec.links.push_back(LinkLossSpec{2, 3, 0.0});  // a later entry wins
  Channel channel(spec, 4, 5);
  int delivered_0_to_1 = 0;
  int delivered_1_to_0 = 0;
  int delivered_2_to_3 = 0;

  for (int64_t round = 0; round < 200; ++round) {
    delivered_0_to_1 += channel.Delivers(0, 1, round, 0) ? 1 : 0;
    delivered_1_to_0 += channel.Delivers(1, 0, round, 0) ? 1 : 0;
    delivered_2_to_3 += channel.Delivers(2, 3, round, 0) ? 1 : 0;
  }

  EXPECT_EQ(delivered_0_to_1, 0);
  EXPECT_EQ(delivered_1_to_0, 200);
  EXPECT_EQ(delivered_2_to_3, 200);
}

TEST(ChannelTest, PerLinkLossReplacesTheGilbertElliottChain) {
  ChannelSpec spec = GilbertElliott(1.0, 0.0);  // every other link goes bad and stays bad
  spec.links.push_back(LinkLossSpec{1, 0, 0.0});
  Channel channel(spec, 2, 5);
  int delivered_0_to_1 = 0;
  int delivered_1_to_0 = 0;

  for (int64_t round = 1; round < 100; ++round) {
    delivered_0_to_1 += channel.Delivers(0, 1, round, 0) ? 1 : 0;
    delivered_1_to_0 += channel.Delivers(1, 0, round, 0) ? 1 : 0;
  }

  EXPECT_EQ(delivered_0_to_1, 0);
  EXPECT_EQ(delivered_1_to_0, 99);
}

// The i.i.d. decision has a fast path (integers, inline) and the general
// one (a draw in [0, 1) against the loss); a partition that never starts
// within the asked rounds sends every question down the general path, with
// the same draws, so both must give the same answers bit for bit, at
// losses whose scaled value is and is not an integer.
TEST(ChannelTest, TheInlineIidDecisionIsTheGeneralOne) {
  for (const double loss : {0.0, 0.05, 0.3, 1.0 / 3.0, 0.5, 1.0}) {
    ChannelSpec far_partition = Iid(loss);
    PartitionSpec partition;
    partition.start_s = 1e6;
    partition.end_s = 2e6;
    partition.groups = {{0}, {1}};
    far_partition.partitions.push_back(partition);
    Channel fast(Iid(loss), 9, 77);
    Channel general(far_partition, 9, 77);
    EXPECT_EQ(AskAll(fast, 40), AskAll(general, 40)) << "loss " << loss;
    EXPECT_EQ(fast.offered(), general.offered());
    EXPECT_EQ(fast.delivered(), general.delivered());
  }
}

TEST(ChannelTest, ACutDropsItsLinkOnlyInItsWindowAndBothWaysOnlyWhenAsked) {
  ChannelSpec spec = Iid(0.0);
  spec.cuts.push_back(CutSpec{.from = 3, .to = 5, .start_s = 1.0, .end_s = 2.0});
  spec.cuts.push_back(CutSpec{.from = 0, .to = 1, .start_s = 1.0, .end_s = 2.0, .both_ways = true});
  Channel channel(spec, 6, 5);
  EXPECT_TRUE(channel.Delivers(3, 5, 10, 0.99));
  EXPECT_FALSE(channel.Delivers(3, 5, 20, 1.0));
  EXPECT_TRUE(channel.Delivers(5, 3, 20, 1.0)) << "one way only";
  EXPECT_TRUE(channel.Delivers(3, 4, 20, 1.0)) << "that link only";
  EXPECT_TRUE(channel.Delivers(3, 5, 40, 2.0)) << "the window is half-open";
  EXPECT_FALSE(channel.Delivers(0, 1, 30, 1.5));
  EXPECT_FALSE(channel.Delivers(1, 0, 30, 1.5));
  EXPECT_EQ(channel.partitioned(), 3u);
  EXPECT_TRUE(CheckChannelSpec(spec, 6) == std::nullopt);
  EXPECT_FALSE(CheckChannelSpec(spec, 5) == std::nullopt) << "robot 5 is beyond 5 robots";
}

TEST(ChannelTest, PartitionDropsCrossGroupBeaconsOnlyInItsWindow) {
  ChannelSpec spec = Iid(0.0);
  PartitionSpec partition;
  partition.start_s = 1.0;
  partition.end_s = 2.0;
  partition.groups = {{0, 1}, {2, 3}};  // 4 and 5 are named nowhere: a third group
  spec.partitions.push_back(partition);
  Channel channel(spec, 6, 5);

  const bool before = channel.Delivers(0, 2, 10, 0.99);
  const bool at_start = channel.Delivers(0, 2, 20, 1.0);
  const bool at_end = channel.Delivers(0, 2, 40, 2.0);
  const bool within_first = channel.Delivers(1, 0, 30, 1.5);
  const bool within_second = channel.Delivers(2, 3, 30, 1.5);
  const bool within_unlisted = channel.Delivers(5, 4, 30, 1.5);
  const bool unlisted_to_listed = channel.Delivers(4, 0, 30, 1.5);
  const bool listed_to_unlisted = channel.Delivers(3, 5, 30, 1.5);

  EXPECT_TRUE(before);
  EXPECT_FALSE(at_start);
  EXPECT_TRUE(at_end);
  EXPECT_TRUE(within_first);
  EXPECT_TRUE(within_second);
  EXPECT_TRUE(within_unlisted);
  EXPECT_FALSE(unlisted_to_listed);
  EXPECT_FALSE(listed_to_unlisted);
  EXPECT_EQ(channel.partitioned(), 3u);
  EXPECT_EQ(channel.offered(), 8u);
  EXPECT_EQ(channel.delivered(), 5u);
}

TEST(ChannelTest, GilbertElliottAverageLossMatchesTheStationaryFormula) {
  ChannelSpec spec = GilbertElliott(0.05, 0.5);
  spec.loss_good = 0.02;
  spec.loss_bad = 0.9;
  Channel channel(spec, 30, 21);

  const double expected = Channel::StationaryLoss(spec);
  const double measured = LossRate(AskAll(channel, 400));  // 348,000 beacons

  EXPECT_NEAR(expected, 0.05 / 0.55 * 0.9 + 0.5 / 0.55 * 0.02, 1e-12);
  // Bursts inflate the standard error (about 0.0005 here) a few times; the
  // bound is still ten times smaller than the loss.
  EXPECT_NEAR(measured, expected, 0.006);
}

// Lengths of the runs of consecutive lost beacons on each link over `rounds`.
double MeanBurstLength(Channel& channel, int64_t rounds) {
  double bursts = 0;
  double lost = 0;
  for (uint16_t from = 0; from < channel.robots(); ++from) {
    for (uint16_t to = 0; to < channel.robots(); ++to) {
      bool previous_lost = false;
      for (int64_t round = 0; round < rounds; ++round) {
        const bool now_lost = !channel.Delivers(from, to, round, 0);
        lost += now_lost ? 1 : 0;
        bursts += now_lost && !previous_lost ? 1 : 0;
        previous_lost = now_lost;
      }
    }
  }
  return lost / bursts;
}

TEST(ChannelTest, GilbertElliottLossesComeInBurstsOfMeanLengthOneOverBadToGood) {
  // Stationary loss 0.02 / 0.22 = 0.091 either way; loss_bad = 1 and
  // loss_good = 0 make bursts exactly the bad sojourns, mean 1 / 0.2 = 5.
  Channel bursty(GilbertElliott(0.02, 0.2), 10, 4);
  Channel iid(Iid(0.02 / 0.22), 10, 4);

  const double bursty_length = MeanBurstLength(bursty, 4000);
  const double iid_length = MeanBurstLength(iid, 4000);

  EXPECT_NEAR(bursty_length, 5.0, 0.4);
  EXPECT_NEAR(iid_length, 1.0 / (1.0 - 0.02 / 0.22), 0.05);
}

TEST(ChannelTest, AskingAnEarlierRoundReplaysTheChain) {
  Channel channel(GilbertElliott(0.2, 0.2), 3, 13);
  Channel fresh(GilbertElliott(0.2, 0.2), 3, 13);

  channel.Delivers(0, 1, 300, 0);
  const bool replayed = channel.Delivers(0, 1, 120, 0);

  EXPECT_EQ(replayed, fresh.Delivers(0, 1, 120, 0));
}

TEST(ChannelTest, CheckChannelSpecSaysWhatIsWrongAndWhere) {
  ChannelSpec beyond = Iid(0.1);
  beyond.links.push_back(LinkLossSpec{0, 9, 0.5});
  ChannelSpec bad_link = Iid(0.1);
  bad_link.links.push_back(LinkLossSpec{0, 2, 1.5});

  auto said = [](const std::optional<Error>& error) { return error ? error->ToString() : std::string("ok"); };
  EXPECT_EQ(said(CheckChannelSpec(Iid(0.1), 4)), "ok");
  EXPECT_EQ(said(CheckChannelSpec(GilbertElliott(0.2, 0.3), 4)), "ok");
  EXPECT_EQ(said(CheckChannelSpec(Iid(1.5), 4)), "loss must be in [0, 1], not 1.500000");
  EXPECT_NE(said(CheckChannelSpec(Iid(std::nan("")), 4)), "ok");
  EXPECT_EQ(said(CheckChannelSpec(GilbertElliott(-0.1, 0.5), 4)),
            "good_to_bad must be in [0, 1], not -0.100000");
  EXPECT_EQ(said(CheckChannelSpec(beyond, 4)), "link 0 -> 9: names a robot beyond the 4 robots");
  EXPECT_EQ(said(CheckChannelSpec(bad_link, 4)), "link 0 -> 2: loss must be in [0, 1], not 1.500000");
}

// A Channel built from a spec that fails the check, or asked about a robot
// it does not have or a negative round, is a caller's bug: the program stops.
TEST(ChannelDeathTest, BadSpecsAndUnknownRobotsStop) {
  ChannelSpec beyond = Iid(0.1);
  beyond.links.push_back(LinkLossSpec{0, 9, 0.5});
  Channel channel(Iid(0.1), 4, 1);

  EXPECT_DEATH_IF_SUPPORTED(Channel(Iid(1.5), 4, 1), "Channel: loss must be in \\[0, 1\\]");
  EXPECT_DEATH_IF_SUPPORTED(Channel(beyond, 4, 1), "Channel: link 0 -> 9: names a robot beyond");
  EXPECT_DEATH_IF_SUPPORTED(channel.Delivers(4, 0, 0, 0), "SYROF_CHECK");
  EXPECT_DEATH_IF_SUPPORTED(channel.Delivers(0, 1, -1, 0), "SYROF_CHECK");
}

TEST(ChannelTest, AScriptedChannelLosesExactlyTheListedBeacons) {
  ChannelSpec spec;
  spec.model = ChannelModel::kScripted;
  spec.lost = {{12, 0, 3}, {12, 1, 3}, {40, 3, 0}, {12, 0, 3}};  // a repeat counts once
  Channel channel(spec, 4, /*seed=*/7);
  int lost = 0;
  for (int64_t round = 0; round < 60; ++round) {
    for (uint16_t from = 0; from < 4; ++from) {
      for (uint16_t to = 0; to < 4; ++to) {
        if (from != to && !channel.Delivers(from, to, round, 0.05 * static_cast<double>(round))) ++lost;
      }
    }
  }
  EXPECT_EQ(lost, 3);
  EXPECT_FALSE(channel.Delivers(0, 3, 12, 0.6));
  EXPECT_TRUE(channel.Delivers(3, 0, 12, 0.6));  // one way only
  EXPECT_TRUE(channel.Delivers(0, 3, 13, 0.65));
}

TEST(ChannelTest, AScriptedChannelStillHasItsPartitions) {
  ChannelSpec spec;
  spec.model = ChannelModel::kScripted;
  spec.partitions = {PartitionSpec{1.0, 2.0, {{0, 1}, {2, 3}}}};
  Channel channel(spec, 4, 1);
  EXPECT_FALSE(channel.Delivers(0, 2, 30, 1.5));
  EXPECT_TRUE(channel.Delivers(0, 1, 30, 1.5));
  EXPECT_TRUE(channel.Delivers(0, 2, 50, 2.5));
}

// A scripted channel once ignored `links`, so a search (which scripts the
// channel) brought a scenario's dead link back to life.
TEST(ChannelTest, AScriptedChannelKeepsItsLinks) {
  ChannelSpec spec;
  spec.model = ChannelModel::kScripted;
  spec.links = {LinkLossSpec{1, 0, 1.0}, LinkLossSpec{2, 0, 0.0}};
  spec.lost = {{4, 2, 0}};
  Channel channel(spec, 3, 5);
  for (int64_t round = 0; round < 50; ++round) {
    const double time_s = 0.05 * static_cast<double>(round);
    EXPECT_FALSE(channel.Delivers(1, 0, round, time_s)) << "round " << round;  // dead
    EXPECT_TRUE(channel.Delivers(0, 1, round, time_s)) << "round " << round;   // the other way lives
    EXPECT_EQ(channel.Delivers(2, 0, round, time_s), round != 4) << "round " << round;  // the script on top
  }
}

TEST(ChannelTest, ScriptedLossesAreChecked) {
  ChannelSpec spec;
  spec.model = ChannelModel::kScripted;
  spec.lost = {{5, 0, 4}};
  ASSERT_TRUE(CheckChannelSpec(spec, 4).has_value());
  EXPECT_NE(CheckChannelSpec(spec, 4)->ToString().find("names a robot beyond the 4 robots"), std::string::npos);
  spec.lost = {{5, 2, 2}};
  EXPECT_NE(CheckChannelSpec(spec, 4)->ToString().find("never hears its own beacon"), std::string::npos);
  spec.lost = {{-1, 0, 1}};
  EXPECT_NE(CheckChannelSpec(spec, 4)->ToString().find("0 or more"), std::string::npos);
  spec.lost = {{5, 0, 1}};
  EXPECT_FALSE(CheckChannelSpec(spec, 4).has_value());
}

}  // namespace
}  // namespace syrof::lab::world
