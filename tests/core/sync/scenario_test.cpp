// Scripted swarms: the situations docs/protocol.md must handle, each checked
// against the properties (P1 synchrony, P3 common knowledge, P6 membership).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "swarm_test_support.h"

namespace syrof::sync::testing {
namespace {

constexpr uint8_t kVoteRounds = 3;       // K
constexpr uint16_t kSilenceRounds = 6;   // F
constexpr uint16_t kManeuverRounds = 10; // 0.5 s at 20 Hz

Swarm MakeSwarm(uint16_t n, std::vector<uint16_t> late = {}) {
  return Swarm(n, kVoteRounds, kSilenceRounds, kManeuverRounds, std::move(late));
}

// Every epoch that anyone started was started by all of `ids` in one round.
void ExpectLockstep(const Swarm& swarm, const std::set<uint16_t>& ids) {
  for (const auto& [epoch, list] : swarm.starts()) {
    std::set<uint16_t> starters;
    for (const EpochStart& start : list) {
      starters.insert(start.robot);
      EXPECT_EQ(start.round, list.front().round) << "epoch " << epoch;
    }
    EXPECT_EQ(starters, ids) << "epoch " << epoch;
  }
}

TEST(SyncScenarioTest, NoLossEveryEpochStartsTogetherAndCooperative) {
  Swarm swarm = MakeSwarm(5);
  swarm.Run(300, Swarm::Lossless);
  ExpectLockstep(swarm, {0, 1, 2, 3, 4});
  EXPECT_GE(swarm.starts().size(), 15u);
  for (uint16_t id = 0; id < 5; ++id) {
    const auto [started, cooperative] = swarm.EpochsOf(id);
    EXPECT_EQ(started, cooperative) << "robot " << id;
  }
  EXPECT_EQ(swarm.MaxStartSkew(), 0);
  EXPECT_EQ(swarm.CommonKnowledgeViolations(), 0);
  // Every COOPERATIVE map holds each member's snapshot of the epoch before.
  for (const auto& [epoch, list] : swarm.starts()) {
    for (const EpochStart& start : list) {
      for (uint16_t id = 0; id < 5; ++id) {
        EXPECT_EQ(start.ldmap.snapshots[id], SnapshotFor(id, static_cast<uint16_t>(epoch - 1)));
      }
    }
  }
}

TEST(SyncScenarioTest, BurstOfKMinusOneLossesKeepsLockstep) {
  Swarm swarm = MakeSwarm(5);
  // Every link loses K - 1 consecutive beacons, at every phase offset over time.
  swarm.Run(400, [](uint16_t from, uint16_t to, int round) {
    const int offset = (from * 7 + to * 3) % 23;
    return (round + offset) % 23 >= kVoteRounds - 1;
  });
  ExpectLockstep(swarm, {0, 1, 2, 3, 4});
  EXPECT_EQ(swarm.CommonKnowledgeViolations(), 0);
  EXPECT_TRUE(swarm.removals().empty());
}

TEST(SyncScenarioTest, BurstLongerThanKIsSafeAndRecovers) {
  Swarm swarm = MakeSwarm(5);
  // Robots 3 and 4 hear nobody for K + 2 rounds, twice.
  swarm.Run(300, [](uint16_t, uint16_t to, int round) {
    const bool burst = (round >= 40 && round < 45) || (round >= 130 && round < 135);
    return !(burst && to >= 3);
  });
  EXPECT_EQ(swarm.CommonKnowledgeViolations(), 0);
  EXPECT_TRUE(swarm.removals().empty()) << "K + 2 < F: nobody is removed";
  // After the bursts the swarm is back in lockstep and COOPERATIVE.
  const auto& last = std::prev(swarm.starts().end())->second;
  EXPECT_EQ(last.size(), 5u);
  for (const EpochStart& start : last) EXPECT_EQ(start.ldmap.mode, Mode::kCooperative);
}

TEST(SyncScenarioTest, PartitionThatHealsMajorityContinuesMinorityWaitsThenAllRejoin) {
  Swarm swarm = MakeSwarm(5);
  auto side = [](uint16_t id) { return id < 3 ? 0 : 1; };
  swarm.Run(400, [&](uint16_t from, uint16_t to, int round) {
    return round < 60 || round >= 200 || side(from) == side(to);
  });
  EXPECT_EQ(swarm.CommonKnowledgeViolations(), 0);
  for (const auto& [epoch, list] : swarm.starts()) {
    for (const EpochStart& start : list) {
      if (start.round < 60 + kSilenceRounds || start.round >= 200) continue;
      if (side(start.robot) == 1) {
        EXPECT_EQ(start.ldmap.mode, Mode::kAutonomous) << "2 of 5 is no quorum";
      }
    }
  }
  // The majority kept cooperating during the partition.
  int majority_cooperative = 0;
  for (const auto& [epoch, list] : swarm.starts()) {
    for (const EpochStart& start : list) {
      if (start.round > 100 && start.round < 200 && start.ldmap.mode == Mode::kCooperative) {
        EXPECT_EQ(side(start.robot), 0);
        EXPECT_EQ(start.ldmap.members.count(), 3);
        ++majority_cooperative;
      }
    }
  }
  EXPECT_GT(majority_cooperative, 0);
  // Healed: the last epoch is started by all five, COOPERATIVE, with all five.
  const auto& last = std::prev(swarm.starts().end())->second;
  ASSERT_EQ(last.size(), 5u);
  for (const EpochStart& start : last) {
    EXPECT_EQ(start.ldmap.mode, Mode::kCooperative);
    EXPECT_EQ(start.ldmap.members.count(), 5);
  }
}

TEST(SyncScenarioTest, AsymmetricLossIsSafeAndEpochsKeepStarting) {
  Swarm swarm = MakeSwarm(3);
  // Robot 1 hears robot 0; robot 0 never hears robot 1.
  swarm.Run(400, [](uint16_t from, uint16_t to, int) { return !(from == 1 && to == 0); });
  EXPECT_EQ(swarm.CommonKnowledgeViolations(), 0);
  for (uint16_t id = 0; id < 3; ++id) {
    const auto [started, cooperative] = swarm.EpochsOf(id);
    EXPECT_GE(started, 10) << "robot " << id << " keeps starting epochs";
  }
}

TEST(SyncScenarioTest, CrashOfTheLeaderIsRemovedEverywhereWithinFAndNeverBlocks) {
  Swarm swarm = MakeSwarm(5);
  swarm.Run(50, Swarm::Lossless);
  const int crash_round = swarm.round();
  swarm.Crash(0);
  swarm.Run(250, Swarm::Lossless);
  std::set<uint16_t> removed_by;
  for (const auto& event : swarm.removals()) {
    EXPECT_EQ(event.subject, 0);
    EXPECT_LE(event.round - crash_round, kSilenceRounds);
    removed_by.insert(event.observer);
  }
  EXPECT_EQ(removed_by, (std::set<uint16_t>{1, 2, 3, 4}));
  EXPECT_EQ(swarm.CommonKnowledgeViolations(), 0);
  const auto& last = std::prev(swarm.starts().end())->second;
  ASSERT_EQ(last.size(), 4u);
  for (const EpochStart& start : last) {
    EXPECT_EQ(start.ldmap.mode, Mode::kCooperative);
    EXPECT_FALSE(start.ldmap.members.test(0));
  }
  EXPECT_GE(swarm.EpochsOf(1).first, 12);
}

TEST(SyncScenarioTest, TwoRobotsJoiningInTheSameRoundAppearInEveryMapWithinTwoEpochs) {
  Swarm swarm = MakeSwarm(6, {4, 5});
  swarm.Run(60, Swarm::Lossless);
  swarm.SwitchOn(4);
  swarm.SwitchOn(5);
  swarm.Run(200, Swarm::Lossless);
  EXPECT_EQ(swarm.CommonKnowledgeViolations(), 0);
  // The joiners' first epoch: the boundary after they were switched on.
  uint16_t first_epoch = 0;
  for (const auto& [epoch, list] : swarm.starts()) {
    for (const EpochStart& start : list) {
      if (start.robot == 4 && first_epoch == 0) first_epoch = epoch;
    }
  }
  ASSERT_NE(first_epoch, 0);
  const uint16_t in_every_map = static_cast<uint16_t>(first_epoch + 1);
  for (const auto& [epoch, list] : swarm.starts()) {
    if (epoch < in_every_map) continue;
    EXPECT_EQ(list.size(), 6u) << "epoch " << epoch;
    for (const EpochStart& start : list) {
      EXPECT_TRUE(start.ldmap.members.test(4) && start.ldmap.members.test(5)) << "epoch " << epoch;
      EXPECT_EQ(start.ldmap.mode, Mode::kCooperative);
    }
  }
}

}  // namespace
}  // namespace syrof::sync::testing
