// PrintSummary (cli/run_summary.h): the lines `syrof run` and `syrof swarm`
// print, from the typed metrics.
#include "run_summary.h"

#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>

namespace syrof::cli {
namespace {

lab::metrics::Metrics SomeRun() {
  lab::metrics::Metrics m;
  m.scenario = "crash";
  m.app.name = "circle";
  m.app.source = "builtin:circle";
  m.robots = 5;
  m.seed = 42;
  m.sim_seconds = 20;
  m.radio_rounds = 2000;
  m.epochs_started = 190;
  m.synchrony.max_start_skew_rounds = 1;
  m.synchrony.max_start_skew_ms = 10.25;
  m.common_knowledge.cooperative_fraction = 0.968;
  m.collisions.count = 2;
  m.collisions.min_separation_m = -0.0125;
  m.walls.contacts = 3;
  m.safety.interventions = 7;
  m.safety.precautions = 5;
  m.safety.robots_involved = 2;
  m.estimation.position_rmse_m = 0.0412;
  m.membership.removals = 4;
  m.membership.joins = 1;
  m.goal.reached = true;
  m.goal.detail = "on the circle";
  return m;
}

std::string Summary(const lab::metrics::Metrics& m) {
  std::ostringstream out;
  PrintSummary(out, m, "/tmp/out", true, false, false, false);
  return out.str();
}

TEST(RunSummary, EveryLineReadsItsOwnField) {
  lab::metrics::Metrics m = SomeRun();
  m.agreement = lab::metrics::AgreementMetrics{};
  m.agreement->cooperative_epochs = 180;
  m.agreement->agreed_epochs = 179;
  m.agreement->first_disagreement = lab::metrics::Disagreement{77, 0, "new_round", 3, 1, 0, 2};

  const std::string text = Summary(m);

  EXPECT_NE(text.find("SyROF run: crash (builtin:circle), 5 robots, seed 42"), std::string::npos) << text;
  EXPECT_NE(text.find("190 epochs, start skew max 1 rounds (10.2 ms)"), std::string::npos) << text;
  EXPECT_NE(text.find("0 P3 violations, 96.8% COOPERATIVE starts"), std::string::npos) << text;
  EXPECT_NE(text.find("2 (min separation -0.013 m), wall contacts 3"), std::string::npos) << text;
  EXPECT_NE(text.find("7 interventions on 2 robots, 5 precautions, 0 join waits"), std::string::npos) << text;
  EXPECT_NE(text.find("agreed in 179 of 180 COOPERATIVE epochs (first disagreement: epoch 77, robot 3)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("position RMSE 0.041 m, max - m"), std::string::npos) << text;
  EXPECT_NE(text.find("4 removals, 0 joins (1 join notices)"), std::string::npos) << text;
  EXPECT_NE(text.find("reached (on the circle)"), std::string::npos) << text;
  EXPECT_NE(text.find("/tmp/out/metrics.json, /tmp/out/replay"), std::string::npos) << text;
}

// The firmware swarm does not measure agreement: the summary says so rather
// than printing zeros.
// One joiner noticed by 12 robots is one join; a joiner whose start disc
// stayed covered is named, not only counted as a join wait.
TEST(RunSummary, JoinsCountRobotsAndAJoinerThatNeverJoinedIsNamed) {
  lab::metrics::Metrics m = SomeRun();
  m.membership.joins = 12;
  m.membership.completed_joins = 1;
  m.safety.join_waits = 2;
  m.safety.joiner_waits = {lab::metrics::JoinWait{4, 3'000'000'000, 4'000'000'000},
                           lab::metrics::JoinWait{2, 8'000'000'000, std::nullopt}};

  const std::string text = Summary(m);

  EXPECT_NE(text.find("4 removals, 1 join (12 join notices)"), std::string::npos) << text;
  EXPECT_NE(text.find("7 interventions on 2 robots, 5 precautions, 2 join waits\n"
                      "    robot 2 never joined: it waited 12.0 s for a clear start disc (from 8.0 s to the end)\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("robot 4 never joined"), std::string::npos) << text;
}

TEST(RunSummary, AgreementNotMeasuredIsSaid) {
  lab::metrics::Metrics m = SomeRun();
  m.runtime = "firmware";

  const std::string text = Summary(m);

  EXPECT_NE(text.find("agreement         not measured (the firmware runtime does not see the app's returns)"),
            std::string::npos)
      << text;
}

TEST(RunSummary, AnUndefinedValuePrintsADash) {
  lab::metrics::Metrics m = SomeRun();
  m.common_knowledge.cooperative_fraction.reset();
  m.collisions.min_separation_m = std::numeric_limits<double>::infinity();

  const std::string text = Summary(m);

  EXPECT_NE(text.find("0 P3 violations, - COOPERATIVE starts"), std::string::npos) << text;
  EXPECT_NE(text.find("(min separation - m)"), std::string::npos) << text;
}

TEST(RunSummary, MisbehaviourIsFlaggedWithItsFirstOccurrence) {
  lab::metrics::Metrics m = SomeRun();
  EXPECT_FALSE(AppMisbehaved(m));
  m.app.invalid_commands.count = 3;
  m.app.invalid_commands.first = lab::metrics::AppIncident{1, 4, "MOVE_TO x_m is not finite"};

  const std::string text = Summary(m);

  EXPECT_TRUE(AppMisbehaved(m));
  EXPECT_NE(text.find("3 in all, each replaced by STOP; first robot 1, epoch 4: MOVE_TO x_m is not finite"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace syrof::cli
