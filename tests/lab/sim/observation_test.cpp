// One observation per robot per round, and the metrics' and replay's views of it.
#include "syrof/lab/sim/observation.h"

#include <gtest/gtest.h>

namespace syrof::lab::sim {
namespace {

RobotObservation Member(replay::Presence presence) {
  sync::SyncState state;
  state.status = sync::Status::kMember;
  state.phase = wire::Phase::kVote;
  state.epoch = 12;
  state.epoch_mode = wire::Mode::kCooperative;
  world::BodyState body;
  body.x_m = 1.25;
  body.y_m = 2.5;
  body.heading_rad = 0.75;
  estimation::StateEstimate estimate{};
  estimate.x_m = 1.3f;
  estimate.y_m = 2.4f;
  estimate.heading_rad = 0.7f;
  return Observe(3, presence, state, body, estimate, true);
}

TEST(ObservationTest, ARunningMemberIsScoredAndRecordedAsObserved) {
  const RobotObservation observation = Member(replay::Presence::kRunning);

  const metrics::RobotRound round = ToRobotRound(observation);
  const replay::RobotFrame frame = ToRobotFrame(observation);

  EXPECT_EQ(round.id, 3);
  EXPECT_TRUE(round.running);
  EXPECT_TRUE(round.member);
  EXPECT_TRUE(round.estimate_valid);
  EXPECT_EQ(round.epoch, 12);
  EXPECT_EQ(round.epoch_mode, wire::Mode::kCooperative);
  EXPECT_EQ(round.phase, wire::Phase::kVote);
  EXPECT_DOUBLE_EQ(round.true_x_m, 1.25);
  EXPECT_DOUBLE_EQ(round.est_x_m, static_cast<double>(1.3f));
  EXPECT_EQ(frame.id, 3);
  EXPECT_EQ(frame.presence, replay::Presence::kRunning);
  EXPECT_EQ(frame.status, 0);
  EXPECT_EQ(frame.phase, static_cast<uint8_t>(wire::Phase::kVote));
  EXPECT_EQ(frame.mode, static_cast<uint8_t>(wire::Mode::kCooperative));
  EXPECT_EQ(frame.epoch, 12);
  EXPECT_FLOAT_EQ(frame.true_y_m, 2.5f);
  EXPECT_FLOAT_EQ(frame.true_heading_rad, 0.75f);
  EXPECT_FLOAT_EQ(frame.est_heading_rad, 0.7f);
}

TEST(ObservationTest, ARobotThatDoesNotRunIsNeitherMemberNorScoredButItsFrameKeepsItsState) {
  for (const replay::Presence presence :
       {replay::Presence::kPaused, replay::Presence::kCrashed, replay::Presence::kAbsent}) {
    const RobotObservation observation = Member(presence);

    const metrics::RobotRound round = ToRobotRound(observation);
    const replay::RobotFrame frame = ToRobotFrame(observation);

    EXPECT_FALSE(round.running);
    EXPECT_FALSE(round.member);
    EXPECT_FALSE(round.estimate_valid);
    EXPECT_EQ(round.epoch, 12);
    EXPECT_EQ(frame.presence, presence);
    EXPECT_EQ(frame.status, 0);  // member when it stopped
    EXPECT_EQ(frame.epoch, 12);
  }
}

TEST(ObservationTest, AJoinerIsNotAMemberAndACooledEstimateIsNotScored) {
  RobotObservation observation = Member(replay::Presence::kRunning);
  observation.status = sync::Status::kJoining;
  observation.estimate_warm = false;

  const metrics::RobotRound round = ToRobotRound(observation);

  EXPECT_TRUE(round.running);
  EXPECT_FALSE(round.member);
  EXPECT_FALSE(round.estimate_valid);
  EXPECT_EQ(ToRobotFrame(observation).status, 1);
}

}  // namespace
}  // namespace syrof::lab::sim
