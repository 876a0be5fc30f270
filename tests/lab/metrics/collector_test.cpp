// Each metric of docs/metrics.md on observation sequences built by hand.
#include "syrof/lab/metrics/collector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <vector>

namespace syrof::lab::metrics {
namespace {

using wire::Mode;

constexpr int64_t kRoundNs = 50'000'000;

// A map of `epoch` whose members are `ids`, each member's snapshot x being
// 10 * id, so two maps built alike are SameKnowledge.
sync::LDMap MapFor(uint16_t epoch, Mode mode, std::initializer_list<uint16_t> ids) {
  sync::LDMap map;
  map.epoch = epoch;
  map.mode = mode;
  for (const uint16_t id : ids) {
    map.members.set(id);
    map.snapshots[id].x_mm = static_cast<int16_t>(10 * id);
  }
  return map;
}

Collector MakeCollector(uint16_t robots) { return Collector(CollectorConfig{robots, kRoundNs}); }

// Every robot in `ids` starts `epoch` at `round`.
void StartAll(Collector& collector, uint16_t epoch, int64_t round, Mode mode,
              std::initializer_list<uint16_t> ids) {
  const sync::LDMap map = MapFor(epoch, mode, ids);
  for (const uint16_t id : ids) collector.OnEpochStart(id, round, map);
}

RobotRound Member(uint16_t id, Mode mode) {
  RobotRound robot;
  robot.id = id;
  robot.running = true;
  robot.member = true;
  robot.epoch_mode = mode;
  return robot;
}

RobotRound Estimated(uint16_t id, double true_x_m, double true_y_m, double est_x_m, double est_y_m) {
  RobotRound robot = Member(id, Mode::kCooperative);
  robot.estimate_valid = true;
  robot.true_x_m = true_x_m;
  robot.true_y_m = true_y_m;
  robot.est_x_m = est_x_m;
  robot.est_y_m = est_y_m;
  return robot;
}

RobotRound Stopped(uint16_t id) {
  RobotRound robot;
  robot.id = id;
  return robot;
}

RobotRound Joining(uint16_t id) {
  RobotRound robot;
  robot.id = id;
  robot.running = true;
  robot.member = false;
  return robot;
}

// One round in which every robot of `modes` is a member in that mode.
void MembersInModes(Collector& collector, int64_t round, std::initializer_list<Mode> modes) {
  std::vector<RobotRound> robots;
  uint16_t id = 0;
  for (const Mode mode : modes) robots.push_back(Member(id++, mode));
  collector.OnRoundEnd(round, robots);
}

// ---- epochs and synchrony ----

TEST(CollectorSynchrony, EpochsStartedInOneRoundHaveSkewZero) {
  Collector collector = MakeCollector(3);

  StartAll(collector, 1, 10, Mode::kCooperative, {0, 1, 2});
  StartAll(collector, 2, 30, Mode::kCooperative, {0, 1, 2});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.epochs_started, 2);
  EXPECT_EQ(metrics.epoch_starts, 6);
  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 0);
  EXPECT_EQ(metrics.synchrony.epochs_measured, 2);
  EXPECT_EQ(metrics.synchrony.epochs_with_skew, 0);
  EXPECT_EQ(metrics.synchrony.skew_histogram[0], 2);
  EXPECT_EQ(metrics.synchrony.mean_start_skew_rounds, 0.0);
}

TEST(CollectorSynchrony, StartsTwoRoundsApartHaveSkewTwo) {
  Collector collector = MakeCollector(3);
  const sync::LDMap map = MapFor(1, Mode::kAutonomous, {0, 1, 2});

  collector.OnEpochStart(1, 11, map);
  collector.OnEpochStart(0, 10, map);
  collector.OnEpochStart(2, 12, map);
  StartAll(collector, 2, 30, Mode::kCooperative, {0, 1, 2});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 2);
  EXPECT_EQ(metrics.synchrony.max_skew_epoch, std::optional<uint16_t>(1));
  EXPECT_EQ(metrics.synchrony.epochs_with_skew, 1);
  EXPECT_EQ(metrics.synchrony.skew_histogram[0], 1);
  EXPECT_EQ(metrics.synchrony.skew_histogram[2], 1);
  EXPECT_EQ(metrics.synchrony.mean_start_skew_rounds, 1.0);
}

TEST(CollectorSynchrony, LateStartAfterTheNextEpochStillCounts) {
  Collector collector = MakeCollector(2);

  StartAll(collector, 1, 10, Mode::kAutonomous, {0});
  StartAll(collector, 2, 20, Mode::kAutonomous, {0});
  StartAll(collector, 1, 21, Mode::kAutonomous, {1});  // a robot that caught up late
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.epochs_started, 2);
  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 11);
  EXPECT_EQ(metrics.synchrony.stale_starts, 0);
}

TEST(CollectorSynchrony, LargeSkewsFallInTheLastHistogramBin) {
  Collector collector = MakeCollector(2);

  StartAll(collector, 1, 0, Mode::kAutonomous, {0});
  StartAll(collector, 1, 15, Mode::kAutonomous, {1});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.synchrony.skew_histogram[kSkewHistogramBins - 1], 1);
  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 15);
}

RobotRound InEpoch(RobotRound robot, uint16_t epoch) {
  robot.epoch = epoch;
  robot.sync_member = robot.member;
  return robot;
}

// The blind spot: a lone robot running 40 epochs ahead made every
// start of the others "stale" and unchecked (a 32-epoch window). Now the
// others' epoch stays open while they can start it, and is compared.
TEST(CollectorCommonKnowledge, ALoneRobotRunningAheadLeavesTheOthersStartsChecked) {
  Collector collector = MakeCollector(3);
  for (uint16_t epoch = 1; epoch <= 40; ++epoch) {
    StartAll(collector, epoch, 10 * epoch, Mode::kAutonomous, {0});
    collector.OnRoundEnd(10 * epoch, std::vector<RobotRound>{InEpoch(Member(0, Mode::kAutonomous), epoch),
                                                             InEpoch(Member(1, Mode::kCooperative), 1),
                                                             InEpoch(Member(2, Mode::kCooperative), 1)});
  }
  collector.OnEpochStart(1, 500, MapFor(2, Mode::kCooperative, {1, 2}));
  sync::LDMap other = MapFor(2, Mode::kCooperative, {1, 2});
  other.snapshots[2].x_mm = 99;
  collector.OnEpochStart(2, 500, other);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.epoch_starts, 42);
  EXPECT_EQ(metrics.synchrony.stale_starts, 0);
  EXPECT_EQ(metrics.common_knowledge.unchecked_cooperative_starts, 0);
  EXPECT_EQ(metrics.common_knowledge.violations, 1);
  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 480) << "robot 0 started epoch 2 at round 20";
}

// Once nobody can start an epoch any more (grace rounds after the last robot
// left the epoch before), its record closes: the same number reached again
// after the 16-bit wrap is another epoch, not compared with the old one.
TEST(CollectorCommonKnowledge, ARecordClosesWhenNobodyCanStartItAndTheNumberMayReturn) {
  Collector collector = MakeCollector(2);
  StartAll(collector, 7, 10, Mode::kCooperative, {0, 1});
  for (int64_t round = 11; round < 11 + kRecordGraceRounds; ++round) {
    collector.OnRoundEnd(round, std::vector<RobotRound>{InEpoch(Member(0, Mode::kCooperative), 7),
                                                        InEpoch(Member(1, Mode::kCooperative), 7)});
  }
  sync::LDMap later = MapFor(7, Mode::kCooperative, {0, 1});
  later.snapshots[0].x_mm = 1234;
  collector.OnEpochStart(0, 9000, later);
  collector.OnEpochStart(1, 9000, later);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.epochs_started, 2);
  EXPECT_EQ(metrics.common_knowledge.violations, 0);
  EXPECT_EQ(metrics.synchrony.repeated_starts, 0);
  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 0);
}

// A robot paused in the epoch before for fewer than F rounds may still start
// it when it resumes: the record stays open, and its start is compared.
TEST(CollectorCommonKnowledge, ARobotPausedBrieflyKeepsTheEpochOpen) {
  Collector collector = Collector(CollectorConfig{2, kRoundNs, 1000});
  StartAll(collector, 3, 10, Mode::kCooperative, {0});
  RobotRound paused = InEpoch(Stopped(1), 2);
  paused.paused = true;
  paused.sync_member = true;
  for (int64_t round = 11; round < 11 + 2 * kRecordGraceRounds; ++round) {
    collector.OnRoundEnd(round, std::vector<RobotRound>{InEpoch(Member(0, Mode::kCooperative), 3), paused});
  }
  sync::LDMap stale = MapFor(3, Mode::kCooperative, {0});
  stale.snapshots[0].x_mm = 5;
  collector.OnEpochStart(1, 11 + 2 * kRecordGraceRounds, stale);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.violations, 1);
}

// P4 per epoch: epochs whose robots did not all start in the same mode.
TEST(CollectorModeDisagreement, EpochsStartedInBothModesAreCountedWithTheirStarts) {
  Collector collector = MakeCollector(3);
  StartAll(collector, 1, 10, Mode::kCooperative, {0, 1, 2});
  StartAll(collector, 2, 20, Mode::kCooperative, {0, 1});
  StartAll(collector, 2, 20, Mode::kAutonomous, {2});
  StartAll(collector, 3, 30, Mode::kAutonomous, {0, 1, 2});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.mixed_mode_epochs, 1);
  EXPECT_EQ(metrics.common_knowledge.mixed_mode_robot_epochs, 3);
}

TEST(CollectorSynchrony, EpochNumbersWrapWithSerialArithmetic) {
  Collector collector = MakeCollector(2);

  StartAll(collector, 65535, 10, Mode::kAutonomous, {0});
  StartAll(collector, 0, 20, Mode::kAutonomous, {0});
  StartAll(collector, 65535, 12, Mode::kAutonomous, {1});  // behind 0 by one, not stale
  StartAll(collector, 1, 30, Mode::kAutonomous, {0, 1});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.epochs_started, 3);
  EXPECT_EQ(metrics.synchrony.stale_starts, 0);
  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 2);
  EXPECT_EQ(metrics.synchrony.max_skew_epoch, std::optional<uint16_t>(65535));
}

TEST(CollectorSynchrony, RobotStartingAnEpochTwiceIsCounted) {
  Collector collector = MakeCollector(2);

  StartAll(collector, 4, 10, Mode::kAutonomous, {0, 1});
  StartAll(collector, 4, 11, Mode::kAutonomous, {1});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.synchrony.repeated_starts, 1);
  EXPECT_EQ(metrics.epochs_started, 1);
}

TEST(CollectorSynchrony, ClosedAndOpenEpochsAreMeasuredAlike) {
  // Epoch 1 closes when epoch 40 starts; epochs 40 and 41 are still open at Finish.
  Collector collector = MakeCollector(2);
  StartAll(collector, 1, 10, Mode::kAutonomous, {0});
  StartAll(collector, 1, 13, Mode::kAutonomous, {1});
  StartAll(collector, 40, 400, Mode::kAutonomous, {0, 1});
  StartAll(collector, 41, 420, Mode::kAutonomous, {0});
  StartAll(collector, 41, 421, Mode::kAutonomous, {1});

  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.synchrony.epochs_measured, 3);
  EXPECT_EQ(metrics.synchrony.skew_histogram[3], 1);
  EXPECT_EQ(metrics.synchrony.skew_histogram[0], 1);
  EXPECT_EQ(metrics.synchrony.skew_histogram[1], 1);
  EXPECT_EQ(metrics.synchrony.max_start_skew_rounds, 3);
}

// ---- round phase ----

// The round-phase statistics of `rounds` by the definition (docs/metrics.md):
// every pair of boundaries one by one, its distance modulo the round, in
// 1 us bins below 2 ms and 100 us bins above, a percentile being its bin's
// upper edge (never above the largest).
PhaseErrorStats PairByPair(const std::vector<std::vector<int64_t>>& rounds) {
  std::vector<int64_t> errors;
  for (const std::vector<int64_t>& boundaries : rounds) {
    for (size_t a = 0; a < boundaries.size(); ++a) {
      for (size_t b = a + 1; b < boundaries.size(); ++b) {
        const int64_t d = ((boundaries[a] - boundaries[b]) % kRoundNs + kRoundNs) % kRoundNs;
        errors.push_back(std::min(d, kRoundNs - d));
      }
    }
  }
  PhaseErrorStats stats;
  stats.samples = static_cast<int64_t>(errors.size());
  if (errors.empty()) return stats;
  std::sort(errors.begin(), errors.end());
  const auto upper_edge = [](int64_t error) {
    return error < 2'000'000 ? (error / 1'000 + 1) * 1'000 : 2'000'000 + ((error - 2'000'000) / 100'000 + 1) * 100'000;
  };
  const auto percentile = [&](double fraction) {
    const auto wanted = static_cast<size_t>(std::ceil(fraction * static_cast<double>(errors.size())));
    return static_cast<double>(std::min(upper_edge(errors[wanted - 1]), errors.back())) * 1e-6;
  };
  stats.p50_ms = percentile(0.5);
  stats.p99_ms = percentile(0.99);
  stats.max_ms = static_cast<double>(errors.back()) * 1e-6;
  return stats;
}

void ExpectSameStats(const PhaseErrorStats& actual, const PhaseErrorStats& expected) {
  EXPECT_EQ(actual.samples, expected.samples);
  EXPECT_DOUBLE_EQ(actual.p50_ms, expected.p50_ms);
  EXPECT_DOUBLE_EQ(actual.p99_ms, expected.p99_ms);
  EXPECT_DOUBLE_EQ(actual.max_ms, expected.max_ms);
}

// Equal boundaries are counted together (OnRoundPhases): the counts must be
// those of the pairs one by one. Three boundaries at a round's start, one a
// round later, one 0.2 ms before a round's start: 6 pairs of 0 and 4 of 0.2 ms.
TEST(CollectorRoundPhase, RepeatedBoundariesCountEveryPair) {
  Collector collector = MakeCollector(5);
  const std::vector<int64_t> boundaries = {kRoundNs, kRoundNs, 2 * kRoundNs - 200'000, kRoundNs, 2 * kRoundNs};

  collector.OnRoundPhases(boundaries);
  const Metrics metrics = collector.Finish(RunFacts{});

  const RoundPhaseMetrics& phase = metrics.round_phase;
  EXPECT_EQ(phase.rounds_measured, 1);
  EXPECT_EQ(phase.run.samples, 10);
  EXPECT_DOUBLE_EQ(phase.run.p50_ms, 0.001);  // the 6 zeros' bin, [0, 1 us)
  EXPECT_DOUBLE_EQ(phase.run.p99_ms, 0.2);    // its bin's edge, 0.201 ms, capped at the largest
  EXPECT_DOUBLE_EQ(phase.run.max_ms, 0.2);
  ExpectSameStats(phase.run, PairByPair({boundaries}));
  ASSERT_TRUE(phase.converged_s.has_value());
  ExpectSameStats(phase.residual, PairByPair({boundaries}));
}

// Seeded rounds of 2 to 60 boundaries drawn from a few residues (many
// repeats), some rounds over the threshold (the residual restarts), some
// boundaries negative or rounds apart: the same statistics as pair by pair.
TEST(CollectorRoundPhase, GroupedCountsMatchPairByPair) {
  std::mt19937_64 random(20261126);
  Collector collector = MakeCollector(60);
  std::vector<std::vector<int64_t>> rounds;
  size_t residual_from = 0;
  for (int round = 0; round < 40; ++round) {
    // Late rounds stay within the threshold, so a residual remains to compare.
    const int64_t spread_ns = round < 30 ? 3'000'000 : 900'000;
    const int distinct = 1 + static_cast<int>(random() % 4);
    std::vector<int64_t> residues;
    for (int i = 0; i < distinct; ++i) residues.push_back(static_cast<int64_t>(random() % spread_ns) - spread_ns / 3);
    std::vector<int64_t> boundaries;
    const size_t count = 2 + random() % 59;
    for (size_t i = 0; i < count; ++i) {
      const int64_t whole_rounds = static_cast<int64_t>(random() % 5) - 1;
      boundaries.push_back(whole_rounds * kRoundNs + residues[random() % residues.size()]);
    }
    collector.OnRoundPhases(boundaries);
    rounds.push_back(boundaries);
    const PhaseErrorStats alone = PairByPair({boundaries});
    if (alone.max_ms > 1.0) residual_from = rounds.size();
  }
  const Metrics metrics = collector.Finish(RunFacts{});

  ExpectSameStats(metrics.round_phase.run, PairByPair(rounds));
  ASSERT_LT(residual_from, rounds.size());
  ASSERT_TRUE(metrics.round_phase.converged_s.has_value());
  ExpectSameStats(metrics.round_phase.residual,
                  PairByPair({rounds.begin() + static_cast<std::ptrdiff_t>(residual_from), rounds.end()}));
}

// ---- common knowledge ----

TEST(CollectorCommonKnowledge, CooperativeMapsDifferingInOneSnapshotAreAViolation) {
  Collector collector = MakeCollector(3);
  const sync::LDMap agreed = MapFor(5, Mode::kCooperative, {0, 1, 2});
  sync::LDMap differing = agreed;
  differing.snapshots[1].y_mm = 7;

  collector.OnEpochStart(0, 100, agreed);
  collector.OnEpochStart(1, 100, agreed);
  collector.OnEpochStart(2, 101, differing);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.violations, 1);
  ASSERT_EQ(metrics.common_knowledge.first_violations.size(), 1u);
  const Violation& violation = metrics.common_knowledge.first_violations[0];
  EXPECT_EQ(violation.epoch, 5);
  EXPECT_EQ(violation.robot, 2);
  EXPECT_EQ(violation.round, 101);
  EXPECT_EQ(violation.first_robot, 0);
}

TEST(CollectorCommonKnowledge, CooperativeMapsWithDifferentMembersAreAViolation) {
  Collector collector = MakeCollector(3);

  collector.OnEpochStart(0, 100, MapFor(5, Mode::kCooperative, {0, 1, 2}));
  collector.OnEpochStart(1, 100, MapFor(5, Mode::kCooperative, {0, 1}));
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.violations, 1);
}

TEST(CollectorCommonKnowledge, EveryStartIsComparedWithTheFirstCooperativeMap) {
  Collector collector = MakeCollector(3);
  const sync::LDMap first = MapFor(5, Mode::kCooperative, {0, 1, 2});
  sync::LDMap other = first;
  other.snapshots[2].payload_length = 1;

  collector.OnEpochStart(0, 100, first);
  collector.OnEpochStart(1, 100, other);
  collector.OnEpochStart(2, 100, other);  // agrees with 1, not with the first
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.violations, 2);
}

TEST(CollectorCommonKnowledge, AutonomousMapsMayDiffer) {
  Collector collector = MakeCollector(3);
  const sync::LDMap cooperative = MapFor(5, Mode::kCooperative, {0, 1, 2});
  sync::LDMap autonomous = MapFor(5, Mode::kAutonomous, {0, 1, 2});
  autonomous.snapshots[1].y_mm = 7;
  sync::LDMap other_autonomous = MapFor(5, Mode::kAutonomous, {1, 2});

  collector.OnEpochStart(0, 100, cooperative);
  collector.OnEpochStart(1, 100, autonomous);
  collector.OnEpochStart(2, 100, other_autonomous);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.violations, 0);
  EXPECT_TRUE(metrics.common_knowledge.first_violations.empty());
}

TEST(CollectorCommonKnowledge, SameMapsInDifferentEpochsAreNotCompared) {
  Collector collector = MakeCollector(2);

  StartAll(collector, 5, 100, Mode::kCooperative, {0, 1});
  StartAll(collector, 6, 120, Mode::kCooperative, {0});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.violations, 0);
  EXPECT_EQ(metrics.common_knowledge.cooperative_epochs, 2);
}

TEST(CollectorCommonKnowledge, AllViolationsCountedButFewListed) {
  Collector collector = MakeCollector(20);
  collector.OnEpochStart(0, 100, MapFor(5, Mode::kCooperative, {0}));
  for (uint16_t robot = 1; robot < 16; ++robot) {
    collector.OnEpochStart(robot, 100, MapFor(5, Mode::kCooperative, {0, robot}));
  }

  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.violations, 15);
  ASSERT_EQ(metrics.common_knowledge.first_violations.size(), kMaxListedViolations);
  EXPECT_EQ(metrics.common_knowledge.first_violations.front().robot, 1);
}

TEST(CollectorCommonKnowledge, CooperativeFractionIsCooperativeStartsOverAllStarts) {
  Collector collector = MakeCollector(4);

  StartAll(collector, 1, 10, Mode::kCooperative, {0, 1, 2});
  StartAll(collector, 1, 10, Mode::kAutonomous, {3});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.cooperative_fraction, std::optional<double>(0.75));
  EXPECT_EQ(metrics.common_knowledge.cooperative_starts, 3);
  EXPECT_EQ(metrics.common_knowledge.autonomous_starts, 1);
  EXPECT_EQ(metrics.common_knowledge.cooperative_epochs, 1);
}

TEST(CollectorCommonKnowledge, CooperativeFractionIsAbsentWithoutStarts) {
  const Collector collector = MakeCollector(4);

  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_FALSE(metrics.common_knowledge.cooperative_fraction.has_value());
  EXPECT_FALSE(metrics.synchrony.mean_start_skew_rounds.has_value());
  EXPECT_EQ(metrics.epochs_started, 0);
}

// ---- mode disagreement ----

TEST(CollectorModeDisagreement, LongestRunOfDisagreeingRounds) {
  Collector collector = MakeCollector(2);
  constexpr Mode kC = Mode::kCooperative;
  constexpr Mode kA = Mode::kAutonomous;

  MembersInModes(collector, 0, {kC, kC});
  MembersInModes(collector, 1, {kC, kA});
  MembersInModes(collector, 2, {kA, kC});
  MembersInModes(collector, 3, {kC, kA});
  MembersInModes(collector, 4, {kA, kA});
  MembersInModes(collector, 5, {kC, kA});
  MembersInModes(collector, 6, {kC, kA});
  MembersInModes(collector, 7, {kC, kC});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.max_mode_disagreement_rounds, 3);
  EXPECT_EQ(metrics.common_knowledge.mode_disagreement_rounds, 5);
}

TEST(CollectorModeDisagreement, RunThatLastsToTheEndCounts) {
  Collector collector = MakeCollector(3);
  constexpr Mode kC = Mode::kCooperative;
  constexpr Mode kA = Mode::kAutonomous;

  MembersInModes(collector, 0, {kC, kA, kC});
  MembersInModes(collector, 1, {kC, kC, kC});
  for (int64_t round = 2; round < 6; ++round) MembersInModes(collector, round, {kC, kC, kA});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.max_mode_disagreement_rounds, 4);
}

TEST(CollectorModeDisagreement, OnlyRunningMembersCount) {
  Collector collector = MakeCollector(4);
  RobotRound joiner = Joining(1);
  joiner.epoch_mode = Mode::kAutonomous;
  RobotRound crashed = Stopped(2);
  crashed.member = true;  // inconsistent on purpose: not running wins
  crashed.epoch_mode = Mode::kAutonomous;
  const std::vector<RobotRound> robots = {Member(0, Mode::kCooperative), joiner, crashed,
                                          Member(3, Mode::kCooperative)};

  collector.OnRoundEnd(0, robots);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.common_knowledge.max_mode_disagreement_rounds, 0);
}

// ---- estimation ----

TEST(CollectorEstimation, RmseAndMaxOverValidEstimates) {
  Collector collector = MakeCollector(3);
  RobotRound warming_up = Estimated(2, 0, 0, 100, 100);
  warming_up.estimate_valid = false;
  RobotRound stopped = Estimated(2, 0, 0, 100, 100);
  stopped.running = false;

  // Errors 5 m (3-4-5) and 0 m in round 0; 1 m in round 1.
  collector.OnRoundEnd(0, std::vector<RobotRound>{Estimated(0, 1, 1, 4, 5), Estimated(1, 2, 2, 2, 2),
                                                 warming_up});
  collector.OnRoundEnd(1, std::vector<RobotRound>{Estimated(0, 1, 1, 1, 0), Estimated(1, 2, 2, 2, 2),
                                                 stopped});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.estimation.samples, 4);
  ASSERT_TRUE(metrics.estimation.position_rmse_m.has_value());
  EXPECT_DOUBLE_EQ(*metrics.estimation.position_rmse_m, std::sqrt((25.0 + 0.0 + 1.0 + 0.0) / 4.0));
  EXPECT_EQ(metrics.estimation.max_error_m, std::optional<double>(5.0));
  EXPECT_EQ(metrics.estimation.max_error_robot, std::optional<uint16_t>(0));
  EXPECT_EQ(metrics.estimation.max_error_round, std::optional<int64_t>(0));
}

TEST(CollectorEstimation, NonFiniteEstimatesAreCountedApart) {
  Collector collector = MakeCollector(2);
  const double nan = std::numeric_limits<double>::quiet_NaN();

  collector.OnRoundEnd(0, std::vector<RobotRound>{Estimated(0, 0, 0, nan, 0), Estimated(1, 0, 0, 0, 2)});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.estimation.non_finite_samples, 1);
  EXPECT_EQ(metrics.estimation.samples, 1);
  EXPECT_EQ(metrics.estimation.position_rmse_m, std::optional<double>(2.0));
}

TEST(CollectorEstimation, NoValidEstimateLeavesTheErrorsEmpty) {
  Collector collector = MakeCollector(1);

  collector.OnRoundEnd(0, std::vector<RobotRound>{Member(0, Mode::kCooperative)});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.estimation.samples, 0);
  EXPECT_FALSE(metrics.estimation.position_rmse_m.has_value());
  EXPECT_FALSE(metrics.estimation.max_error_m.has_value());
}

// ---- contacts ----

TEST(CollectorContacts, CollisionsCountedWithTheirPairs) {
  Collector collector = MakeCollector(4);

  collector.OnCollision(1'000'000'000, 2, 1);
  collector.OnCollision(2'500'000'000, 0, 1);
  RunFacts facts;
  facts.min_separation_m = -0.01;
  const Metrics metrics = collector.Finish(facts);

  EXPECT_EQ(metrics.collisions.count, 2);
  EXPECT_EQ(metrics.collisions.robots_involved, 3);
  EXPECT_EQ(metrics.collisions.min_separation_m, -0.01);
  ASSERT_EQ(metrics.collisions.pairs.size(), 2u);
  EXPECT_EQ(metrics.collisions.pairs[0].time_ns, 1'000'000'000);
  EXPECT_EQ(metrics.collisions.pairs[0].a, 1);
  EXPECT_EQ(metrics.collisions.pairs[0].b, 2);
  EXPECT_EQ(metrics.collisions.pairs[1].a, 0);
}

TEST(CollectorContacts, OnlyTheFirstCollisionsAreListed) {
  Collector collector = MakeCollector(2);
  for (int64_t i = 0; i < 150; ++i) collector.OnCollision(i * kRoundNs, 0, 1);

  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.collisions.count, 150);
  ASSERT_EQ(metrics.collisions.pairs.size(), kMaxListedCollisions);
  EXPECT_EQ(metrics.collisions.pairs.back().time_ns, 99 * kRoundNs);
}

TEST(CollectorContacts, WallContactsCounted) {
  Collector collector = MakeCollector(3);

  collector.OnWallContact(10, 2);
  collector.OnWallContact(20, 2);
  collector.OnWallContact(30, 0);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.walls.contacts, 3);
  EXPECT_EQ(metrics.walls.robots_involved, 2);
  ASSERT_EQ(metrics.walls.first_contacts.size(), 3u);
  EXPECT_EQ(metrics.walls.first_contacts[2].robot, 0);
}

// ---- membership ----

TEST(CollectorMembership, RemovalsAreSummedOverObserversWithLatency) {
  Collector collector = MakeCollector(3);
  wire::MemberSet crashed;
  crashed.set(2);
  const wire::MemberSet none;
  const std::vector<RobotRound> all_running = {Member(0, Mode::kCooperative), Member(1, Mode::kCooperative),
                                               Member(2, Mode::kCooperative)};
  const std::vector<RobotRound> two_running = {Member(0, Mode::kCooperative), Member(1, Mode::kCooperative),
                                               Stopped(2)};

  for (int64_t round = 0; round < 5; ++round) collector.OnRoundEnd(round, all_running);
  for (int64_t round = 5; round < 11; ++round) collector.OnRoundEnd(round, two_running);
  collector.OnMembership(0, 11, crashed, none);
  collector.OnRoundEnd(11, two_running);
  collector.OnMembership(1, 12, crashed, none);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.membership.removals, 2);
  EXPECT_EQ(metrics.membership.robots_removed, 1);
  EXPECT_EQ(metrics.membership.removals_of_running_robots, 0);
  EXPECT_EQ(metrics.membership.max_removal_latency_rounds, std::optional<int64_t>(7));
  EXPECT_EQ(metrics.membership.mean_removal_latency_rounds, std::optional<double>(6.5));
}

// Robot 0 is paused for 4 rounds while robot 2 is silent: its failure
// detector did not run then, so those rounds are not counted as latency
// (before, they were: 11 instead of 7).
TEST(CollectorMembership, APausedObserversOwnStopIsNotRemovalLatency) {
  Collector collector = MakeCollector(3);
  wire::MemberSet crashed;
  crashed.set(2);
  RobotRound paused = Stopped(0);
  paused.paused = true;
  for (int64_t round = 0; round < 5; ++round) {
    collector.OnRoundEnd(round, std::vector<RobotRound>{Member(0, Mode::kCooperative), Member(1, Mode::kCooperative),
                                                        Member(2, Mode::kCooperative)});
  }
  for (int64_t round = 5; round < 16; ++round) {
    const bool observer_paused = round >= 7 && round < 11;
    collector.OnRoundEnd(round, std::vector<RobotRound>{observer_paused ? paused : Member(0, Mode::kCooperative),
                                                        Member(1, Mode::kCooperative), Stopped(2)});
  }
  collector.OnMembership(0, 16, crashed, wire::MemberSet{});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.membership.max_removal_latency_rounds, std::optional<int64_t>(7));
}

TEST(CollectorMembership, RemovingARunningRobotIsCountedApart) {
  Collector collector = MakeCollector(2);
  wire::MemberSet removed;
  removed.set(1);

  collector.OnRoundEnd(0, std::vector<RobotRound>{Member(0, Mode::kCooperative), Member(1, Mode::kCooperative)});
  collector.OnMembership(0, 1, removed, wire::MemberSet{});
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.membership.removals_of_running_robots, 1);
  EXPECT_FALSE(metrics.membership.max_removal_latency_rounds.has_value());
}

TEST(CollectorMembership, JoinsAndJoinLatency) {
  Collector collector = MakeCollector(3);
  wire::MemberSet newcomer;
  newcomer.set(2);
  const RobotRound zero = Member(0, Mode::kCooperative);
  const RobotRound one = Member(1, Mode::kCooperative);

  collector.OnRoundEnd(0, std::vector<RobotRound>{zero, one, Stopped(2)});
  for (int64_t round = 1; round < 5; ++round) {
    collector.OnRoundEnd(round, std::vector<RobotRound>{zero, one, Joining(2)});
  }
  collector.OnRoundEnd(5, std::vector<RobotRound>{zero, one, Member(2, Mode::kAutonomous)});
  collector.OnMembership(0, 6, wire::MemberSet{}, newcomer);
  collector.OnMembership(1, 6, wire::MemberSet{}, newcomer);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.membership.joins, 2);
  EXPECT_EQ(metrics.membership.robots_joined, 1);
  EXPECT_EQ(metrics.membership.completed_joins, 1);
  EXPECT_EQ(metrics.membership.max_join_latency_rounds, std::optional<int64_t>(4));
}

// ---- robustness ----

TEST(CollectorInput, UnknownRobotIdsAreIgnoredAndCounted) {
  Collector collector = MakeCollector(2);
  wire::MemberSet stranger;
  stranger.set(7);

  collector.OnEpochStart(5, 0, MapFor(1, Mode::kCooperative, {5}));
  collector.OnMembership(0, 0, stranger, wire::MemberSet{});
  collector.OnRoundEnd(0, std::vector<RobotRound>{Member(9, Mode::kAutonomous)});
  collector.OnCollision(0, 0, 3);
  collector.OnCollision(0, 1, 1);
  collector.OnWallContact(0, 2);
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.diagnostics.ignored_observations, 6);
  EXPECT_EQ(metrics.epoch_starts, 0);
  EXPECT_EQ(metrics.membership.removals, 0);
  EXPECT_EQ(metrics.collisions.count, 0);
  EXPECT_EQ(metrics.walls.contacts, 0);
  EXPECT_EQ(metrics.diagnostics.rounds_observed, 1);
}

TEST(CollectorInput, FinishLeavesTheCollectorUnchanged) {
  Collector collector = MakeCollector(2);
  StartAll(collector, 1, 10, Mode::kCooperative, {0});
  StartAll(collector, 1, 12, Mode::kCooperative, {1});

  const std::string first = ToJson(collector.Finish(RunFacts{}));
  const std::string second = ToJson(collector.Finish(RunFacts{}));
  StartAll(collector, 2, 30, Mode::kCooperative, {0, 1});
  const Metrics later = collector.Finish(RunFacts{});

  EXPECT_EQ(first, second);
  EXPECT_EQ(later.synchrony.epochs_measured, 2);
  EXPECT_EQ(later.synchrony.max_start_skew_rounds, 2);
}

TEST(CollectorInput, RunFactsPassThrough) {
  const Collector collector = MakeCollector(2);
  RunFacts facts;
  facts.seed = 42;
  facts.robots = 2;
  facts.sim_seconds = 12.5;
  facts.radio_rounds = 250;
  facts.scenario = "two";
  facts.app_name = "circle";
  facts.app_source = "builtin:circle";
  facts.goal = GoalResult{"builtin:circle", true, 0.03, "on the circle"};

  const Metrics metrics = collector.Finish(facts);

  EXPECT_EQ(metrics.seed, 42u);
  EXPECT_EQ(metrics.robots, 2);
  EXPECT_EQ(metrics.sim_seconds, 12.5);
  EXPECT_EQ(metrics.radio_rounds, 250);
  EXPECT_EQ(metrics.radio_round_ns, kRoundNs);
  EXPECT_EQ(metrics.scenario, "two");
  EXPECT_EQ(metrics.goal.detail, "on the circle");
  EXPECT_TRUE(metrics.goal.reached);
  EXPECT_EQ(metrics.app.name, "circle");
  EXPECT_EQ(metrics.app.source, "builtin:circle");
}

TEST(CollectorApp, FaultsAreListedOncePerRobotInTheOrderTheyCame) {
  Collector collector = MakeCollector(3);

  collector.OnAppFault(AppFault{2, "new_round", 3, 500, "timeout", "cpu"});
  collector.OnAppFault(AppFault{0, "init", 0, 0, "load_failed", ""});
  collector.OnAppFault(AppFault{2, "end_of_round", 4, 900, "crashed", ""});  // already faulted
  collector.OnAppFault(AppFault{7, "init", 0, 0, "crashed", ""});            // no such robot
  const Metrics metrics = collector.Finish(RunFacts{});

  ASSERT_EQ(metrics.app.faults.size(), 2u);
  EXPECT_EQ(metrics.app.faults[0].robot, 2);
  EXPECT_EQ(metrics.app.faults[0].verdict, "timeout");
  EXPECT_EQ(metrics.app.faults[1].robot, 0);
  EXPECT_EQ(metrics.diagnostics.ignored_observations, 1);
}

TEST(CollectorApp, IncidentsAreCountedWithTheirFirstOccurrence) {
  Collector collector = MakeCollector(3);

  collector.OnInvalidCommand(1, 4, "kind 9 is unknown");
  collector.OnInvalidCommand(0, 5, "TURN_TO heading_rad is not finite");
  collector.OnPayloadRefused(2, 6, "12 bytes");
  collector.OnPayloadRefused(9, 6, "12 bytes");  // no such robot
  const Metrics metrics = collector.Finish(RunFacts{});

  EXPECT_EQ(metrics.app.invalid_commands.count, 2);
  ASSERT_TRUE(metrics.app.invalid_commands.first.has_value());
  EXPECT_EQ(metrics.app.invalid_commands.first->robot, 1);
  EXPECT_EQ(metrics.app.invalid_commands.first->epoch, 4);
  EXPECT_EQ(metrics.app.invalid_commands.first->what, "kind 9 is unknown");
  EXPECT_EQ(metrics.app.payload_refused.count, 1);
  EXPECT_EQ(metrics.app.payload_refused.first->robot, 2);
  EXPECT_EQ(metrics.diagnostics.ignored_observations, 1);
}

TEST(CollectorApp, NothingReportedMeansNoFaultsAndNoFirsts) {
  const Metrics metrics = MakeCollector(2).Finish(RunFacts{});

  EXPECT_TRUE(metrics.app.faults.empty());
  EXPECT_EQ(metrics.app.invalid_commands.count, 0);
  EXPECT_FALSE(metrics.app.invalid_commands.first.has_value());
  EXPECT_FALSE(metrics.app.payload_refused.first.has_value());
}

}  // namespace
}  // namespace syrof::lab::metrics
