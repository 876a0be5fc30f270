// The epoch table (lab/replay's epoch_table.h): who started which epoch, in
// which mode, with which members, read from a replay's rounds.
#include "syrof/lab/replay/epoch_table.h"

#include <gtest/gtest.h>

#include <vector>

#include "epoch_runs_test_support.h"
#include "replay_test_support.h"

namespace syrof::lab::replay {
namespace {

using testing::kAutonomous;
using testing::kCooperative;

// Reads `bytes` back and builds the table of what the reader returns.
EpochTable TableOfBytes(const std::string& bytes) {
  const testing::ReadBack read = testing::Read(bytes);
  EXPECT_TRUE(read.complete) << read.error;
  std::istringstream in(bytes);
  Reader reader(in);
  Header header;
  EXPECT_TRUE(reader.ReadHeader(header));
  EpochTableBuilder builder(header, reader.version());
  Round round;
  while (reader.Next(round)) builder.Add(round);
  return std::move(builder).Finish();
}

std::vector<uint16_t> MembersOf(const EpochStart& start) {
  return start.members == nullptr ? std::vector<uint16_t>{} : *start.members;
}

TEST(EpochTableTest, RecordsEachRobotsStartRoundModeAndMembers) {
  testing::SyntheticRun run = testing::SteppedRun(3, 2);
  testing::SetStart(run, testing::StartRoundOf(2), 2, kAutonomous, {2});

  const EpochTable table = TableOfBytes(run.Bytes());

  EXPECT_EQ(table.robot_ids, (std::vector<uint16_t>{0, 1, 2}));
  EXPECT_TRUE(table.has_maps);
  EXPECT_EQ(table.round_count, 5u);
  EXPECT_EQ(table.first_round, 1u);
  EXPECT_EQ(table.last_round, 5u);
  ASSERT_EQ(table.epochs.size(), 2u);
  EXPECT_EQ(table.epochs[0].number, 1);
  EXPECT_EQ(table.epochs[1].number, 2);
  for (const EpochStart& start : table.epochs[0].robots) {
    EXPECT_EQ(start.start_count, 1);
    EXPECT_EQ(start.round, 2u);
    EXPECT_EQ(start.mode, kCooperative);
    EXPECT_EQ(MembersOf(start), (std::vector<uint16_t>{0, 1, 2}));
  }
  const EpochStart& robot2 = table.epochs[1].robots[2];
  EXPECT_EQ(robot2.round, 4u);
  EXPECT_EQ(robot2.mode, kAutonomous);
  EXPECT_EQ(MembersOf(robot2), (std::vector<uint16_t>{2}));
  EXPECT_EQ(table.epochs[1].robots[0].mode, kCooperative);
}

TEST(EpochTableTest, RobotsHandedOneMapShareOneMemberList) {
  const testing::SyntheticRun run = testing::SteppedRun(4, 1);

  const EpochTable table = TableOfBytes(run.Bytes());

  ASSERT_EQ(table.epochs.size(), 1u);
  const std::vector<EpochStart>& robots = table.epochs[0].robots;
  ASSERT_NE(robots[0].members, nullptr);
  for (const EpochStart& start : robots) EXPECT_EQ(start.members.get(), robots[0].members.get());
}

TEST(EpochTableTest, ARobotThatSkipsAnEpochHasNotStartedIt) {
  testing::SyntheticRun run = testing::SteppedRun(3, 3);
  testing::DropStart(run, testing::StartRoundOf(2), 1);

  const EpochTable table = BuildEpochTable(run.header, kFormatVersion, run.rounds);

  ASSERT_EQ(table.epochs.size(), 3u);
  EXPECT_FALSE(table.epochs[1].robots[1].started());
  EXPECT_EQ(table.epochs[1].robots[1].members, nullptr);
  EXPECT_TRUE(table.epochs[1].robots[0].started());
  EXPECT_TRUE(table.epochs[2].robots[1].started());
}

TEST(EpochTableTest, ALateStartJoinsItsEpochsRow) {
  testing::SyntheticRun run = testing::SteppedRun(2, 3);
  // Robot 1 starts epoch 2 only in round 5, after robot 0 did in round 4.
  testing::DropStart(run, testing::StartRoundOf(2), 1);
  Round& late = testing::RoundAt(run, 5);
  late.events.push_back({EventKind::kEpochStart, 1, kNoRobot, 2, kCooperative, late.time_ns});
  late.maps.push_back({1, testing::Map(2, kCooperative, {0, 1})});

  const EpochTable table = BuildEpochTable(run.header, kFormatVersion, run.rounds);

  ASSERT_EQ(table.epochs.size(), 3u);
  EXPECT_EQ(table.epochs[1].number, 2);
  EXPECT_EQ(table.epochs[1].robots[1].round, 5u);
  EXPECT_EQ(MembersOf(table.epochs[1].robots[1]), (std::vector<uint16_t>{0, 1}));
}

TEST(EpochTableTest, EpochNumbersThatWrapKeepTheirOrderInTheFile) {
  // Epochs 65534, 65535, 0, 1: the 0 and 1 come after 65535, not first.
  testing::SyntheticRun run = testing::SteppedRun(2, 4, 65534);
  // Robot 1 starts 65535 late, after robot 0 started 0 (wire): still 65535.
  testing::DropStart(run, testing::StartRoundOf(2), 1);
  Round& late = testing::RoundAt(run, testing::StartRoundOf(3));
  late.events.push_back({EventKind::kEpochStart, 1, kNoRobot, 65535, kCooperative, late.time_ns});

  const EpochTable table = BuildEpochTable(run.header, kFormatVersion, run.rounds);

  ASSERT_EQ(table.epochs.size(), 4u);
  EXPECT_EQ(table.epochs[0].number, 65534);
  EXPECT_EQ(table.epochs[1].number, 65535);
  EXPECT_EQ(table.epochs[2].number, 65536);
  EXPECT_EQ(table.epochs[3].number, 65537);
  EXPECT_EQ(table.epochs[2].wire_epoch(), 0);
  EXPECT_EQ(table.epochs[1].robots[1].round, testing::StartRoundOf(3));
  EXPECT_TRUE(table.epochs[2].robots[1].started());
}

TEST(EpochTableTest, AnEpochStartedTwiceKeepsTheFirstStart) {
  testing::SyntheticRun run = testing::SteppedRun(2, 2);
  Round& again = testing::RoundAt(run, 5);
  again.events.push_back({EventKind::kEpochStart, 0, kNoRobot, 2, kAutonomous, again.time_ns});
  again.maps.push_back({0, testing::Map(2, kAutonomous, {0})});

  const EpochTable table = BuildEpochTable(run.header, kFormatVersion, run.rounds);

  const EpochStart& start = table.epochs[1].robots[0];
  EXPECT_EQ(start.start_count, 2);
  EXPECT_EQ(start.round, 4u);
  EXPECT_EQ(start.mode, kCooperative);
  EXPECT_EQ(MembersOf(start), (std::vector<uint16_t>{0, 1}));
}

// Every row holds an entry per robot, so a hostile file (65,535 robots, an
// EPOCH_START of a new epoch per 20 bytes) could ask for gigabytes.
TEST(EpochTableTest, StopsAtTheRowThatWouldPassItsEntryCap) {
  const testing::SyntheticRun run = testing::SteppedRun(3, 4);
  EpochTableBuilder builder(run.header, kFormatVersion, 9);  // three rows of three robots

  for (const Round& round : run.rounds) {
    if (!builder.Add(round)) break;
  }

  EXPECT_TRUE(builder.full());
  const EpochTable table = std::move(builder).Finish();
  ASSERT_EQ(table.epochs.size(), 3u);
  EXPECT_EQ(table.last_round, testing::StartRoundOf(4));
}

TEST(EpochTableTest, AVersion2FileHasStartsButNoMembers) {
  const std::vector<uint8_t>& golden = testing::GoldenFileVersion2();

  const EpochTable table = TableOfBytes(std::string(golden.begin(), golden.end()));

  EXPECT_FALSE(table.has_maps);
  EXPECT_EQ(table.robot_ids, (std::vector<uint16_t>{7}));
  ASSERT_EQ(table.epochs.size(), 1u);
  EXPECT_EQ(table.epochs[0].number, 258);
  EXPECT_EQ(table.epochs[0].robots[0].mode, 1);
  EXPECT_EQ(table.epochs[0].robots[0].members, nullptr);
}

}  // namespace
}  // namespace syrof::lab::replay
