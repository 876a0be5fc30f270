// App-level agreement on hand-made call sequences: agreement, the first
// disagreement with its robots and values, separate maps, AUTONOMOUS calls
// ignored, and the window's bounded memory over wrapping epochs.
#include "syrof/lab/metrics/agreement.h"

#include "syrof/lab/metrics/collector.h"

#include <gtest/gtest.h>

namespace syrof::lab::metrics {
namespace {

using Call = AgreementTracker::Call;
constexpr uint64_t kMap = 0x1234;

TEST(AgreementTrackerTest, NoCallsGiveNoEpochsAndANullFraction) {
  const AgreementMetrics metrics = AgreementTracker().Finish();
  EXPECT_EQ(metrics.cooperative_epochs, 0);
  EXPECT_FALSE(metrics.agreed_fraction.has_value());
  EXPECT_FALSE(metrics.first_disagreement.has_value());
}

TEST(AgreementTrackerTest, EqualStatesAgree) {
  AgreementTracker tracker;
  for (uint16_t epoch = 1; epoch <= 3; ++epoch) {
    for (uint16_t robot = 0; robot < 4; ++robot) tracker.OnAppState(robot, epoch * 30, Call::kNewRound, epoch, true, kMap + epoch, 7);
    for (uint16_t robot = 0; robot < 4; ++robot) tracker.OnAppState(robot, epoch * 30 + 20, Call::kEndOfRound, epoch, true, kMap + epoch, 9);
  }
  const AgreementMetrics metrics = tracker.Finish();
  EXPECT_EQ(metrics.cooperative_epochs, 3);
  EXPECT_EQ(metrics.agreed_epochs, 3);
  EXPECT_EQ(metrics.agreed_fraction, 1.0);
  EXPECT_EQ(metrics.new_round_calls, 12);
  EXPECT_EQ(metrics.end_of_round_calls, 12);
  EXPECT_EQ(metrics.disagreeing_calls, 0);
}

TEST(AgreementTrackerTest, TheFirstDisagreementNamesRobotsAndValues) {
  AgreementTracker tracker;
  tracker.OnAppState(0, 30, Call::kNewRound, 1, true, kMap, 5);
  tracker.OnAppState(1, 30, Call::kNewRound, 1, true, kMap, 5);
  tracker.OnAppState(0, 50, Call::kEndOfRound, 1, true, kMap, 6);
  tracker.OnAppState(1, 50, Call::kEndOfRound, 1, true, kMap, 8);  // differs
  tracker.OnAppState(0, 60, Call::kNewRound, 2, true, kMap + 1, 1);
  tracker.OnAppState(1, 60, Call::kNewRound, 2, true, kMap + 1, 2);  // differs too, later

  const AgreementMetrics metrics = tracker.Finish();
  EXPECT_EQ(metrics.cooperative_epochs, 2);
  EXPECT_EQ(metrics.agreed_epochs, 0);
  EXPECT_EQ(metrics.disagreeing_calls, 2);
  ASSERT_TRUE(metrics.first_disagreement.has_value());
  const Disagreement& first = *metrics.first_disagreement;
  EXPECT_EQ(first.epoch, 1);
  EXPECT_EQ(first.round, 50);
  EXPECT_EQ(first.callback, "end_of_round");
  EXPECT_EQ(first.robot, 1);
  EXPECT_EQ(first.state, 8);
  EXPECT_EQ(first.reference_robot, 0);
  EXPECT_EQ(first.reference_state, 6);
}

TEST(AgreementTrackerTest, RobotsWithDifferentMapsAreComparedApart) {
  AgreementTracker tracker;
  tracker.OnAppState(0, 30, Call::kNewRound, 4, true, kMap, 1);
  tracker.OnAppState(1, 30, Call::kNewRound, 4, true, kMap, 1);
  tracker.OnAppState(2, 31, Call::kNewRound, 4, true, kMap + 7, 2);  // the other side of a partition
  const AgreementMetrics metrics = tracker.Finish();
  EXPECT_EQ(metrics.agreed_epochs, 1);
  EXPECT_EQ(metrics.split_epochs, 1);
}

TEST(AgreementTrackerTest, AutonomousCallsAreNotCompared) {
  AgreementTracker tracker;
  tracker.OnAppState(0, 30, Call::kNewRound, 4, false, kMap, 1);
  tracker.OnAppState(1, 30, Call::kNewRound, 4, false, kMap + 1, 2);
  const AgreementMetrics metrics = tracker.Finish();
  EXPECT_EQ(metrics.cooperative_epochs, 0);
  EXPECT_EQ(metrics.new_round_calls, 0);
}

TEST(AgreementTrackerTest, MemoryStaysBoundedOverWrappingEpochs) {
  AgreementTracker tracker;
  // 70000 epochs: the 16-bit epoch wraps; one disagreeing epoch early on.
  for (int64_t i = 0; i < 70000; ++i) {
    const auto epoch = static_cast<uint16_t>(i);
    tracker.OnAppState(0, i, Call::kNewRound, epoch, true, kMap + i, 3);
    tracker.OnAppState(1, i, Call::kNewRound, epoch, true, kMap + i, i == 10 ? 4 : 3);
  }
  const AgreementMetrics metrics = tracker.Finish();
  EXPECT_EQ(metrics.cooperative_epochs, 70000);
  EXPECT_EQ(metrics.agreed_epochs, 69999);
  EXPECT_EQ(metrics.unchecked_calls, 0);
  EXPECT_EQ(metrics.first_disagreement->epoch, 10);
}

TEST(AgreementTrackerTest, ACallFarBehindIsNotCompared) {
  AgreementTracker tracker;
  tracker.OnAppState(0, 1, Call::kNewRound, 100, true, kMap, 3);
  tracker.OnAppState(1, 2, Call::kNewRound, 100 - kAgreementEpochWindow, true, kMap, 3);
  EXPECT_EQ(tracker.Finish().unchecked_calls, 1);
  EXPECT_EQ(tracker.Finish().cooperative_epochs, 1);
}

}  // namespace
}  // namespace syrof::lab::metrics
