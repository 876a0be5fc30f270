// ScoreRun on hand-made metrics: full marks for a clean run, and each
// criterion losing exactly what the rubric says, with its reason.
#include "syrof/assignment/score.h"

#include <gtest/gtest.h>

namespace syrof::grader::assignment {
namespace {

using lab::metrics::Metrics;

Rubric FullRubric() {
  Rubric rubric;
  rubric.goal = GoalCriterion{50, true};
  rubric.collisions = CollisionCriterion{15, 5, 2};
  rubric.safety = SafetyCriterion{5, 0.5};
  rubric.synchrony = SynchronyCriterion{5, 2};
  rubric.common_knowledge = CommonKnowledgeCriterion{5};
  rubric.agreement = AgreementCriterion{15, 1.0};
  rubric.faults = FaultCriterion{5, 5, 1, 0};
  return rubric;
}

// A run that did everything right: two declared checks passed.
Metrics CleanRun() {
  Metrics metrics;
  metrics.goal.source = "scenario";
  metrics.goal.reached = true;
  metrics.goal.detail = "2 of 2 checks passed";
  lab::metrics::GoalCheckResult check;
  check.passed = true;
  metrics.goal.checks = {check, check};
  metrics.synchrony.max_start_skew_rounds = 1;
  metrics.agreement = lab::metrics::AgreementMetrics{};
  metrics.agreement->cooperative_epochs = 40;
  metrics.agreement->agreed_epochs = 40;
  metrics.agreement->agreed_fraction = 1.0;
  return metrics;
}

const CriterionScore& Find(const RunScore& score, const std::string& name) {
  for (const CriterionScore& criterion : score.criteria) {
    if (criterion.criterion == name) return criterion;
  }
  static const CriterionScore kNone{};
  ADD_FAILURE() << "no criterion " << name;
  return kNone;
}

TEST(ScoreRunTest, ACleanRunGetsFullMarks) {
  const RunScore score = ScoreRun(FullRubric(), CleanRun());
  EXPECT_EQ(score.points, 100);
  EXPECT_EQ(score.max_points, 100);
  ASSERT_EQ(score.criteria.size(), 7u);
  EXPECT_EQ(score.criteria[0].criterion, "goal");
  EXPECT_EQ(score.criteria[6].criterion, "faults");
}

TEST(ScoreRunTest, GoalPointsAreSharedAmongTheChecks) {
  Metrics metrics = CleanRun();
  metrics.goal.checks[1].passed = false;
  metrics.goal.reached = false;
  metrics.goal.detail = "1 of 2 checks passed; gathered: robot 3 is 0.900 m from (1.000, 1.000)";

  const CriterionScore goal = Find(ScoreRun(FullRubric(), metrics), "goal");

  EXPECT_EQ(goal.points, 25);
  EXPECT_EQ(goal.reason, metrics.goal.detail);
}

TEST(ScoreRunTest, AllOrNothingGoalGivesNothingForAMissedCheck) {
  Rubric rubric = FullRubric();
  rubric.goal->per_check = false;
  Metrics metrics = CleanRun();
  metrics.goal.checks[1].passed = false;
  metrics.goal.reached = false;
  EXPECT_EQ(Find(ScoreRun(rubric, metrics), "goal").points, 0);
}

TEST(ScoreRunTest, ABuiltinGoalIsAllOrNothing) {
  Metrics metrics = CleanRun();
  metrics.goal = lab::metrics::GoalResult{"builtin:circle", false, 0.4, "2 of 6 robots on the circle"};
  const CriterionScore goal = Find(ScoreRun(FullRubric(), metrics), "goal");
  EXPECT_EQ(goal.points, 0);
  EXPECT_EQ(goal.reason, "goal missed: 2 of 6 robots on the circle");
}

// A joiner whose start disc stayed covered never joins; the checks then only
// say where it is not, so the goal's reason names the wait.
TEST(ScoreRunTest, AJoinerThatNeverJoinedIsNamedInTheGoalsReason) {
  Metrics metrics = CleanRun();
  metrics.sim_seconds = 60;
  metrics.goal.checks[1].passed = false;
  metrics.goal.reached = false;
  metrics.goal.detail = "1 of 2 checks passed; gathered: robot 2 is 2.471 m from (1.500, 3.500)";
  metrics.safety.join_waits = 2;
  metrics.safety.joiner_waits = {lab::metrics::JoinWait{2, 12'000'000'000, std::nullopt},
                                 lab::metrics::JoinWait{3, 5'000'000'000, 6'000'000'000}};

  const CriterionScore goal = Find(ScoreRun(FullRubric(), metrics), "goal");

  EXPECT_EQ(goal.points, 25);
  EXPECT_EQ(goal.reason, metrics.goal.detail +
                             "; robot 2 never joined: it waited 48.0 s for a clear start disc (from 12.0 s to the end)");
  // All or nothing, and a built-in goal: the same words.
  Rubric rubric = FullRubric();
  rubric.goal->per_check = false;
  EXPECT_NE(Find(ScoreRun(rubric, metrics), "goal").reason.find("robot 2 never joined"), std::string::npos);
  // A goal reached despite the wait says nothing of it.
  metrics.goal.checks[1].passed = true;
  metrics.goal.reached = true;
  metrics.goal.detail = "2 of 2 checks passed";
  EXPECT_EQ(Find(ScoreRun(FullRubric(), metrics), "goal").reason, "2 of 2 checks passed");
}

TEST(ScoreRunTest, CollisionsAndWallContactsCostTheirPenaltyDownToZero) {
  Metrics metrics = CleanRun();
  metrics.collisions.count = 2;
  metrics.collisions.pairs = {{12'300'000'000, 1, 4}, {13'000'000'000, 2, 3}};
  metrics.walls.contacts = 1;

  const CriterionScore collisions = Find(ScoreRun(FullRubric(), metrics), "collisions");
  EXPECT_EQ(collisions.points, 15 - 2 * 5 - 2);
  EXPECT_EQ(collisions.reason,
            "2 collisions and 1 wall contact; first: robots 1 and 4 at 12.30 s (-5 per collision, -2 per wall contact)");

  metrics.collisions.count = 9;
  EXPECT_EQ(Find(ScoreRun(FullRubric(), metrics), "collisions").points, 0);
}

TEST(ScoreRunTest, SafetyInterventionsCostPointsWhenTheFilterIsOn) {
  Metrics metrics = CleanRun();
  metrics.safety.interventions = 3;
  EXPECT_EQ(Find(ScoreRun(FullRubric(), metrics), "safety").points, 3.5);
  metrics.safety.enabled = false;
  const CriterionScore off = Find(ScoreRun(FullRubric(), metrics), "safety");
  EXPECT_EQ(off.points, 5);
  EXPECT_EQ(off.reason, "the scenario turns the safety filter off: nothing to score");
}

TEST(ScoreRunTest, SkewAboveTheLimitLosesSynchrony) {
  Metrics metrics = CleanRun();
  metrics.synchrony.max_start_skew_rounds = 3;
  metrics.synchrony.max_skew_epoch = 17;
  const CriterionScore synchrony = Find(ScoreRun(FullRubric(), metrics), "synchrony");
  EXPECT_EQ(synchrony.points, 0);
  EXPECT_EQ(synchrony.reason, "epoch 17 started 3 rounds apart on different robots; at most 2 allowed");
}

TEST(ScoreRunTest, AP3ViolationLosesCommonKnowledge) {
  Metrics metrics = CleanRun();
  metrics.common_knowledge.violations = 1;
  metrics.common_knowledge.first_violations = {{9, 2, 180, 0}};
  const CriterionScore knowledge = Find(ScoreRun(FullRubric(), metrics), "common_knowledge");
  EXPECT_EQ(knowledge.points, 0);
  EXPECT_EQ(knowledge.reason,
            "1 common-knowledge (P3) violation; first: robot 2's map in epoch 9 differs from robot 0's");
}

TEST(ScoreRunTest, AgreementBelowTheMinimumScalesWithTheFraction) {
  Metrics metrics = CleanRun();
  metrics.agreement->agreed_epochs = 30;
  metrics.agreement->agreed_fraction = 0.75;
  metrics.agreement->first_disagreement = lab::metrics::Disagreement{12, 250, "new_round", 3, 7, 0, 2};

  const CriterionScore agreement = Find(ScoreRun(FullRubric(), metrics), "agreement");

  EXPECT_EQ(agreement.points, 11.25);
  EXPECT_EQ(agreement.reason,
            "the robots' global states agreed in 30 of 40 COOPERATIVE epochs; first in epoch 12: robot 3's newRound "
            "returned 7, robot 0's 2");
}

TEST(ScoreRunTest, NoCooperativeEpochGivesNoAgreementPoints) {
  Metrics metrics = CleanRun();
  metrics.agreement = lab::metrics::AgreementMetrics{};
  EXPECT_EQ(Find(ScoreRun(FullRubric(), metrics), "agreement").points, 0);
}

TEST(ScoreRunTest, AgreementNotMeasuredGivesNoPointsAndSaysWhy) {
  Metrics metrics = CleanRun();
  metrics.runtime = "firmware";
  metrics.agreement.reset();

  const CriterionScore agreement = Find(ScoreRun(FullRubric(), metrics), "agreement");

  EXPECT_EQ(agreement.points, 0);
  EXPECT_EQ(agreement.reason, "the firmware runtime does not measure agreement");
}

TEST(ScoreRunTest, AFaultAndRefusedCommandsCostThePenalties) {
  Rubric rubric = FullRubric();
  rubric.faults = FaultCriterion{10, 4, 1, 0};
  Metrics metrics = CleanRun();
  metrics.app.faults = {{2, "new_round", 5, 7'500'000'000, "timeout", "CPU budget 100 ms"}};
  metrics.app.invalid_commands.count = 3;
  metrics.app.invalid_commands.first = lab::metrics::AppIncident{1, 4, "MOVE_TO x_m is not finite"};

  const CriterionScore faults = Find(ScoreRun(rubric, metrics), "faults");

  EXPECT_EQ(faults.points, 10 - 4 - 3);
  EXPECT_EQ(faults.reason,
            "1 robot's app faulted; first: robot 2 in new_round at 7.50 s: timeout (CPU budget 100 ms); 3 refused "
            "commands (first: MOVE_TO x_m is not finite)");
}

TEST(ScoreRunTest, CriteriaLeftOutOfTheRubricAreNotScored) {
  Rubric rubric;
  rubric.goal = GoalCriterion{10, true};
  const RunScore score = ScoreRun(rubric, CleanRun());
  ASSERT_EQ(score.criteria.size(), 1u);
  EXPECT_EQ(score.max_points, 10);
}

}  // namespace
}  // namespace syrof::grader::assignment
