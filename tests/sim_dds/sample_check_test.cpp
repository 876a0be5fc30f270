#include "syrof/sim_dds/sample_check.h"

#include <gtest/gtest.h>

#include <vector>

#include "syrof/wire/beacon_codec.h"

namespace syrof::sim_dds {
namespace {

constexpr uint16_t kSwarm = 5;

std::vector<uint8_t> Bytes(uint16_t robot_id, uint16_t swarm = kSwarm) {
  wire::Beacon beacon;
  beacon.robot_id = robot_id;
  beacon.epoch = 3;
  beacon.snapshot.x_mm = 120;
  std::vector<uint8_t> bytes(wire::EncodedSize(swarm));
  const auto size = wire::Encode(beacon, swarm, bytes);
  EXPECT_TRUE(size.ok());
  return bytes;
}

SampleVerdict Check(uint16_t sender, uint32_t round, const std::vector<uint8_t>& bytes, int64_t current = 10,
                    int64_t last = -1) {
  wire::Beacon beacon;
  return CheckSample(sender, round, bytes, ReceiverView{.self = 0, .swarm_size = kSwarm, .current_round = current,
                                                        .last_round_from_sender = last},
                     beacon);
}

TEST(SampleCheck, AcceptsAGoodBeaconAndDecodesIt) {
  wire::Beacon beacon;
  const auto bytes = Bytes(2);
  ASSERT_EQ(CheckSample(2, 10, bytes, ReceiverView{.self = 0, .swarm_size = kSwarm, .current_round = 10}, beacon),
            SampleVerdict::kAccepted);
  EXPECT_EQ(beacon.robot_id, 2);
  EXPECT_EQ(beacon.snapshot.x_mm, 120);
}

TEST(SampleCheck, EachReason) {
  auto longer = Bytes(2);
  longer.push_back(0);
  EXPECT_EQ(Check(2, 10, longer), SampleVerdict::kOversized);
  EXPECT_EQ(Check(2, 10, std::vector<uint8_t>(2000, 0xAB)), SampleVerdict::kOversized);
  EXPECT_EQ(Check(5, 10, Bytes(2)), SampleVerdict::kSenderOutOfSwarm);
  EXPECT_EQ(Check(65535, 10, Bytes(2)), SampleVerdict::kSenderOutOfSwarm);
  EXPECT_EQ(Check(0, 10, Bytes(0)), SampleVerdict::kFromSelf);
  auto wrong_version = Bytes(2);
  wrong_version[0] = 9;
  EXPECT_EQ(Check(2, 10, wrong_version), SampleVerdict::kMalformed);
  EXPECT_EQ(Check(2, 10, std::vector<uint8_t>{}), SampleVerdict::kMalformed);
  auto shorter = Bytes(2);
  shorter.pop_back();
  EXPECT_EQ(Check(2, 10, shorter), SampleVerdict::kMalformed);
  EXPECT_EQ(Check(3, 10, Bytes(2)), SampleVerdict::kSenderMismatch);
  EXPECT_EQ(Check(2, 7, Bytes(2)), SampleVerdict::kRoundOutOfWindow);
  EXPECT_EQ(Check(2, 13, Bytes(2)), SampleVerdict::kRoundOutOfWindow);
  EXPECT_EQ(Check(2, 10, Bytes(2), 10, 10), SampleVerdict::kDuplicate);
  EXPECT_EQ(Check(2, 9, Bytes(2), 10, 10), SampleVerdict::kDuplicate);
}

TEST(SampleCheck, TheWindowIsTwoRoundsEachWay) {
  for (uint32_t round = 8; round <= 12; ++round) EXPECT_EQ(Check(2, round, Bytes(2)), SampleVerdict::kAccepted) << round;
  // Before the run starts there is no round to compare with.
  EXPECT_EQ(Check(2, 4000000000u, Bytes(2), -1), SampleVerdict::kAccepted);
}

TEST(SampleCheck, FirstFailingCheckNamesTheReason) {
  // Oversized and from a sender beyond the swarm: size is checked first.
  EXPECT_EQ(Check(9, 10, std::vector<uint8_t>(500, 0)), SampleVerdict::kOversized);
  // Garbage claiming to be from the receiver: from_self before malformed.
  EXPECT_EQ(Check(0, 10, std::vector<uint8_t>(3, 0xFF)), SampleVerdict::kFromSelf);
  // Wrong id and an old round: the mismatch is named.
  EXPECT_EQ(Check(3, 1, Bytes(2)), SampleVerdict::kSenderMismatch);
}

TEST(SampleFilter, CountsByReasonAndRemembersRounds) {
  SampleFilter filter(0, kSwarm);
  wire::Beacon beacon;
  EXPECT_EQ(filter.Check(2, 10, Bytes(2), 10, beacon), SampleVerdict::kAccepted);
  EXPECT_EQ(filter.Check(2, 10, Bytes(2), 10, beacon), SampleVerdict::kDuplicate);
  EXPECT_EQ(filter.Check(3, 10, Bytes(3), 10, beacon), SampleVerdict::kAccepted);  // per sender
  EXPECT_EQ(filter.Check(2, 11, Bytes(2), 11, beacon), SampleVerdict::kAccepted);
  EXPECT_EQ(filter.Check(2, 3, Bytes(2), 11, beacon), SampleVerdict::kRoundOutOfWindow);
  EXPECT_EQ(filter.Check(7, 11, Bytes(2), 11, beacon), SampleVerdict::kSenderOutOfSwarm);
  EXPECT_EQ(filter.counters().accepted(), 3u);
  EXPECT_EQ(filter.counters().count(SampleVerdict::kDuplicate), 1u);
  EXPECT_EQ(filter.counters().count(SampleVerdict::kRoundOutOfWindow), 1u);
  EXPECT_EQ(filter.counters().count(SampleVerdict::kSenderOutOfSwarm), 1u);
  EXPECT_EQ(filter.counters().rejected(), 3u);
}

// Two runs on one domain (issue 46): a sample of another run never reaches
// the other checks, and is counted by its own reason.
TEST(SampleFilter, RefusesSamplesOfAnotherRun) {
  EXPECT_EQ(CheckRun(42, 42), SampleVerdict::kAccepted);
  EXPECT_EQ(CheckRun(43, 42), SampleVerdict::kOtherRun);
  EXPECT_EQ(CheckRun(0, 42), SampleVerdict::kOtherRun);  // the bridge's relayed beacons are no run's robots
  SampleFilter filter(0, kSwarm, 42);
  EXPECT_EQ(filter.CheckRun(7), SampleVerdict::kOtherRun);
  EXPECT_EQ(filter.CheckRun(42), SampleVerdict::kAccepted);
  EXPECT_EQ(filter.counters().count(SampleVerdict::kOtherRun), 1u);
  EXPECT_EQ(filter.counters().accepted(), 0u);  // Check counts the accepted ones
  EXPECT_EQ(filter.counters().rejected(), 1u);
  EXPECT_STREQ(ToString(SampleVerdict::kOtherRun), "other_run");
}

TEST(SampleVerdictNames, EveryVerdictHasOne) {
  for (int verdict = 0; verdict < kSampleVerdicts; ++verdict) {
    EXPECT_STRNE(ToString(static_cast<SampleVerdict>(verdict)), "?") << verdict;
  }
  EXPECT_STREQ(ToString(SampleVerdict::kRoundOutOfWindow), "round_out_of_window");
}

// Round alignment: robots number their own rounds and take the swarm's count.
TEST(AgreedRoundOffsetTest, NoneWhenTheSendersAgreeOrNoneWasHeard) {
  EXPECT_EQ(AgreedRoundOffset({}, 5), 0);
  const std::vector<SenderRoundOffset> agree = {{10, 0}, {10, 0}, {-1, 0}, {9, 0}};
  EXPECT_EQ(AgreedRoundOffset(agree, 9), 0);
}

TEST(AgreedRoundOffsetTest, ALateJoinerTakesTheCountMostSendersAreAheadBy) {
  // Three of four senders heard since round 9 are 3 ahead; one is 1 ahead.
  const std::vector<SenderRoundOffset> offsets = {{10, 3}, {10, 3}, {9, 1}, {10, 3}, {-1, 0}};
  EXPECT_EQ(AgreedRoundOffset(offsets, 9), 3);
  // From round 10 on only the three that are 3 ahead were heard.
  EXPECT_EQ(AgreedRoundOffset(offsets, 10), 3);
  // A sender heard long ago (round 4) is left out.
  const std::vector<SenderRoundOffset> stale = {{4, 2}, {10, 0}, {10, 0}};
  EXPECT_EQ(AgreedRoundOffset(stale, 9), 0);
}

TEST(AgreedRoundOffsetTest, AheadNeedsMoreThanHalfOfTheSendersHeard) {
  const std::vector<SenderRoundOffset> half = {{10, 1}, {10, 1}, {10, 0}, {10, 0}};
  EXPECT_EQ(AgreedRoundOffset(half, 10), 0);
  const std::vector<SenderRoundOffset> two_of_three = {{10, 1}, {10, 1}, {10, 0}};
  EXPECT_EQ(AgreedRoundOffset(two_of_three, 10), 1);
  // A two-robot swarm: the one behind takes the other's count.
  const std::vector<SenderRoundOffset> pair = {{10, 2}};
  EXPECT_EQ(AgreedRoundOffset(pair, 10), 2);
}

TEST(AgreedRoundOffsetTest, BehindOnlyWhenEverySenderOfAtLeastTwoIsBehindBySameCount) {
  // A robot that started counting ahead of the swarm moves back...
  const std::vector<SenderRoundOffset> all_behind = {{10, -2}, {10, -2}, {10, -2}};
  EXPECT_EQ(AgreedRoundOffset(all_behind, 10), -2);
  // ... but not because of one sender (its partner in a pair moves instead),
  const std::vector<SenderRoundOffset> pair = {{10, -2}};
  EXPECT_EQ(AgreedRoundOffset(pair, 10), 0);
  // nor when some agree: in two halves that disagree only the half behind
  // moves, so they never swap counts.
  const std::vector<SenderRoundOffset> halves = {{10, -1}, {10, -1}, {10, 0}};
  EXPECT_EQ(AgreedRoundOffset(halves, 10), 0);
}

}  // namespace
}  // namespace syrof::sim_dds
