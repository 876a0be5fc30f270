// FaultOutcomes: whether the swarm handled its faults, from the robots'
// console reports.
#include "syrof/firmware/swarm/fault_outcomes.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <vector>

namespace syrof::firmware::swarm {
namespace {

constexpr int64_t kWorldSecondNs = 1'000'000'000;

RoundLine Round(uint16_t robot, int64_t t_ms, bool member) {
  RoundLine line;
  line.robot = robot;
  line.t_ms = t_ms;
  line.member = member;
  return line;
}

EpochLine Epoch(uint16_t robot, uint16_t epoch, std::initializer_list<uint16_t> members) {
  EpochLine line;
  line.robot = robot;
  line.map.epoch = epoch;
  for (const uint16_t member : members) line.map.members.set(member);
  return line;
}

const std::vector<lab::sim::Lifecycle> kAllRunning(4, lab::sim::Lifecycle::kRunning);

TEST(FaultOutcomesTest, ACrashedRobotIsRemovedWhenEverySurvivorsLatestMapLacksIt) {
  FaultOutcomes outcomes(4);
  outcomes.OnEpochLine(Epoch(0, 1, {0, 1, 2, 3}), 1 * kWorldSecondNs);  // before the crash: not judged
  outcomes.OnAction({HostAction::Kind::kKill, 1}, 2 * kWorldSecondNs);
  outcomes.OnEpochLine(Epoch(0, 2, {0, 1, 2, 3}), 2 * kWorldSecondNs + 100'000'000);  // within F rounds: still there
  outcomes.OnEpochLine(Epoch(0, 3, {0, 2, 3}), 3 * kWorldSecondNs);
  outcomes.OnEpochLine(Epoch(2, 3, {0, 2, 3}), 3 * kWorldSecondNs);
  std::vector<lab::sim::Lifecycle> presence = kAllRunning;
  presence[1] = lab::sim::Lifecycle::kCrashed;

  const std::vector<FaultOutcome> removed = outcomes.Finish(presence);

  ASSERT_EQ(removed.size(), 1u);
  EXPECT_TRUE(removed[0].ok) << removed[0].detail;
  EXPECT_EQ(removed[0].done_ns, 3 * kWorldSecondNs);

  // A survivor whose latest map still holds the crashed robot fails it.
  outcomes.OnEpochLine(Epoch(3, 4, {0, 1, 2, 3}), 4 * kWorldSecondNs);
  const std::vector<FaultOutcome> kept = outcomes.Finish(presence);
  EXPECT_FALSE(kept[0].ok);
  EXPECT_NE(kept[0].detail.find("robot(s) 3"), std::string::npos) << kept[0].detail;
}

TEST(FaultOutcomesTest, ACrashWithNoEpochStartedAfterItIsNotJudgedOk) {
  FaultOutcomes outcomes(4);
  outcomes.OnAction({HostAction::Kind::kKill, 1}, 2 * kWorldSecondNs);
  std::vector<lab::sim::Lifecycle> presence = kAllRunning;
  presence[1] = lab::sim::Lifecycle::kCrashed;

  const std::vector<FaultOutcome> result = outcomes.Finish(presence);

  ASSERT_EQ(result.size(), 1u);
  EXPECT_FALSE(result[0].ok);
}

TEST(FaultOutcomesTest, APausedRobotComesBackAndItsClockJumpIsKept) {
  FaultOutcomes outcomes(4);
  outcomes.OnRoundLine(Round(2, 3950, true), 4 * kWorldSecondNs - 40'000'000);
  outcomes.OnAction({HostAction::Kind::kStop, 2}, 4 * kWorldSecondNs);
  outcomes.OnAction({HostAction::Kind::kContinue, 2}, 6 * kWorldSecondNs - 50'000'000);
  outcomes.OnRoundLine(Round(2, 5990, false), 6 * kWorldSecondNs);  // restarted as a joiner
  outcomes.OnRoundLine(Round(2, 6400, true), 6 * kWorldSecondNs + 400'000'000);

  const std::vector<FaultOutcome> result = outcomes.Finish(kAllRunning);

  ASSERT_EQ(result.size(), 1u);
  EXPECT_TRUE(result[0].ok) << result[0].detail;
  EXPECT_EQ(result[0].done_ns, 6 * kWorldSecondNs + 400'000'000);
  EXPECT_TRUE(result[0].rejoined_as_joiner);
  EXPECT_EQ(result[0].guest_gap_ms, 2040);
  EXPECT_EQ(result[0].world_gap_ms, 2040);
}

TEST(FaultOutcomesTest, APausedRobotThatNeverBecomesAMemberAgainFails) {
  FaultOutcomes outcomes(4);
  outcomes.OnAction({HostAction::Kind::kStop, 2}, 4 * kWorldSecondNs);
  outcomes.OnRoundLine(Round(2, 4100, true), 4 * kWorldSecondNs + 100'000'000);  // cannot happen while stopped; not "after"
  outcomes.OnAction({HostAction::Kind::kContinue, 2}, 6 * kWorldSecondNs);
  outcomes.OnRoundLine(Round(2, 6050, false), 6 * kWorldSecondNs + 50'000'000);

  const std::vector<FaultOutcome> result = outcomes.Finish(kAllRunning);

  ASSERT_EQ(result.size(), 1u);
  EXPECT_FALSE(result[0].ok);
  EXPECT_NE(result[0].detail.find("never MEMBER"), std::string::npos) << result[0].detail;
}

TEST(FaultOutcomesTest, AJoinerJoinsWhenItIsAMemberAndInAnotherRobotsMap) {
  FaultOutcomes outcomes(4);
  outcomes.OnAction({HostAction::Kind::kSwitchOn, 3}, 2 * kWorldSecondNs);
  outcomes.OnRoundLine(Round(3, 500, false), 2 * kWorldSecondNs + 500'000'000);
  outcomes.OnEpochLine(Epoch(3, 5, {0, 1, 2, 3}), 3 * kWorldSecondNs);  // its own map does not count
  outcomes.OnRoundLine(Round(3, 1000, true), 3 * kWorldSecondNs);

  EXPECT_FALSE(outcomes.Finish(kAllRunning)[0].ok);

  outcomes.OnEpochLine(Epoch(0, 6, {0, 1, 2, 3}), 4 * kWorldSecondNs);
  const std::vector<FaultOutcome> result = outcomes.Finish(kAllRunning);
  EXPECT_TRUE(result[0].ok) << result[0].detail;
  EXPECT_EQ(result[0].done_ns, 4 * kWorldSecondNs);
}

}  // namespace
}  // namespace syrof::firmware::swarm
