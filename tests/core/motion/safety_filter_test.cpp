// The safety filter on hand-built situations: what it lets through, what it
// limits, against whom, and when an intervention starts.
#include "syrof/motion/safety_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace syrof::motion {
namespace {

constexpr int64_t kSecond = 1'000'000'000;

ControllerConfig Omni() {
  ControllerConfig config;
  config.kind = DriveKind::kOmni;
  config.limits.max_speed_mps = 0.5f;
  config.limits.max_accel_mps2 = 1.0f;
  config.limits.body_radius_m = 0.1f;
  return config;
}

ControllerConfig WheeledConfig() {
  ControllerConfig config = Omni();
  config.kind = DriveKind::kWheels;
  return config;
}

SafetyConfig Config() {
  SafetyConfig config;
  config.self_id = 0;
  config.others_max_speed_mps = 0.5f;
  config.others_radius_m = 0.1f;
  config.margin_m = 0.05f;
  return config;
}

estimation::StateEstimate At(float x, float y, float heading = 0) {
  estimation::StateEstimate estimate{};
  estimate.x_m = x;
  estimate.y_m = y;
  estimate.heading_rad = heading;
  estimate.status = estimation::kEstimateInitialized;
  return estimate;
}

DriveCommand DriveVelocity(float vx, float vy) {
  DriveCommand drive;
  drive.kind = DriveKind::kOmni;
  drive.vx_mps = vx;
  drive.vy_mps = vy;
  return drive;
}

DriveCommand Wheels(float left, float right) {
  DriveCommand drive;
  drive.kind = DriveKind::kWheels;
  drive.left_mps = left;
  drive.right_mps = right;
  return drive;
}

TEST(SafetyFilterTest, PassesACommandWhenNobodyIsNear) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 3.0f, 3.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(DriveVelocity(0.5f, 0), At(1, 1), reports, 0, outcome);

  EXPECT_FALSE(outcome.limited);
  EXPECT_FLOAT_EQ(out.vx_mps, 0.5f);
}

TEST(SafetyFilterTest, StopsTheApproachAtTheEdgeOfAFreshDisc) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  // Disc radius 0.1 + 0.1 + 0.05 = 0.25 m; the robot is 0.25 m from the centre.
  reports.ReportMetres(1, 0, 1.25f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(DriveVelocity(0.5f, 0), At(1, 1), reports, 0, outcome);

  EXPECT_TRUE(outcome.limited);
  EXPECT_TRUE(outcome.started);
  EXPECT_EQ(outcome.other, 1);
  EXPECT_LE(out.vx_mps, 1e-4f);
}

TEST(SafetyFilterTest, SlowsTheApproachOnTheBrakingCurveAndKeepsTheTangent) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.35f, 1.0f, false, 0, 0, 0.8f);  // gap 0.1 m
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(DriveVelocity(0.4f, 0.3f), At(1, 1), reports, 0, outcome);

  // min(gain 4 * 0.1, sqrt(0.8 * 0.1)) = 0.283 m/s towards it; the sideways
  // part is never touched.
  EXPECT_NEAR(out.vx_mps, std::sqrt(0.08f), 1e-4f);
  EXPECT_FLOAT_EQ(out.vy_mps, 0.3f);
}

TEST(SafetyFilterTest, AStaleReportGrowsItsDiscAtTheSpeedLimit) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.5f, 1.0f, false, 0, 0, 0.8f);  // 0.5 m away: clear when fresh
  SafetyOutcome fresh;
  SafetyOutcome stale;

  (void)filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), reports, 0, fresh);
  // 0.4 s later the other may have come 0.2 m closer: the disc's edge is at
  // 0.45 m, a gap of 0.05 m allows min(4 * 0.05, sqrt(0.8 * 0.05)) = 0.2 m/s.
  const DriveCommand out = filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), reports, 4 * kSecond / 10, stale);

  EXPECT_FALSE(fresh.limited);
  EXPECT_TRUE(stale.limited);
  EXPECT_NEAR(out.vx_mps, 0.2f, 1e-4f);
}

TEST(SafetyFilterTest, InsideADiscOnlyMovesAwayFromEveryPlaceTheOtherCanBe) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.2f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;
  const int64_t later = kSecond / 10;  // sigma = 0.05 m, d = 0.2 m: sin(phi) = 0.25

  const DriveCommand towards = filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), reports, later, outcome);
  const DriveCommand sideways = filter.Apply(DriveVelocity(0, 0.3f), At(1, 1), reports, later, outcome);
  const DriveCommand away = filter.Apply(DriveVelocity(-0.3f, 0), At(1, 1), reports, later, outcome);

  EXPECT_NEAR(towards.vx_mps, 0, 1e-4f);
  EXPECT_NEAR(towards.vy_mps, 0, 1e-4f);
  // Sideways is tilted away until it leaves every point of the other's disc.
  EXPECT_LT(sideways.vx_mps, 0);
  EXPECT_LE(sideways.vx_mps, -0.25f * std::hypot(sideways.vx_mps, sideways.vy_mps) + 1e-4f);
  EXPECT_FLOAT_EQ(away.vx_mps, -0.3f);
}

TEST(SafetyFilterTest, KeepsOffTheWalls) {
  SafetyConfig config = Config();
  config.arena_width_m = 4;
  config.arena_height_m = 4;
  SafetyFilter filter(config, Omni(), 1);
  SafetyReports reports;
  SafetyOutcome outcome;

  // Radius 0.1 + margin 0.05: the wall's edge is at x = 3.85.
  const DriveCommand out = filter.Apply(DriveVelocity(0.5f, 0), At(3.85f, 2), reports, 0, outcome);

  EXPECT_TRUE(outcome.limited);
  EXPECT_EQ(outcome.other, kWallObstacle);
  EXPECT_LE(out.vx_mps, 1e-4f);
}

TEST(SafetyFilterTest, LimitsARoversForwardSpeedAndKeepsItsTurn) {
  SafetyFilter filter(Config(), WheeledConfig(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.25f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(Wheels(0.3f, 0.4f), At(1, 1, 0), reports, 0, outcome);

  EXPECT_TRUE(outcome.limited);
  EXPECT_NEAR(0.5f * (out.left_mps + out.right_mps), 0, 1e-4f);
  EXPECT_NEAR(out.right_mps - out.left_mps, 0.1f, 1e-5f);
}

TEST(SafetyFilterTest, ARoverFacingAwayMayDriveOn) {
  SafetyFilter filter(Config(), WheeledConfig(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.25f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(Wheels(0.3f, 0.3f), At(1, 1, 3.14159f), reports, 0, outcome);

  EXPECT_FALSE(outcome.limited);
  EXPECT_FLOAT_EQ(out.left_mps, 0.3f);
}

TEST(SafetyFilterTest, AParkedReportAddsItsSendersBrakingDistance) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports moving;
  SafetyReports parked;
  moving.ReportMetres(1, 0, 1.4f, 1.0f, false, -0.4f, 0, 0.8f);
  parked.ReportMetres(1, 0, 1.4f, 1.0f, true, -0.4f, 0, 0.8f);  // may still brake 0.1 m towards us
  SafetyOutcome a;
  SafetyOutcome b;

  const DriveCommand free = filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), moving, 0, a);
  const DriveCommand braked = filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), parked, 0, b);

  EXPECT_LT(braked.vx_mps, free.vx_mps);
}

TEST(SafetyFilterTest, IgnoresItsOwnReportAndInvalidOnes) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(0, 0, 1.0f, 1.0f, false, 0, 0, 0.8f);  // self
  reports.ReportMetres(2, 0, NAN, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(DriveVelocity(0.5f, 0), At(1, 1), reports, 0, outcome);

  EXPECT_FALSE(outcome.limited);
  EXPECT_FLOAT_EQ(out.vx_mps, 0.5f);
}

// A relayed position (wire::Relay) fills only an entry with no report at
// all: what a robot heard itself, or was relayed before, stays; the silent
// robot's own next beacon replaces it.
TEST(SafetyReportsTest, ARelayFillsOnlyARobotWithNoReport) {
  SafetyReports reports;
  reports.Report(1, 5'000'000'000, 1000, 1000, false, 0, 0, 1.0f);

  EXPECT_FALSE(reports.Relayed(1, 1'000'000'000, -500, -500, 22));
  EXPECT_EQ(reports[1].x_mm, 1000);
  EXPECT_EQ(reports[1].time_ns, 5'000'000'000);

  EXPECT_TRUE(reports.Relayed(2, 1'000'000'000, 2000, -300, 22));
  EXPECT_EQ(reports[2].x_mm, 2000);
  EXPECT_EQ(reports[2].y_mm, -300);
  EXPECT_EQ(reports[2].allowance_mm, 22);
  EXPECT_FALSE(reports.Relayed(2, 2'000'000'000, 0, 0, 22));  // a second relay: the first stays
  EXPECT_EQ(reports[2].x_mm, 2000);

  reports.Report(2, 6'000'000'000, 2100, -250, false, 0, 0, 1.0f);  // robot 2 speaks again
  EXPECT_EQ(reports[2].x_mm, 2100);
  EXPECT_EQ(reports[2].allowance_mm, 0);
  EXPECT_FALSE(reports.Relayed(wire::kMaxSwarmSize, 0, 0, 0, 22));
}

// The silent robots are taken in turn after the last one relayed, never the
// robot itself, and a robot heard since `before_ns` is not silent.
TEST(SafetyReportsTest, NextSilentGoesRoundTheSilentRobots) {
  SafetyReports reports;
  constexpr int64_t kBefore = 10'000'000'000;
  for (const uint16_t id : {0, 2, 5, 6}) reports.Report(id, kBefore - 1, 0, 0, false, 0, 0, 1.0f);
  reports.Report(3, kBefore, 0, 0, false, 0, 0, 1.0f);  // heard at before_ns: not silent

  uint16_t cursor = 2;  // robot 2's own id
  EXPECT_EQ(reports.NextSilent(cursor, 2, 8, kBefore, 8), 5);  // robot 2 itself is skipped
  EXPECT_EQ(cursor, 5);
  EXPECT_EQ(reports.NextSilent(cursor, 2, 8, kBefore, 8), 6);
  EXPECT_EQ(reports.NextSilent(cursor, 2, 8, kBefore, 8), 0);  // round to the start
  EXPECT_EQ(reports.NextSilent(cursor, 2, 8, kBefore, 8), 5);
  cursor = 0;
  EXPECT_EQ(reports.NextSilent(cursor, 0, 6, kBefore, 8), 2);  // ids below the count only: 6 is out
  EXPECT_EQ(reports.NextSilent(cursor, 0, 6, kBefore, 8), 5);
  EXPECT_EQ(reports.NextSilent(cursor, 0, 6, kBefore, 8), 2);

  SafetyReports only_self;
  only_self.Report(4, 0, 0, 0, false, 0, 0, 1.0f);
  cursor = 4;
  EXPECT_EQ(only_self.NextSilent(cursor, 4, 8, kBefore, 8), SafetyReports::kNoSilentReport);
  EXPECT_EQ(cursor, 4);  // looked at all eight, itself last
  EXPECT_EQ(SafetyReports().NextSilent(cursor, 0, 0, kBefore, 8), SafetyReports::kNoSilentReport);
}

// A call looks at no more than `limit` robots and leaves the cursor at the
// last one, so a large swarm's search goes on over several beacons and
// still reaches every silent robot.
TEST(SafetyReportsTest, NextSilentLooksAtMostLimitRobotsAndGoesOnFromThere) {
  // 32 robots: the Teensy build's kMaxSwarmSize, so the test runs there too.
  constexpr uint16_t kRobots = 32;
  static_assert(kRobots <= wire::kMaxSwarmSize);
  SafetyReports reports;
  constexpr int64_t kBefore = 10'000'000'000;
  for (uint16_t id = 0; id < kRobots; ++id) reports.Report(id, kBefore, 0, 0, false, 0, 0, 1.0f);  // all heard
  reports.Report(29, kBefore - 1, 0, 0, false, 0, 0, 1.0f);                                        // one silent

  uint16_t cursor = 3;
  EXPECT_EQ(reports.NextSilent(cursor, 3, kRobots, kBefore, 8), SafetyReports::kNoSilentReport);
  EXPECT_EQ(cursor, 11);
  int calls = 1;
  uint16_t found = SafetyReports::kNoSilentReport;
  while (found == SafetyReports::kNoSilentReport && calls < 100) {
    found = reports.NextSilent(cursor, 3, kRobots, kBefore, 8);
    ++calls;
  }
  EXPECT_EQ(found, 29);
  EXPECT_EQ(calls, 4);  // 4-11, 12-19, 20-27, 28-29
  EXPECT_EQ(cursor, 29);
}

TEST(SafetyFilterTest, DisabledPassesEverything) {
  SafetyConfig config = Config();
  config.enabled = false;
  SafetyFilter filter(config, Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.1f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(DriveVelocity(0.5f, 0), At(1, 1), reports, 0, outcome);

  EXPECT_FALSE(outcome.limited);
  EXPECT_FLOAT_EQ(out.vx_mps, 0.5f);
}

TEST(SafetyFilterTest, AnInterventionStartsOnceUntilItHasBeenQuietForHalfASecond) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.25f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;
  int starts = 0;
  const int64_t step = kSecond / 100;

  for (int i = 0; i < 10; ++i) {
    reports.ReportMetres(1, i * step, 1.25f, 1.0f, false, 0, 0, 0.8f);
    (void)filter.Apply(DriveVelocity(0.5f, 0), At(1, 1), reports, i * step, outcome);
    starts += outcome.started ? 1 : 0;
    (void)filter.Apply(DriveVelocity(-0.5f, 0), At(1, 1), reports, i * step, outcome);  // not limited
  }
  reports.ReportMetres(1, 2 * kSecond, 1.25f, 1.0f, false, 0, 0, 0.8f);
  (void)filter.Apply(DriveVelocity(0.5f, 0), At(1, 1), reports, 2 * kSecond, outcome);
  starts += outcome.started ? 1 : 0;

  EXPECT_EQ(starts, 2);
  EXPECT_EQ(filter.interventions(), 2u);
  EXPECT_EQ(filter.limited_steps(), 11u);
}

// Two robots driving head-on, each filtering against the other's report of
// the previous 50 ms round (the lab's timing), never come closer than their
// radii: the filter alone keeps them apart.
estimation::StateEstimate Doubtful(float x, float y, float position_sigma, float heading_sigma, float heading = 0) {
  estimation::StateEstimate estimate = At(x, y, heading);
  estimate.sigma_x_m = position_sigma;
  estimate.sigma_y_m = 0.5f * position_sigma;  // the larger of the two counts
  estimate.sigma_heading_rad = heading_sigma;
  return estimate;
}

TEST(SafetyFilterTest, OwnPositionDoubtGrowsEveryDisc) {
  SafetyConfig config = Config();
  config.own_sigmas = 2.0f;
  SafetyFilter filter(config, Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.35f, 1.0f, false, 0, 0, 0.8f);  // gap 0.1 m when sure of itself
  SafetyOutcome sure;
  SafetyOutcome doubtful;

  const DriveCommand approach = filter.Apply(DriveVelocity(0.4f, 0), At(1, 1), reports, 0, sure);
  // sigma 0.0625 m, two of them less half the margin (0.025 m): the disc
  // grows by 0.1 m and reaches this robot; only away or sideways.
  const DriveCommand held = filter.Apply(DriveVelocity(0.4f, 0), Doubtful(1, 1, 0.0625f, 0), reports, 0, doubtful);
  // Within half the margin nothing changes.
  const DriveCommand usual = filter.Apply(DriveVelocity(0.4f, 0), Doubtful(1, 1, 0.0125f, 0), reports, 0, sure);
  EXPECT_NEAR(usual.vx_mps, std::sqrt(0.08f), 1e-4f);

  EXPECT_NEAR(approach.vx_mps, std::sqrt(0.08f), 1e-4f);
  EXPECT_TRUE(doubtful.limited);
  EXPECT_LE(held.vx_mps, 1e-4f);
}

// The margin's share for this robot's own error: own_sigmas of its larger
// position sigma, never less than half the margin, capped; four by default
// (kOwnSigmas, docs/safety.md "Margin coverage").
TEST(SafetyFilterTest, OwnErrorAllowanceIsOwnSigmasTimesTheLargerSigmaAndAtLeastHalfTheMargin) {
  SafetyConfig config = Config();  // margin 0.05 m
  EXPECT_FLOAT_EQ(config.own_sigmas, 4.0f);
  EXPECT_FLOAT_EQ(OwnErrorAllowanceM(config, Doubtful(1, 1, 0.022f, 0)), 0.088f);
  config.own_sigmas = 2.0f;
  EXPECT_FLOAT_EQ(OwnErrorAllowanceM(config, Doubtful(1, 1, 0.022f, 0)), 0.044f);
  config.own_sigmas = 4.0f;
  estimation::StateEstimate uneven = Doubtful(1, 1, 0.01f, 0);
  uneven.sigma_y_m = 0.03f;  // the larger axis counts
  EXPECT_FLOAT_EQ(OwnErrorAllowanceM(config, uneven), 0.12f);
  EXPECT_FLOAT_EQ(OwnErrorAllowanceM(config, Doubtful(1, 1, 0.002f, 0)), 0.025f);
  EXPECT_FLOAT_EQ(OwnErrorAllowanceM(config, Doubtful(1, 1, 3.0f, 0)), 2.0f);  // capped at 0.5 m
  estimation::StateEstimate broken = At(1, 1);
  broken.sigma_x_m = std::nanf("");
  EXPECT_FLOAT_EQ(OwnErrorAllowanceM(config, broken), 2.0f);
}

// A sigma of 2.2 cm, the lab's usual: four sigmas (8.8 cm) reach past half
// the margin by 6.3 cm, two (4.4 cm) by 1.9 cm. With four, a robot 5 cm
// outside the sure disc is inside the grown one and may not approach; with
// two it still may.
TEST(SafetyFilterTest, FourSigmasOfTheUsualDoubtHoldARobotThatTwoLetApproach) {
  SafetyConfig config = Config();
  config.own_sigmas = 2.0f;
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.3f, 1.0f, false, 0, 0, 0.8f);  // sure disc: 0.25 m, gap 0.05 m
  SafetyOutcome outcome;
  SafetyFilter two(config, Omni(), 4);
  const DriveCommand approaching = two.Apply(DriveVelocity(0.4f, 0), Doubtful(1, 1, 0.022f, 0), reports, 0, outcome);
  EXPECT_GT(approaching.vx_mps, 0.05f);
  config.own_sigmas = 4.0f;
  SafetyFilter four(config, Omni(), 4);
  const DriveCommand held = four.Apply(DriveVelocity(0.4f, 0), Doubtful(1, 1, 0.022f, 0), reports, 0, outcome);
  EXPECT_TRUE(outcome.limited);
  EXPECT_LE(held.vx_mps, 1e-4f);
}

// Grading charges an app only for what it asked (charged_sigmas, two):
// a command a filter at two sigmas lets through but the four-sigma cover
// holds is a precaution; one that two sigmas would limit too starts an
// intervention, even while a precaution goes on.
TEST(SafetyFilterTest, AStepHeldOnlyByTheWiderCoverIsAPrecautionNotAnIntervention) {
  SafetyConfig config = Config();
  config.own_sigmas = 4.0f;
  ASSERT_FLOAT_EQ(config.charged_sigmas, 2.0f);
  SafetyFilter filter(config, Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.3f, 1.0f, false, 0, 0, 0.8f);  // sure disc: 0.25 m, gap 0.05 m
  SafetyOutcome outcome;

  // 5 cm/s: within two sigmas' bound (about 0.1 m/s at a 3.1 cm gap), inside the four-sigma disc.
  const DriveCommand slow = filter.Apply(DriveVelocity(0.05f, 0), Doubtful(1, 1, 0.022f, 0), reports, 0, outcome);
  EXPECT_TRUE(outcome.limited);
  EXPECT_LE(slow.vx_mps, 1e-4f);  // held all the same: the cover is what keeps robots apart
  EXPECT_FALSE(outcome.charged);
  EXPECT_FALSE(outcome.started);
  EXPECT_TRUE(outcome.precaution_started);
  EXPECT_EQ(outcome.other, 1u);

  // The next step is the same precaution, not a new one.
  (void)filter.Apply(DriveVelocity(0.05f, 0), Doubtful(1, 1, 0.022f, 0), reports, kSecond / 100, outcome);
  EXPECT_TRUE(outcome.limited);
  EXPECT_FALSE(outcome.precaution_started);

  // 0.4 m/s breaks two sigmas' rule as well: the app's doing.
  (void)filter.Apply(DriveVelocity(0.4f, 0), Doubtful(1, 1, 0.022f, 0), reports, 2 * kSecond / 100, outcome);
  EXPECT_TRUE(outcome.charged);
  EXPECT_TRUE(outcome.started);
  EXPECT_FALSE(outcome.precaution_started);
  // One intervention a hold: a slow step and a fast one again are the same hold.
  (void)filter.Apply(DriveVelocity(0.05f, 0), Doubtful(1, 1, 0.022f, 0), reports, 3 * kSecond / 100, outcome);
  (void)filter.Apply(DriveVelocity(0.4f, 0), Doubtful(1, 1, 0.022f, 0), reports, 4 * kSecond / 100, outcome);
  EXPECT_TRUE(outcome.charged);
  EXPECT_FALSE(outcome.started);

  EXPECT_EQ(filter.interventions(), 1u);
  EXPECT_EQ(filter.precautions(), 1u);
  EXPECT_EQ(filter.limited_steps(), 5u);
}

// With own_sigmas at charged_sigmas every limited step is the app's: the
// filter counts as it did before precautions existed.
TEST(SafetyFilterTest, AtTheChargedSigmasEveryLimitedStepIsAnIntervention) {
  SafetyConfig config = Config();
  config.own_sigmas = config.charged_sigmas;
  SafetyFilter filter(config, Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.3f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;
  for (const float speed : {0.2f, 0.3f, 0.4f}) {
    (void)filter.Apply(DriveVelocity(speed, 0), Doubtful(1, 1, 0.022f, 0), reports, 0, outcome);
    EXPECT_TRUE(outcome.limited) << speed;
    EXPECT_TRUE(outcome.charged) << speed;
  }
  EXPECT_EQ(filter.precautions(), 0u);
  EXPECT_EQ(filter.interventions(), 1u);
}

// The charged rule is a filter at charged_sigmas: over many seeded
// scenes (an omni robot and a rover among up to 12 reports, some fresh,
// some old, some parked, walls), a four-sigma filter's step is charged
// exactly when a two-sigma filter given the same inputs limits it.
TEST(SafetyFilterTest, AChargedStepIsOneATwoSigmaFilterLimitsToo) {
  std::mt19937 random(20261207);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int charged = 0;
  int precautions = 0;
  for (int scene = 0; scene < 4000; ++scene) {
    SafetyConfig config = Config();
    config.arena_width_m = 4.0f;
    config.arena_height_m = 4.0f;
    SafetyConfig two = config;
    two.own_sigmas = 2.0f;
    config.own_sigmas = 4.0f;
    const bool rover = scene % 2 == 1;
    SafetyFilter four_filter(config, rover ? WheeledConfig() : Omni(), 16);
    SafetyFilter two_filter(two, rover ? WheeledConfig() : Omni(), 16);
    SafetyReports reports;
    const float x = 0.5f + 3.0f * unit(random);
    const float y = 0.5f + 3.0f * unit(random);
    const int64_t now = 2 * kSecond;
    const int others = 1 + static_cast<int>(unit(random) * 12.0f);
    for (int id = 1; id <= others; ++id) {
      const float angle = 6.2831853f * unit(random);
      const float distance = 0.2f + 0.6f * unit(random);
      const auto age = static_cast<int64_t>(unit(random) * 1.5e9f);
      const bool parked = unit(random) < 0.3f;
      reports.ReportMetres(static_cast<uint16_t>(id), now - age, x + distance * std::cos(angle),
                           y + distance * std::sin(angle), parked, 0.2f * unit(random), 0.0f, 0.8f);
    }
    const float sigma = 0.005f + 0.04f * unit(random);
    const estimation::StateEstimate estimate = Doubtful(x, y, sigma, 0.1f * unit(random), 6.2831853f * unit(random));
    const float speed = 0.5f * unit(random);
    const float direction = 6.2831853f * unit(random);
    const DriveCommand desired = rover ? Wheels(speed, speed)
                                       : DriveVelocity(speed * std::cos(direction), speed * std::sin(direction));
    SafetyOutcome four_outcome;
    SafetyOutcome two_outcome;
    (void)four_filter.Apply(desired, estimate, reports, now, four_outcome);
    (void)two_filter.Apply(desired, estimate, reports, now, two_outcome);
    ASSERT_EQ(four_outcome.charged, two_outcome.limited) << "scene " << scene;
    if (two_outcome.limited) {
      EXPECT_TRUE(four_outcome.limited) << "scene " << scene;
    }
    charged += four_outcome.charged ? 1 : 0;
    precautions += four_outcome.limited && !four_outcome.charged ? 1 : 0;
  }
  // Both kinds of step occur, often: the comparison is not vacuous.
  EXPECT_GT(charged, 400);
  EXPECT_GT(precautions, 20);  // 36 of the 4000 scenes
}

TEST(SafetyFilterTest, ALostEstimateStopsNearOthersOnly) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.6f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;
  // A relocalizing filter claims metres of doubt: capped at 0.5 m, two of
  // them less 0.025 m, a disc of 1.225 m around a robot 0.6 m away.
  const DriveCommand lost = filter.Apply(DriveVelocity(0.3f, 0.2f), Doubtful(1, 1, 3.0f, 0), reports, 0, outcome);
  EXPECT_TRUE(outcome.limited);
  EXPECT_LE(lost.vx_mps, 1e-4f);  // nothing towards it

  estimation::StateEstimate broken = At(1, 1);
  broken.sigma_x_m = std::nanf("");  // a doubt that is not a number counts as the largest
  const DriveCommand nan = filter.Apply(DriveVelocity(0.3f, 0), broken, reports, 0, outcome);
  EXPECT_LE(nan.vx_mps, 1e-4f);

  SafetyReports far;
  far.ReportMetres(1, 0, 3.5f, 3.5f, false, 0, 0, 0.8f);
  const DriveCommand alone = filter.Apply(DriveVelocity(0.3f, 0), Doubtful(1, 1, 3.0f, 0), far, 0, outcome);
  EXPECT_FALSE(outcome.limited);
  EXPECT_FLOAT_EQ(alone.vx_mps, 0.3f);
}

TEST(SafetyFilterTest, HeadingDoubtSlowsATangentThatATurnWouldBendInwards) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.27f, 1.0f, false, 0, 0, 0.8f);  // gap 0.02 m: u . n <= min(0.08, 0.126)
  SafetyOutcome outcome;

  const DriveCommand sure = filter.Apply(DriveVelocity(0, 0.3f), At(1, 1), reports, 0, outcome);
  EXPECT_FLOAT_EQ(sure.vy_mps, 0.3f);  // a pure tangent is never limited
  // A well-known heading (sigma 0.05 rad: two of them are the 0.1 rad the
  // margin absorbs) changes nothing.
  const DriveCommand known = filter.Apply(DriveVelocity(0, 0.3f), Doubtful(1, 1, 0, 0.05f), reports, 0, outcome);
  EXPECT_FALSE(outcome.limited);
  EXPECT_FLOAT_EQ(known.vy_mps, 0.3f);
  // sigma 0.3 rad, two of them less 0.1: the body may move 0.5 rad off the
  // tangent, 0.3 sin(0.5) towards the disc; scaled to keep 0.08.
  const DriveCommand doubtful = filter.Apply(DriveVelocity(0, 0.3f), Doubtful(1, 1, 0, 0.3f), reports, 0, outcome);
  EXPECT_TRUE(outcome.limited);
  EXPECT_NEAR(doubtful.vy_mps, 0.08f / std::sin(0.5f), 1e-4f);
  EXPECT_NEAR(doubtful.vx_mps, 0, 1e-6f);
  // Straight away from it stays away in every turn of half a radian.
  const DriveCommand away = filter.Apply(DriveVelocity(-0.3f, 0), Doubtful(1, 1, 0, 0.3f), reports, 0, outcome);
  EXPECT_FLOAT_EQ(away.vx_mps, -0.3f);
}

TEST(SafetyFilterTest, HeadingDoubtInsideADiscKeepsOnlyDirectionsSafeInEveryTurn) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.2f, 1.0f, false, 0, 0, 0.8f);
  SafetyOutcome outcome;
  const int64_t later = kSecond / 10;  // sin(phi) = 0.25: within acos(0.25) = 1.318 rad of straight away
  // 1.2 rad off straight away (-x): inside the cone when sure.
  const float vx = -0.3f * std::cos(1.2f);
  const float vy = 0.3f * std::sin(1.2f);
  const DriveCommand sure = filter.Apply(DriveVelocity(vx, vy), At(1, 1), reports, later, outcome);
  EXPECT_FLOAT_EQ(sure.vx_mps, vx);
  // A doubt of 2 x 0.15 - 0.1 = 0.2 rad could turn it to 1.4 rad, outside: stop.
  const DriveCommand doubtful = filter.Apply(DriveVelocity(vx, vy), Doubtful(1, 1, 0, 0.15f), reports, later, outcome);
  EXPECT_NEAR(doubtful.vx_mps, 0, 1e-6f);
  EXPECT_NEAR(doubtful.vy_mps, 0, 1e-6f);
  const DriveCommand away = filter.Apply(DriveVelocity(-0.3f, 0), Doubtful(1, 1, 0, 0.15f), reports, later, outcome);
  EXPECT_FLOAT_EQ(away.vx_mps, -0.3f);
}

TEST(SafetyFilterTest, HeadingDoubtSlowsARoverPassingCloseBy) {
  SafetyFilter filter(Config(), WheeledConfig(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.0f, 1.27f, false, 0, 0, 0.8f);  // gap 0.02 m to its left
  SafetyOutcome outcome;
  // Heading +x, driving past it: no forward component towards it when sure.
  const DriveCommand sure = filter.Apply(Wheels(0.3f, 0.3f), At(1, 1, 0), reports, 0, outcome);
  EXPECT_FLOAT_EQ(sure.left_mps, 0.3f);
  const DriveCommand doubtful = filter.Apply(Wheels(0.3f, 0.3f), Doubtful(1, 1, 0, 0.3f, 0), reports, 0, outcome);
  EXPECT_NEAR(0.5f * (doubtful.left_mps + doubtful.right_mps), 0.08f / std::sin(0.5f), 1e-4f);
}

TEST(SafetyFilterTest, AReportFreshWhenThisRobotPausedGrowsForThePauseToo) {
  SafetyFilter filter(Config(), Omni(), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 2.5f, 1.0f, false, 0, 0, 0.8f);  // 1.5 m away
  SafetyOutcome outcome;
  // 7 s later without a gap: the disc stopped growing at 1 s, 0.75 m.
  const DriveCommand capped = filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), reports, 7 * kSecond, outcome);
  EXPECT_FALSE(outcome.limited);
  EXPECT_FLOAT_EQ(capped.vx_mps, 0.3f);
  // This robot was paused from 0.5 s to 6.5 s while robot 1 was talking: it
  // may have driven all that time, 3.5 m of disc; this robot stands in it.
  reports.MarkListeningGap(kSecond / 2, 13 * kSecond / 2);
  const DriveCommand held = filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), reports, 7 * kSecond, outcome);
  EXPECT_NEAR(held.vx_mps, 0, 1e-6f);
  EXPECT_NEAR(held.vy_mps, 0, 1e-6f);
  // A report already older than the horizon when the pause began (a robot
  // silent before it: crashed, paused) keeps its capped disc.
  reports.MarkListeningGap(2 * kSecond, 8 * kSecond);
  const DriveCommand stale = filter.Apply(DriveVelocity(0.3f, 0), At(1, 1), reports, 9 * kSecond, outcome);
  EXPECT_FLOAT_EQ(stale.vx_mps, 0.3f);
  // The motion task's copy carries the gap.
  SafetyReports copy;
  copy.CopyFrom(reports, 4);
  EXPECT_EQ(copy.gap_start_ns(), 2 * kSecond);
  EXPECT_EQ(copy.gap_end_ns(), 8 * kSecond);
}

TEST(SafetyFilterTest, TwoRobotsDrivingHeadOnNeverTouch) {
  SafetyFilter a(Config(), Omni(), 2);
  SafetyConfig b_config = Config();
  b_config.self_id = 1;
  SafetyFilter b(b_config, Omni(), 2);
  SafetyReports reports;
  float ax = 0.5f;
  float bx = 2.5f;
  float avx = 0;
  float bvx = 0;
  float closest = 10;
  const int64_t step = kSecond / 100;
  for (int i = 0; i < 800; ++i) {
    const int64_t now = i * step;
    if (i % 5 == 0) {  // a beacon per round, a round old when heard
      reports.ReportMetres(0, now - 5 * step, ax - avx * 0.05f, 1, false, avx, 0, 0.8f);
      reports.ReportMetres(1, now - 5 * step, bx - bvx * 0.05f, 1, false, bvx, 0, 0.8f);
    }
    SafetyOutcome outcome;
    const float a_cmd = a.Apply(DriveVelocity(0.5f, 0), At(ax, 1), reports, now, outcome).vx_mps;
    const float b_cmd = b.Apply(DriveVelocity(-0.5f, 0), At(bx, 1), reports, now, outcome).vx_mps;
    // Bodies slew towards the setpoint at 1 m/s^2, as the lab's omni bodies do.
    avx += std::clamp(a_cmd - avx, -0.01f, 0.01f);
    bvx += std::clamp(b_cmd - bvx, -0.01f, 0.01f);
    ax += avx * 0.01f;
    bx += bvx * 0.01f;
    closest = std::min(closest, bx - ax);
  }
  EXPECT_GT(closest, 0.2f);
  EXPECT_LT(closest, 0.5f);  // and they did come close: the filter let them approach
}


// A drone: its velocity follows the setpoint through a tilt lag.
ControllerConfig Lagged(float lag_s) {
  ControllerConfig config = Omni();
  config.limits.response_lag_s = lag_s;
  return config;
}

TEST(BrakingSpeedTest, WithoutALagItIsTheSquareRootBitForBit) {
  for (const float d : {0.0f, 0.001f, 0.1f, 0.37f, 2.0f}) {
    EXPECT_EQ(BrakingSpeed(d, 0.8f, 0.0f), std::sqrt(2.0f * 0.8f * d));
  }
}

TEST(BrakingSpeedTest, WithALagTheBodyStopsExactlyWithinTheDistance) {
  for (const float d : {0.001f, 0.1f, 0.5f, 2.0f}) {
    const float v = BrakingSpeed(d, 0.4f, 0.25f);
    EXPECT_NEAR(v * 0.25f + v * v / (2.0f * 0.4f), d, 1e-6f * (1 + d));
    EXPECT_LT(v, std::sqrt(2.0f * 0.4f * d));
  }
  EXPECT_EQ(BrakingSpeed(0.0f, 0.4f, 0.25f), 0.0f);
}

TEST(SafetyFilterTest, ALaggedRobotApproachesOnItsLaggedCurveWithHalfTheGapAndTwiceTheLag) {
  SafetyFilter filter(Config(), Lagged(0.25f), 4);
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.35f, 1.0f, false, 0, 0, 0.8f);  // gap 0.1 m, as above
  SafetyOutcome outcome;

  const DriveCommand out = filter.Apply(DriveVelocity(0.4f, 0.3f), At(1, 1), reports, 0, outcome);

  // Shared braking 0.4 m/s^2 with twice the lag: v 0.5 + v^2 / 0.8 = 0.1,
  // 0.1464 m/s, where the omni above may approach at 0.283 m/s.
  EXPECT_NEAR(out.vx_mps, BrakingSpeed(0.1f, 0.4f, 0.5f), 1e-6f);
  EXPECT_NEAR(out.vx_mps, 0.1464f, 1e-4f);
  EXPECT_FLOAT_EQ(out.vy_mps, 0.3f);
  EXPECT_TRUE(outcome.limited);
}

TEST(SafetyFilterTest, ALaggedRobotBrakesForAWallOnItsLaggedCurve) {
  SafetyConfig config = Config();
  config.arena_width_m = 4;
  config.arena_height_m = 4;
  SafetyFilter filter(config, Lagged(0.25f), 4);
  SafetyReports reports;
  SafetyOutcome outcome;

  // 0.2 m from the wall at x = 4 beyond radius and margin.
  const DriveCommand out = filter.Apply(DriveVelocity(0.5f, 0), At(4 - 0.1f - 0.05f - 0.2f, 2), reports, 0, outcome);

  EXPECT_NEAR(out.vx_mps, BrakingSpeed(0.2f, 0.8f, 0.25f), 1e-5f);
  EXPECT_LT(out.vx_mps, std::sqrt(2.0f * 0.8f * 0.2f));
}

TEST(SafetyReportsTest, AParkedReportsAllowanceAddsTheSwarmsLagAtItsSpeed) {
  SafetyReports reports;
  reports.ReportMetres(1, 0, 1.0f, 1.0f, true, 0.4f, 0, 0.8f);
  reports.ReportMetres(2, 0, 2.0f, 1.0f, true, 0.4f, 0, 0.8f, 0.25f);
  EXPECT_EQ(reports[1].allowance_mm, 100);        // 0.4^2 / 1.6
  EXPECT_EQ(reports[2].allowance_mm, 100 + 100);  // + 0.4 * 0.25
}

}  // namespace
}  // namespace syrof::motion
