// Comparing two runs (lab/replay's comparison.h): the first epoch where the
// started set, a mode or the members differ; positions round by round; and
// two replay streams read side by side.
#include "syrof/lab/replay/comparison.h"

#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "epoch_runs_test_support.h"
#include "replay_test_support.h"

namespace syrof::lab::replay {
namespace {

using testing::kAutonomous;
using testing::kCooperative;
using testing::StartRoundOf;
using testing::SteppedRun;
using testing::SyntheticRun;

EpochTable TableOf(const SyntheticRun& run) { return BuildEpochTable(run.header, kFormatVersion, run.rounds); }

ReplayComparison CompareBytes(const std::string& a, const std::string& b, ComparisonOptions options = {}) {
  std::istringstream in_a(a);
  std::istringstream in_b(b);
  return CompareReplays(in_a, in_b, options);
}

TEST(CompareEpochsTest, TheSameRunAgreesOnEveryEpoch) {
  const SyntheticRun run = SteppedRun(4, 6);

  const EpochComparison comparison = CompareEpochs(TableOf(run), TableOf(run));

  EXPECT_FALSE(comparison.first_difference.has_value());
  EXPECT_EQ(comparison.epochs_compared, 6u);
  EXPECT_EQ(comparison.first_epoch, 1);
  EXPECT_EQ(comparison.last_epoch, 6);
  EXPECT_TRUE(comparison.members_compared);
  EXPECT_EQ(comparison.a_epochs_after + comparison.b_epochs_after, 0u);
}

TEST(CompareEpochsTest, OneRobotsModeAtEpochKIsReportedAtK) {
  const SyntheticRun a = SteppedRun(4, 6);
  SyntheticRun b = a;
  // Same members, only the mode differs, from epoch 4 on.
  for (uint16_t epoch = 4; epoch <= 6; ++epoch) {
    testing::SetStart(b, StartRoundOf(epoch), 2, kAutonomous, {0, 1, 2, 3});
  }

  const EpochComparison comparison = CompareEpochs(TableOf(a), TableOf(b));

  ASSERT_TRUE(comparison.first_difference.has_value());
  const EpochDisagreement& first = *comparison.first_difference;
  EXPECT_EQ(first.number, 4);
  ASSERT_EQ(first.robots.size(), 1u);
  EXPECT_EQ(first.robots[0].robot, 2);
  EXPECT_EQ(first.robots[0].fields, kModeField);
  EXPECT_EQ(first.fields, kModeField);
  EXPECT_EQ(first.a.robots[2].mode, kCooperative);
  EXPECT_EQ(first.b.robots[2].mode, kAutonomous);
  EXPECT_EQ(comparison.epochs_compared, 4u);  // 1 .. 4, stopped at the first difference
}

TEST(CompareEpochsTest, OneRobotsMembersAtEpochKAreReportedAtK) {
  const SyntheticRun a = SteppedRun(4, 6);
  SyntheticRun b = a;
  testing::SetStart(b, StartRoundOf(5), 0, kCooperative, {0, 1, 3});

  const EpochComparison comparison = CompareEpochs(TableOf(a), TableOf(b));

  ASSERT_TRUE(comparison.first_difference.has_value());
  EXPECT_EQ(comparison.first_difference->number, 5);
  ASSERT_EQ(comparison.first_difference->robots.size(), 1u);
  EXPECT_EQ(comparison.first_difference->robots[0].robot, 0);
  EXPECT_EQ(comparison.first_difference->robots[0].fields, kMembersField);
  EXPECT_EQ(*comparison.first_difference->b.robots[0].members, (std::vector<uint16_t>{0, 1, 3}));
}

TEST(CompareEpochsTest, PayloadsAreComparedOnlyWhenAskedAndReportedAtTheirEpoch) {
  SyntheticRun a = SteppedRun(3, 6);
  testing::SetPayload(a, StartRoundOf(2), 1, {'C', 0x62, 0x03});
  SyntheticRun b = a;
  testing::SetPayload(b, StartRoundOf(4), 2, {'C', 0x17});  // another app state, the same members

  const EpochComparison without = CompareEpochs(TableOf(a), TableOf(b));
  const EpochComparison with = CompareEpochs(TableOf(a), TableOf(b), /*compare_payloads=*/true);

  EXPECT_FALSE(without.first_difference.has_value());
  EXPECT_FALSE(without.payloads_compared);
  EXPECT_TRUE(with.payloads_compared);
  ASSERT_TRUE(with.first_difference.has_value());
  const EpochDisagreement& first = *with.first_difference;
  EXPECT_EQ(first.number, 4);
  EXPECT_EQ(first.fields, kPayloadsField);
  ASSERT_EQ(first.robots.size(), 3u);  // each robot's map holds robot 2's payload
  EXPECT_EQ(MembersWithOtherPayloads(first.a.robots[0], first.b.robots[0]), (std::vector<uint16_t>{2}));
  EXPECT_EQ((*first.b.robots[0].payloads)[2], (std::vector<uint8_t>{'C', 0x17}));
}

TEST(CompareEpochsTest, EqualPayloadsAgreeAndMembersThatDifferAreNotPayloadDifferences) {
  SyntheticRun a = SteppedRun(3, 4);
  testing::SetPayload(a, StartRoundOf(3), 0, {1, 2, 3});
  SyntheticRun b = a;

  EXPECT_FALSE(CompareEpochs(TableOf(a), TableOf(b), true).first_difference.has_value());

  testing::SetStart(b, StartRoundOf(3), 0, kCooperative, {0, 1});
  const EpochComparison comparison = CompareEpochs(TableOf(a), TableOf(b), true);
  ASSERT_TRUE(comparison.first_difference.has_value());
  EXPECT_EQ(comparison.first_difference->robots[0].fields, kMembersField);
}

TEST(CompareEpochsTest, ARobotThatStartedInOneRunOnlyIsAStartedDifference) {
  const SyntheticRun a = SteppedRun(3, 5);
  SyntheticRun b = a;
  testing::DropStart(b, StartRoundOf(3), 1);

  const EpochComparison comparison = CompareEpochs(TableOf(a), TableOf(b));

  ASSERT_TRUE(comparison.first_difference.has_value());
  EXPECT_EQ(comparison.first_difference->number, 3);
  ASSERT_EQ(comparison.first_difference->robots.size(), 1u);
  EXPECT_EQ(comparison.first_difference->robots[0].fields, kStartedField);
  EXPECT_TRUE(comparison.first_difference->a.robots[1].started());
  EXPECT_FALSE(comparison.first_difference->b.robots[1].started());
}

TEST(CompareEpochsTest, AnEpochMissingFromOneRunIsReported) {
  const SyntheticRun a = SteppedRun(2, 5);
  SyntheticRun b = a;
  testing::DropStart(b, StartRoundOf(2), 0);
  testing::DropStart(b, StartRoundOf(2), 1);

  const EpochComparison comparison = CompareEpochs(TableOf(a), TableOf(b));

  ASSERT_TRUE(comparison.first_difference.has_value());
  EXPECT_EQ(comparison.first_difference->number, 2);
  EXPECT_EQ(comparison.first_difference->robots.size(), 2u);
  EXPECT_FALSE(comparison.first_difference->b.robots[0].started());
}

TEST(CompareEpochsTest, ALongerRunIsComparedOnTheRoundsBothHold) {
  const SyntheticRun longer = SteppedRun(3, 8);
  SyntheticRun shorter = longer;
  testing::CutAfter(shorter, StartRoundOf(5) + 1);

  const EpochComparison comparison = CompareEpochs(TableOf(shorter), TableOf(longer));

  EXPECT_FALSE(comparison.first_difference.has_value());
  EXPECT_EQ(comparison.last_common_round, StartRoundOf(5) + 1);
  EXPECT_EQ(comparison.epochs_compared, 5u);
  EXPECT_EQ(comparison.a_epochs_after, 0u);
  EXPECT_EQ(comparison.b_epochs_after, 3u);
  EXPECT_EQ(comparison.b_first_after, 6);
  EXPECT_EQ(comparison.b_last_after, 8);
}

TEST(CompareEpochsTest, AnEpochCutShortByTheShorterRunIsNotADifference) {
  // The longer run's robot 2 starts epoch 3 a round after the others, in a
  // round the shorter run does not hold.
  SyntheticRun longer = SteppedRun(3, 4);
  testing::DropStart(longer, StartRoundOf(3), 2);
  Round& late = testing::RoundAt(longer, StartRoundOf(3) + 1);
  late.events.push_back({EventKind::kEpochStart, 2, kNoRobot, 3, kCooperative, late.time_ns});
  late.maps.push_back({2, testing::Map(3, kCooperative, {0, 1, 2})});
  SyntheticRun shorter = longer;
  testing::CutAfter(shorter, StartRoundOf(3));

  SyntheticRun never_started = longer;  // as long, but robot 2 never starts epoch 3
  testing::DropStart(never_started, StartRoundOf(3) + 1, 2);

  const EpochComparison cut = CompareEpochs(TableOf(shorter), TableOf(longer));
  const EpochComparison whole = CompareEpochs(TableOf(never_started), TableOf(longer));

  EXPECT_FALSE(cut.first_difference.has_value());
  EXPECT_EQ(cut.epochs_compared, 3u);
  ASSERT_TRUE(whole.first_difference.has_value());  // when both runs hold the round, the start counts
  EXPECT_EQ(whole.first_difference->number, 3);
  EXPECT_EQ(whole.first_difference->robots[0].fields, kStartedField);
}

TEST(CompareEpochsTest, AfterAWrapEpochsKeepTheirOrderInTheFile) {
  // Epochs 65534, 65535, 0, 1, 2: the wrapped 0 comes after 65535.
  const SyntheticRun a = SteppedRun(2, 5, 65534);
  SyntheticRun both = a;
  testing::SetStart(both, StartRoundOf(2), 0, kAutonomous, {0});  // wire epoch 65535
  testing::SetStart(both, StartRoundOf(3), 1, kAutonomous, {1});  // wire epoch 0
  SyntheticRun wrapped_only = a;
  testing::SetStart(wrapped_only, StartRoundOf(3), 1, kAutonomous, {1});

  const EpochComparison first_of_two = CompareEpochs(TableOf(a), TableOf(both));
  const EpochComparison wrapped = CompareEpochs(TableOf(a), TableOf(wrapped_only));

  ASSERT_TRUE(first_of_two.first_difference.has_value());
  EXPECT_EQ(first_of_two.first_difference->number, 65535);
  EXPECT_EQ(first_of_two.first_difference->robots[0].robot, 0);
  ASSERT_TRUE(wrapped.first_difference.has_value());
  EXPECT_EQ(wrapped.first_difference->number, 65536);
  EXPECT_EQ(wrapped.first_difference->a.wire_epoch(), 0);
  EXPECT_EQ(wrapped.first_difference->robots[0].robot, 1);
  EXPECT_EQ(wrapped.first_epoch, 65534);
}

TEST(CompareEpochsTest, MembersAreNotComparedWhenARunRecordsNoMaps) {
  const SyntheticRun a = SteppedRun(3, 3);
  SyntheticRun b = a;
  testing::SetStart(b, StartRoundOf(2), 0, kCooperative, {0});

  const EpochComparison comparison =
      CompareEpochs(BuildEpochTable(a.header, 2, a.rounds), BuildEpochTable(b.header, kFormatVersion, b.rounds));

  EXPECT_FALSE(comparison.members_compared);
  EXPECT_FALSE(comparison.first_difference.has_value());
}

TEST(ComparePositionsTest, ReportsTheRobotsFartherApartThanTheTolerance) {
  const SyntheticRun a = SteppedRun(3, 1);
  SyntheticRun b = a;
  b.rounds[0].robots[1].true_x_m += 0.03f;  // 3 cm
  b.rounds[0].robots[2].true_y_m -= 0.2f;   // 20 cm

  const std::vector<PositionDifference> loose = ComparePositions(a.rounds[0], b.rounds[0], 0.5);
  const std::vector<PositionDifference> medium = ComparePositions(a.rounds[0], b.rounds[0], 0.1);
  const std::vector<PositionDifference> tight = ComparePositions(a.rounds[0], b.rounds[0], 0.01);

  EXPECT_TRUE(loose.empty());
  ASSERT_EQ(medium.size(), 1u);
  EXPECT_EQ(medium[0].robot, 2);
  EXPECT_NEAR(medium[0].distance_m, 0.2, 1e-6);
  ASSERT_EQ(tight.size(), 2u);
  EXPECT_EQ(tight[0].robot, 1);
  EXPECT_NEAR(tight[0].distance_m, 0.03, 1e-6);
}

TEST(ComparePositionsTest, ANotANumberOnOneSideIsADifference) {
  const SyntheticRun a = SteppedRun(2, 1);
  SyntheticRun b = a;
  b.rounds[0].robots[0].true_x_m = std::numeric_limits<float>::quiet_NaN();

  EXPECT_EQ(ComparePositions(a.rounds[0], b.rounds[0], 1.0).size(), 1u);
  EXPECT_TRUE(ComparePositions(b.rounds[0], b.rounds[0], 1.0).empty());
}

TEST(CompareReplaysTest, ReadsBothFilesAndFindsTheFirstDifferences) {
  const SyntheticRun a = SteppedRun(3, 5);
  SyntheticRun b = a;
  testing::SetStart(b, StartRoundOf(4), 1, kAutonomous, {1});
  testing::RoundAt(b, 3).robots[0].true_x_m += 0.5f;

  const ReplayComparison result = CompareBytes(a.Bytes(), b.Bytes(), {.pose_tolerance_m = 0.1});

  EXPECT_TRUE(result.comparable());
  ASSERT_TRUE(result.epochs.first_difference.has_value());
  EXPECT_EQ(result.epochs.first_difference->number, 4);
  EXPECT_EQ(result.epochs.first_difference->fields, kModeField | kMembersField);
  ASSERT_TRUE(result.first_position_difference.has_value());
  EXPECT_EQ(result.first_position_difference->round, 3u);
  EXPECT_EQ(result.rounds_position_compared, 3u);
  EXPECT_EQ(result.a.header.scenario_name, "three_robots");
}

TEST(CompareReplaysTest, PayloadsAreReadFromTheFilesMaps) {
  SyntheticRun a = SteppedRun(2, 3);
  testing::SetPayload(a, StartRoundOf(1), 0, {'G', 1});
  SyntheticRun b = a;
  testing::SetPayload(b, StartRoundOf(2), 0, {'G', 2});

  const ReplayComparison result = CompareBytes(a.Bytes(), b.Bytes(), {.pose_tolerance_m = std::nullopt, .compare_payloads = true});

  ASSERT_TRUE(result.epochs.first_difference.has_value());
  EXPECT_EQ(result.epochs.first_difference->number, 2);
  EXPECT_EQ(result.epochs.first_difference->fields, kPayloadsField);
  EXPECT_FALSE(CompareBytes(a.Bytes(), b.Bytes()).epochs.first_difference.has_value());
}

TEST(CompareReplaysTest, PositionsAreComparedOnlyWhenAsked) {
  const SyntheticRun a = SteppedRun(2, 2);
  SyntheticRun b = a;
  testing::RoundAt(b, 2).robots[1].true_y_m += 1.0f;

  const ReplayComparison result = CompareBytes(a.Bytes(), b.Bytes());

  EXPECT_FALSE(result.first_position_difference.has_value());
  EXPECT_EQ(result.rounds_position_compared, 0u);
  EXPECT_FALSE(result.epochs.first_difference.has_value());
}

TEST(CompareReplaysTest, DifferentRobotSetsAreNamedAndNotCompared) {
  const SyntheticRun a = SteppedRun(3, 2);
  const SyntheticRun b = SteppedRun(5, 2);

  const ReplayComparison result = CompareBytes(a.Bytes(), b.Bytes());

  EXPECT_FALSE(result.comparable());
  EXPECT_TRUE(result.robots.only_a.empty());
  EXPECT_EQ(result.robots.only_b, (std::vector<uint16_t>{3, 4}));
  EXPECT_EQ(result.epochs.epochs_compared, 0u);
}

TEST(CompareReplaysTest, AFileThatCannotBeReadWholeIsAnErrorOfItsSide) {
  const SyntheticRun run = SteppedRun(3, 4);
  const testing::Written written = testing::Write(run.header, run.rounds);
  std::string damaged = written.bytes;
  damaged[written.round_ends[1] - 6] ^= 0x01;  // a byte of round 2's record
  const std::string cut = written.bytes.substr(0, written.round_ends[2]);

  const ReplayComparison damaged_b = CompareBytes(written.bytes, damaged);
  const ReplayComparison cut_a = CompareBytes(cut, written.bytes);
  const ReplayComparison not_replay = CompareBytes("hello, world", written.bytes);

  EXPECT_FALSE(damaged_b.a.error.has_value());
  ASSERT_TRUE(damaged_b.b.error.has_value());
  EXPECT_NE(damaged_b.b.error->message.find("checksum"), std::string::npos) << damaged_b.b.error->ToString();
  EXPECT_FALSE(damaged_b.b.truncated);
  EXPECT_FALSE(damaged_b.comparable());
  ASSERT_TRUE(cut_a.a.error.has_value());
  EXPECT_TRUE(cut_a.a.truncated);
  ASSERT_TRUE(not_replay.a.error.has_value());
  EXPECT_NE(not_replay.a.error->message.find("not a SyROF replay file"), std::string::npos);
  EXPECT_EQ(not_replay.b.table.round_count, run.rounds.size());  // the other file is still read
}

TEST(CompareReplaysTest, ARunWithMoreEpochsThanTheTableHoldsIsAnErrorOfItsSide) {
  const std::string four_epochs = SteppedRun(3, 4).Bytes();
  const std::string two_epochs = SteppedRun(3, 2).Bytes();
  ComparisonOptions options;
  options.max_epoch_table_cells = 9;

  const ReplayComparison result = CompareBytes(four_epochs, two_epochs, options);

  ASSERT_TRUE(result.a.error.has_value());
  EXPECT_EQ(result.a.error->where, "round " + std::to_string(StartRoundOf(4)));
  EXPECT_NE(result.a.error->message.find("more than 9"), std::string::npos) << result.a.error->ToString();
  EXPECT_FALSE(result.b.error.has_value());
  EXPECT_FALSE(result.comparable());
}

}  // namespace
}  // namespace syrof::lab::replay
