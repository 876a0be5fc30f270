// Every transition of docs/protocol.md on one robot, with hand-made beacons.
#include "syrof/sync/synchronizer.h"

#include <gtest/gtest.h>

#include <vector>

namespace syrof::sync {
namespace {

constexpr uint16_t kSwarm = 4;

class SynchronizerTest : public ::testing::Test {
 protected:
  SynchronizerTest() {
    config_ = SyncConfig::ForSwarm(kSwarm, 0);  // K = 3, F = 6, Q = 3
    state_ = InitialState(config_, Own());
  }

  static wire::Snapshot Own() {
    wire::Snapshot snapshot;
    snapshot.x_mm = 11;
    return snapshot;
  }

  // A beacon from `id` in `epoch` and `phase`; VOTE beacons carry `vote` and
  // robot 0's members as their view, WAIT beacons only the sender waiting,
  // PROGRESS beacons a heard set of the whole swarm (the sender hears all).
  wire::Beacon From(uint16_t id, uint16_t epoch, Phase phase, uint8_t vote = 0) const {
    wire::Beacon beacon;
    beacon.robot_id = id;
    beacon.epoch = epoch;
    beacon.phase = phase;
    beacon.vote_counter = vote;
    beacon.snapshot.x_mm = static_cast<int16_t>(100 * id);
    beacon.mode = Mode::kCooperative;
    if (phase == Phase::kVote) {
      beacon.waiting = state_.members;
    } else if (phase == Phase::kWait) {
      beacon.waiting.set(id);
    } else {
      for (uint16_t other = 0; other < kSwarm; ++other) beacon.waiting.set(other);
    }
    return beacon;
  }

  void StepWith(std::vector<wire::Beacon> beacons, bool finished = false) {
    StepInput input;
    input.maneuver_finished = finished;
    input.own_snapshot = Own();
    Step(config_, state_, beacons, input, out_, ldmap_);
  }

  // Everyone else's WAIT beacons in epoch 0: moves robot 0 into VOTE.
  void EnterVote() {
    StepWith({From(1, 0, Phase::kWait), From(2, 0, Phase::kWait), From(3, 0, Phase::kWait)});
    ASSERT_EQ(state_.phase, Phase::kVote);
  }

  bool HeardWell(uint16_t id) const {
    SyncState progress = state_;
    progress.phase = Phase::kProgress;
    return MakeBeacon(config_, progress).waiting.test(id);
  }

  std::vector<wire::Beacon> Votes(uint8_t vote) const {
    return {From(1, 0, Phase::kVote, vote), From(2, 0, Phase::kVote, vote),
            From(3, 0, Phase::kVote, vote)};
  }

  SyncConfig config_;
  SyncState state_;
  StepOutput out_;
  LDMap ldmap_;
};

TEST_F(SynchronizerTest, InitialMemberStartsInWaitOfEpochZeroWithItsSnapshotFrozen) {
  EXPECT_EQ(state_.status, Status::kMember);
  EXPECT_EQ(state_.phase, Phase::kWait);
  EXPECT_EQ(state_.epoch, 0);
  EXPECT_EQ(state_.members.count(), kSwarm);
  EXPECT_TRUE(state_.held.test(0));
  EXPECT_EQ(state_.snapshots[0], Own());
}

TEST_F(SynchronizerTest, BeaconsByAddressGiveTheSameStepAsBeaconsByValue) {
  // Through a whole epoch, including a malformed beacon and a duplicate.
  std::vector<std::vector<wire::Beacon>> rounds = {
      {From(1, 0, Phase::kWait), From(2, 0, Phase::kWait), From(3, 0, Phase::kWait)}, Votes(1), Votes(2), Votes(3),
      {From(1, 1, Phase::kProgress), From(7, 1, Phase::kProgress), From(1, 1, Phase::kProgress)}};
  SyncState by_address = state_;
  StepOutput out_by_address;
  LDMap ldmap_by_address;

  for (const std::vector<wire::Beacon>& round : rounds) {
    std::vector<const wire::Beacon*> addresses;
    for (const wire::Beacon& beacon : round) addresses.push_back(&beacon);
    StepInput input;
    input.own_snapshot = Own();
    Step(config_, by_address, std::span<const wire::Beacon* const>(addresses), input, out_by_address,
         ldmap_by_address);
    StepWith(round);

    ASSERT_EQ(by_address, state_);
    ASSERT_EQ(out_by_address.beacon, out_.beacon);
    ASSERT_EQ(out_by_address.epoch_started, out_.epoch_started);
  }
  EXPECT_TRUE(ldmap_by_address.SameKnowledge(ldmap_));
  EXPECT_EQ(state_.epoch, 1);
  EXPECT_EQ(state_.stats.beacons_rejected, 2u);
}

TEST_F(SynchronizerTest, RobotOutsideTheInitialMembersStartsJoiningAndSilent) {
  config_.initial_members.reset(0);
  state_ = InitialState(config_, Own());
  EXPECT_EQ(state_.status, Status::kJoining);
  StepWith({});
  EXPECT_FALSE(out_.send);
}

TEST_F(SynchronizerTest, WaitBecomesVoteWhenEveryMemberIsKnownWaiting) {
  StepWith({From(1, 0, Phase::kWait), From(2, 0, Phase::kWait)});
  EXPECT_EQ(state_.phase, Phase::kWait) << "robot 3 is not known to be waiting";
  StepWith({From(3, 0, Phase::kWait)});
  EXPECT_EQ(state_.phase, Phase::kVote);
  EXPECT_EQ(state_.view, state_.members);
  EXPECT_EQ(out_.beacon.vote_counter, 1);
  EXPECT_EQ(out_.beacon.waiting, state_.view);
}

TEST_F(SynchronizerTest, WaitingSetsSpreadTransitively) {
  wire::Beacon relayed = From(1, 0, Phase::kWait);
  relayed.waiting.clear();
  relayed.waiting.set(1);
  relayed.waiting.set(2);
  relayed.waiting.set(3);
  StepWith({relayed});
  EXPECT_EQ(state_.phase, Phase::kVote);
}

TEST_F(SynchronizerTest, WaitAdoptsTheHighestVoteCounterHeard) {
  StepWith({From(1, 0, Phase::kVote, 1), From(2, 0, Phase::kVote, 2)});
  EXPECT_EQ(state_.phase, Phase::kVote);
  EXPECT_EQ(state_.vote, 3) << "heard 2, so the next beacon carries 3";
}

TEST_F(SynchronizerTest, VoteStartsTheEpochAfterKRoundsCooperativeWhenEveryVoteMatches) {
  EnterVote();
  StepWith(Votes(1));
  StepWith(Votes(2));
  EXPECT_FALSE(out_.epoch_started);
  StepWith(Votes(3));
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.epoch, 1);
  EXPECT_EQ(ldmap_.mode, Mode::kCooperative);
  EXPECT_EQ(ldmap_.members.count(), kSwarm);
  EXPECT_EQ(ldmap_.snapshots[0], Own());
  EXPECT_EQ(ldmap_.snapshots[2].x_mm, 200);
  EXPECT_EQ(state_.phase, Phase::kProgress);
  EXPECT_EQ(state_.epoch, 1);
  EXPECT_EQ(state_.epoch_mode, Mode::kCooperative);
}

TEST_F(SynchronizerTest, AMemberNeverHeardVotingMakesTheEpochAutonomous) {
  EnterVote();
  StepWith({From(1, 0, Phase::kVote, 1), From(2, 0, Phase::kVote, 1)});
  StepWith({From(1, 0, Phase::kVote, 2)});
  StepWith({From(1, 0, Phase::kVote, 3)});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous);
  EXPECT_TRUE(ldmap_.members.test(3)) << "its WAIT snapshot is still this robot's knowledge";
}

TEST_F(SynchronizerTest, AVoteWithAnotherViewVetoes) {
  EnterVote();
  wire::Beacon other_view = From(1, 0, Phase::kVote, 1);
  other_view.waiting.reset(3);
  StepWith({other_view, From(2, 0, Phase::kVote, 1), From(3, 0, Phase::kVote, 1)});
  EXPECT_TRUE(state_.veto);
  EXPECT_EQ(out_.beacon.mode, Mode::kAutonomous) << "the veto is announced";
  StepWith(Votes(2));
  StepWith(Votes(3));
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous);
}

TEST_F(SynchronizerTest, AnAutonomousVoteVetoes) {
  EnterVote();
  std::vector<wire::Beacon> votes = Votes(1);
  votes[1].mode = Mode::kAutonomous;
  StepWith(votes);
  StepWith(Votes(2));
  StepWith(Votes(3));
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous);
}

TEST_F(SynchronizerTest, AViewBelowQuorumIsAutonomous) {
  for (int round = 0; round < config_.silence_rounds; ++round) {
    StepWith({From(1, 0, Phase::kWait)});
  }
  ASSERT_EQ(state_.members.count(), 2) << "2 and 3 removed";
  ASSERT_EQ(state_.phase, Phase::kVote);
  EXPECT_TRUE(state_.veto);
  StepWith({From(1, 0, Phase::kVote, 2)});
  StepWith({From(1, 0, Phase::kVote, 3)});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous) << "2 of 4 is no majority";
}

TEST_F(SynchronizerTest, FailureDetectorRemovesAfterExactlyFSilentRounds) {
  for (int round = 1; round < config_.silence_rounds; ++round) {
    StepWith({From(1, 0, Phase::kWait), From(2, 0, Phase::kWait)});
    EXPECT_TRUE(state_.members.test(3)) << "round " << round;
  }
  StepWith({From(1, 0, Phase::kWait), From(2, 0, Phase::kWait)});
  EXPECT_FALSE(state_.members.test(3));
  EXPECT_TRUE(out_.removed.test(3));
  EXPECT_EQ(out_.removed.count(), 1);
}

TEST_F(SynchronizerTest, NeighbouringEpochsCountAsAliveButFarOnesDoNot) {
  state_.phase = Phase::kProgress;
  state_.epoch = 5;
  for (int round = 0; round < config_.silence_rounds; ++round) {
    StepWith({From(1, 4, Phase::kVote, 1), From(2, 6, Phase::kProgress), From(3, 5, Phase::kProgress)});
  }
  EXPECT_TRUE(state_.members.test(1));
  EXPECT_TRUE(state_.members.test(2));
  state_.epoch = 5;
  for (int round = 0; round < config_.silence_rounds; ++round) {
    StepWith({From(1, 3, Phase::kProgress), From(3, 5, Phase::kProgress)});
  }
  EXPECT_FALSE(state_.members.test(1)) << "two epochs behind is another group";
}

TEST_F(SynchronizerTest, UnknownRobotInTheSameEpochJoinsAtOnce) {
  config_.initial_members.reset(3);
  state_ = InitialState(config_, Own());
  StepWith({From(3, 0, Phase::kWait)});
  EXPECT_TRUE(state_.members.test(3));
  EXPECT_TRUE(out_.joined.test(3));
  EXPECT_TRUE(state_.held.test(3));
}

TEST_F(SynchronizerTest, ProgressEndsWhenTheManeuverFinishesAndFreezesTheSnapshot) {
  EnterVote();
  StepWith(Votes(1));
  StepWith(Votes(2));
  StepWith(Votes(3));
  ASSERT_EQ(state_.phase, Phase::kProgress);
  StepWith({});
  EXPECT_EQ(state_.phase, Phase::kProgress);
  StepWith({}, true);
  EXPECT_EQ(state_.phase, Phase::kWait);
  EXPECT_TRUE(state_.waiting.test(0));
  EXPECT_EQ(out_.beacon.snapshot.x_mm, Own().x_mm);
}

TEST_F(SynchronizerTest, CatchesUpWhenAMemberIsOneEpochAheadAndItsManeuverIsOver) {
  StepWith({From(1, 1, Phase::kProgress)});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous);
  EXPECT_EQ(state_.epoch, 1);
  EXPECT_EQ(state_.stats.catch_ups, 1u);
}

TEST_F(SynchronizerTest, DoesNotCatchUpBeforeItsManeuverIsOver) {
  state_.phase = Phase::kProgress;
  StepWith({From(1, 1, Phase::kProgress)});
  EXPECT_FALSE(out_.epoch_started);
  EXPECT_EQ(state_.epoch, 0);
}

TEST_F(SynchronizerTest, TwoEpochsBehindItBecomesASilentJoinerAndStartsWithTheGroup) {
  StepWith({From(1, 7, Phase::kVote, 1)});
  EXPECT_TRUE(out_.became_joiner);
  EXPECT_EQ(state_.status, Status::kJoining);
  EXPECT_FALSE(out_.send);
  // The group starts epoch 8 at the end of the round whose beacons carry K = 3.
  StepWith({From(1, 7, Phase::kVote, 2)});
  EXPECT_FALSE(out_.epoch_started);
  StepWith({});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.epoch, 8);
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous);
  EXPECT_EQ(state_.status, Status::kMember);
  EXPECT_TRUE(state_.members.test(1));
  EXPECT_TRUE(out_.send);
}

TEST_F(SynchronizerTest, JoinerIgnoresEpochsItHasAlreadyBeenIn) {
  state_ = SyncState{};
  state_.status = Status::kJoining;
  state_.epoch = 9;
  StepWith({From(1, 7, Phase::kVote, 3)});
  EXPECT_FALSE(out_.epoch_started) << "epoch 8 is not after 9";
  StepWith({From(1, 9, Phase::kVote, 3)});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.epoch, 10);
}

TEST_F(SynchronizerTest, JoinerThatHearsNobodyFoundsAGroupOfOne) {
  config_.initial_members.reset(0);
  state_ = InitialState(config_, Own());
  for (int round = 1; round < config_.silence_rounds; ++round) {
    StepWith({});
    EXPECT_FALSE(out_.epoch_started);
  }
  StepWith({});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(state_.members.count(), 1);
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous);
}

TEST_F(SynchronizerTest, MalformedBeaconsAreCountedAndDropped) {
  wire::Beacon from_self = From(0, 0, Phase::kWait);
  wire::Beacon out_of_range = From(9, 0, Phase::kWait);
  wire::Beacon bad_vote = From(1, 0, Phase::kVote, 7);
  wire::Beacon counter_outside_vote = From(2, 0, Phase::kWait, 1);
  wire::Beacon wide_set = From(3, 0, Phase::kWait);
  wide_set.waiting.set(kSwarm);
  StepWith({from_self, out_of_range, bad_vote, counter_outside_vote, wide_set});
  EXPECT_EQ(state_.stats.beacons_rejected, 5u);
  EXPECT_EQ(state_.stats.last_issue, BeaconIssue::kMemberOutOfRange);
  EXPECT_EQ(state_.phase, Phase::kWait);
  StepWith({From(1, 0, Phase::kWait), From(1, 0, Phase::kWait)});
  EXPECT_EQ(state_.stats.last_issue, BeaconIssue::kDuplicate);
}

// Pauses and epoch numbers (docs/protocol.md, "Epoch numbers").
TEST_F(SynchronizerTest, AMemberThatMissedFRoundsRestartsAsAJoinerButFMinusOneDoesNot) {
  EnterVote();
  StepInput input;
  input.own_snapshot = Own();
  input.rounds_elapsed = config_.silence_rounds;  // missed F - 1 rounds
  Step(config_, state_, std::span<const wire::Beacon>(), input, out_, ldmap_);
  EXPECT_EQ(state_.status, Status::kMember);
  EXPECT_FALSE(out_.became_joiner);
  input.rounds_elapsed = config_.silence_rounds + 1u;  // missed F rounds
  Step(config_, state_, std::span<const wire::Beacon>(), input, out_, ldmap_);
  EXPECT_EQ(state_.status, Status::kJoining);
  EXPECT_TRUE(out_.became_joiner);
  EXPECT_FALSE(state_.held.test(1)) << "the others' snapshots are forgotten";
  EXPECT_EQ(state_.stats.restarts_after_gap, 1u);
}

// The issue's case: paused in VOTE of epoch 0, resumed 65,536 epochs later
// when the group's counter reads 0 again. Before, it voted with its old view
// and started epoch 1 COOPERATIVE with the old snapshots.
TEST_F(SynchronizerTest, APauseAcrossTheEpochWrapNeverReusesOldSnapshots) {
  EnterVote();
  StepWith(Votes(1));
  StepInput input;
  input.own_snapshot = Own();
  input.rounds_elapsed = 2u * 65536u * 25u;
  std::vector<wire::Beacon> fresh = Votes(3);
  for (wire::Beacon& beacon : fresh) beacon.snapshot.x_mm = static_cast<int16_t>(beacon.snapshot.x_mm + 1);
  Step(config_, state_, fresh, input, out_, ldmap_);
  EXPECT_TRUE(out_.became_joiner);
  EXPECT_EQ(state_.stats.restarts_after_gap, 1u);
  // It joined the group's boundary at once (the votes say K), AUTONOMOUS,
  // holding only this round's snapshots.
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.mode, Mode::kAutonomous);
  for (const uint16_t id : {1, 2, 3}) EXPECT_EQ(ldmap_.snapshots[id].x_mm, 100 * id + 1) << id;
}

TEST_F(SynchronizerTest, AMemberStuckInOneEpochForTheStayLimitRestartsAsAJoiner) {
  state_.phase = Phase::kProgress;
  StepInput input;
  input.own_snapshot = Own();
  input.rounds_elapsed = 1;
  for (uint32_t round = 1; round < kMaxStayRounds; ++round) {
    Step(config_, state_, Votes(1), input, out_, ldmap_);  // heard, never finishing
    ASSERT_EQ(state_.status, Status::kMember) << round;
  }
  Step(config_, state_, Votes(1), input, out_, ldmap_);
  EXPECT_EQ(state_.status, Status::kJoining);
  EXPECT_EQ(state_.stats.restarts_long_stay, 1u);
}

TEST_F(SynchronizerTest, JoinsSpendCreditSoNoRobotCirclesTheEpochNumbersQuickly) {
  state_ = SyncState{};
  state_.status = Status::kJoining;
  state_.epoch = 0;
  state_.join_credit = 20000;
  StepWith({From(1, 30000, Phase::kVote, 3)});
  EXPECT_FALSE(out_.epoch_started) << "a jump of 30,001 epochs exceeds the credit";
  StepWith({From(1, 10000, Phase::kVote, 3)});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(state_.epoch, 10001);
  EXPECT_EQ(state_.join_credit, 20000 + 2 - 10001);
}

TEST_F(SynchronizerTest, ARobotSwitchedOnLateMayJoinAnyEpoch) {
  config_.initial_members.reset(0);
  state_ = InitialState(config_, Own());
  StepWith({From(1, 50000, Phase::kVote, 3)});  // "behind" 0 by serial arithmetic
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(state_.epoch, 50001);
}

// "Connectivity": a PROGRESS beacon's set is whom its sender hears well.
TEST_F(SynchronizerTest, AProgressBeaconCarriesTheMembersTheRobotHearsWell) {
  state_.phase = Phase::kProgress;
  EXPECT_EQ(MakeBeacon(config_, state_).waiting, state_.members);
  const auto silence_three = [this] {
    for (int round = 0; round < 6; ++round) StepWith({From(1, 0, Phase::kProgress), From(2, 0, Phase::kProgress)});
    ASSERT_TRUE(out_.removed.test(3));
    StepWith({From(1, 0, Phase::kProgress), From(2, 0, Phase::kProgress), From(3, 0, Phase::kProgress)});
    ASSERT_TRUE(state_.members.test(3));
  };
  // Removed once, heard again: a lost run of beacons, still heard well.
  silence_three();
  EXPECT_TRUE(MakeBeacon(config_, state_).waiting.test(3));
  EXPECT_FALSE(state_.pruned.test(3));
  // Removed in the previous epoch too: flaky, not heard well.
  state_.flaky_previous.set(3);
  silence_three();
  EXPECT_FALSE(MakeBeacon(config_, state_).waiting.test(3))
      << "a member removed in two epochs in a row is not heard well";
  EXPECT_TRUE(state_.pruned.test(3)) << "this robot does not hear 3 well: the higher id of the pair is left out";
}

TEST_F(SynchronizerTest, AFlakyMemberStaysOutWhileRemovedAgainAndReturnsAfterAQuietEpoch) {
  // Every member waits and votes in `epoch`; this robot's maneuver is over.
  const auto run_epoch = [this](uint16_t epoch) {
    StepWith({From(1, epoch, Phase::kWait), From(2, epoch, Phase::kWait), From(3, epoch, Phase::kWait)}, true);
    ASSERT_EQ(state_.phase, Phase::kVote);
    for (uint8_t vote = 1; vote <= 3; ++vote) {
      std::vector<wire::Beacon> votes = Votes(vote);
      for (wire::Beacon& beacon : votes) beacon.epoch = epoch;
      StepWith(votes);
    }
    ASSERT_TRUE(out_.epoch_started);
  };
  state_.flaky.set(3);
  EXPECT_FALSE(HeardWell(3));
  state_.flaky_current.set(3);  // removed again in this epoch
  run_epoch(0);
  EXPECT_FALSE(HeardWell(3)) << "removed again in the epoch that ended: still flaky";
  run_epoch(1);
  EXPECT_TRUE(HeardWell(3)) << "an epoch without a removal ends it";
}

TEST_F(SynchronizerTest, ARobotThatDoesNotHearThisOneIsLeftOutAndCannotVeto) {
  state_.phase = Phase::kProgress;
  wire::Beacon deaf_to_me = From(3, 0, Phase::kProgress);
  deaf_to_me.waiting.reset(0);  // robot 3 does not hear robot 0
  StepWith({From(1, 0, Phase::kProgress), From(2, 0, Phase::kProgress), deaf_to_me});
  EXPECT_TRUE(state_.pruned.test(3));
  EXPECT_FALSE(state_.pruned.test(0));
  EXPECT_TRUE(state_.members.test(3)) << "still a member: it is heard, and watched by the failure detector";
  // The epoch ends; 3 votes AUTONOMOUS with another view, and is ignored.
  StepWith({From(1, 0, Phase::kWait), From(2, 0, Phase::kWait)}, true);
  ASSERT_EQ(state_.phase, Phase::kVote) << "3 is not waited for";
  MemberSet expected_view;
  for (const uint16_t id : {0, 1, 2}) expected_view.set(id);
  EXPECT_EQ(state_.view, expected_view);
  for (uint8_t vote = 1; vote <= 3; ++vote) {
    wire::Beacon one = From(1, 0, Phase::kVote, vote);
    one.waiting = expected_view;
    wire::Beacon two = From(2, 0, Phase::kVote, vote);
    two.waiting = expected_view;
    wire::Beacon three = From(3, 0, Phase::kVote, vote);
    three.mode = Mode::kAutonomous;
    StepWith({one, two, three});
  }
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(ldmap_.mode, Mode::kCooperative);
  EXPECT_EQ(ldmap_.members, expected_view);
}

TEST_F(SynchronizerTest, ThisRobotLeftOutVotesAutonomousAndComesBackWhenTheReportsDo) {
  state_.phase = Phase::kProgress;
  std::vector<wire::Beacon> deaf_to_me;
  for (const uint16_t id : {1, 2, 3}) {
    deaf_to_me.push_back(From(id, 0, Phase::kProgress));
    deaf_to_me.back().waiting.reset(0);  // nobody hears robot 0 (it is mute)
  }
  StepWith(deaf_to_me);
  EXPECT_TRUE(state_.pruned.test(0));
  EXPECT_EQ(state_.pruned.count(), 1) << "only the robot with the most broken links";
  StepWith({From(1, 0, Phase::kWait), From(2, 0, Phase::kWait), From(3, 0, Phase::kWait)}, true);
  ASSERT_EQ(state_.phase, Phase::kVote);
  EXPECT_EQ(MakeBeacon(config_, state_).mode, Mode::kAutonomous) << "a robot left out vetoes its own start";
  // Its links come back: every report names it again.
  StepWith({From(1, 0, Phase::kProgress), From(2, 0, Phase::kProgress), From(3, 0, Phase::kProgress)});
  EXPECT_FALSE(state_.pruned.test(0));
  EXPECT_EQ(state_.report_count, 0) << "reports equal to the members are not kept";
}

TEST_F(SynchronizerTest, TheRuleLeavesOutTheRobotWithTheMostBrokenLinksThenTheHigherId) {
  state_.phase = Phase::kProgress;
  // 1 does not hear 2 or 3; 3 does not hear 1 (the same pair as 1-3).
  wire::Beacon one = From(1, 0, Phase::kProgress);
  one.waiting.reset(2);
  one.waiting.reset(3);
  wire::Beacon three = From(3, 0, Phase::kProgress);
  three.waiting.reset(1);
  StepWith({one, From(2, 0, Phase::kProgress), three});
  MemberSet expected;
  expected.set(1);  // two broken pairs; after it, none
  EXPECT_EQ(state_.pruned, expected);
  // Only the pair 2-3 broken: the higher id goes.
  wire::Beacon two = From(2, 0, Phase::kProgress);
  two.waiting.reset(3);
  StepWith({From(1, 0, Phase::kProgress), two, From(3, 0, Phase::kProgress)});
  expected.clear();
  expected.set(3);
  EXPECT_EQ(state_.pruned, expected);
}

// Robot 2 does not hear robot 0, which 1 and 3 hear: 2 cannot know how well
// 0 hears the others, so it leaves the decision about 0 to those that hear
// it (in the explored triangle, counting 0 with a guessed row made 2 leave
// itself out while 1 kept it, and nobody cooperated).
TEST_F(SynchronizerTest, ARobotNotHeardHereIsLeftToThoseThatHearIt) {
  config_ = SyncConfig::ForSwarm(kSwarm, 2);
  state_ = InitialState(config_, Own());
  state_.phase = Phase::kProgress;
  for (int round = 0; round < 7; ++round) StepWith({From(1, 0, Phase::kProgress), From(3, 0, Phase::kProgress)});
  ASSERT_FALSE(state_.members.test(0));
  EXPECT_TRUE(state_.pruned.empty());
  StepWith({From(1, 0, Phase::kWait), From(3, 0, Phase::kWait)}, true);
  ASSERT_EQ(state_.phase, Phase::kVote);
  MemberSet expected_view;
  for (const uint16_t id : {1, 2, 3}) expected_view.set(id);
  EXPECT_EQ(state_.view, expected_view) << "the view robots 1 and 3 reach when 0 hears only some of them";
}

TEST_F(SynchronizerTest, ARobotAloneIsNotFollowedButWaitsForAGroupBehindIt) {
  // A lone robot two epochs ahead does not drag this one along...
  wire::Beacon lone = From(1, 7, Phase::kVote, 1);
  lone.waiting.clear();
  lone.waiting.set(1);
  StepWith({lone});
  EXPECT_EQ(state_.status, Status::kMember);
  // ... and a robot alone that hears a group behind it waits for that group.
  state_.members.clear();
  state_.members.set(0);
  state_.epoch = 9;
  StepWith({From(1, 5, Phase::kVote, 1)});
  EXPECT_EQ(state_.status, Status::kJoining);
  StepWith({From(1, 8, Phase::kVote, 3)});
  EXPECT_FALSE(out_.epoch_started) << "epoch 9 again is not allowed";
  StepWith({From(1, 9, Phase::kVote, 3)});
  ASSERT_TRUE(out_.epoch_started);
  EXPECT_EQ(state_.epoch, 10);
}

TEST(EpochDifferenceTest, UsesSerialArithmeticAcrossTheWrap) {
  EXPECT_EQ(EpochDifference(5, 3), 2);
  EXPECT_EQ(EpochDifference(3, 5), -2);
  EXPECT_EQ(EpochDifference(0, 65535), 1);
  EXPECT_EQ(EpochDifference(65535, 0), -1);
}

TEST(SyncConfigTest, ValidateNamesEachBrokenRule) {
  SyncConfig config = SyncConfig::ForSwarm(5, 1);
  EXPECT_EQ(Validate(config), ConfigError::kOk);
  EXPECT_EQ(config.quorum, 3);

  SyncConfig bad = config;
  bad.swarm_size = 0;
  EXPECT_EQ(Validate(bad), ConfigError::kSwarmSizeOutOfRange);
  bad = config;
  bad.self_id = 5;
  EXPECT_EQ(Validate(bad), ConfigError::kSelfOutOfRange);
  bad = config;
  bad.vote_rounds = 0;
  EXPECT_EQ(Validate(bad), ConfigError::kVoteRoundsOutOfRange);
  bad = config;
  bad.silence_rounds = bad.vote_rounds;
  EXPECT_EQ(Validate(bad), ConfigError::kSilenceNotAboveVote);
  bad = config;
  bad.silence_rounds = kMaxSilenceRounds + 1;
  EXPECT_EQ(Validate(bad), ConfigError::kSilenceTooLong);
  bad = config;
  bad.quorum = 2;
  EXPECT_EQ(Validate(bad), ConfigError::kQuorumNotMajority);
  bad = config;
  bad.quorum = 6;
  EXPECT_EQ(Validate(bad), ConfigError::kQuorumNotMajority);
  bad = config;
  bad.initial_members.set(5);
  EXPECT_EQ(Validate(bad), ConfigError::kInitialMemberOutOfRange);
  EXPECT_STREQ(ToString(ConfigError::kQuorumNotMajority), "QuorumNotMajority");
}

}  // namespace
}  // namespace syrof::sync
