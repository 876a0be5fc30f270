// Each rule of the sweep policy (uwb_screen.h) on its own, in double on the
// default arena with exact ranges unless a test plants an outlier.
#include "syrof/estimation/uwb_screen.h"

#include <gtest/gtest.h>

#include <cmath>

#include "syrof/estimation/range_model.h"

namespace syrof::estimation {
namespace {

using Config = EstimatorConfig<double>;

// A sweep of exact ranges from (x, y) on the antenna plane to every anchor.
UwbReading ExactSweep(const Config& config, double x, double y) {
  UwbReading sweep{};
  StateVector<double> at = StateVector<double>::Zero();
  at[kStateX] = x;
  at[kStateY] = y;
  for (int i = 0; i < config.arena.anchor_count; ++i) {
    sweep.range_m[i] = static_cast<float>(PredictRange(at, config.arena.anchors[i], config.arena.tag_height_m));
    sweep.valid_mask |= 1u << i;
  }
  return sweep;
}

// A filter at (x, y), at rest, with position standard deviation sigma_m.
Ekf<double> FilterAt(const Config& config, double x, double y, double sigma_m) {
  Ekf<double> filter(config.filter);
  InitialPose<double> pose;
  pose.x_m = x;
  pose.y_m = y;
  pose.position_sigma_m = sigma_m;
  StartFilter(filter, pose, config);
  return filter;
}

TEST(UwbScreenTest, GatherRangesKeepsValidRangesToTheArenasAnchorsInOrder) {
  Config config;
  UwbReading sweep = ExactSweep(config, 1.0, 2.0);
  sweep.valid_mask = 0b1101u | (1u << 6);  // anchor 1 failed; bit 6 is beyond the arena's four
  const SweepRanges<double> ranges = GatherRanges(config.arena, sweep);
  ASSERT_EQ(ranges.count, 3u);
  EXPECT_EQ(ranges.anchor_index[0], 0);
  EXPECT_EQ(ranges.anchor_index[1], 2);
  EXPECT_EQ(ranges.anchor_index[2], 3);
  EXPECT_EQ(ranges.ranges_m[1], static_cast<double>(sweep.range_m[2]));
  EXPECT_EQ(ranges.anchors[2], config.arena.anchors[3]);
}

TEST(UwbScreenTest, ChooseSweepUseGoesByTheLargerPositionVariance) {
  Config config;  // fix above 0.5 m, screen above 0.1 m
  StateCovariance<double> covariance = StateCovariance<double>::Identity() * 1e-4;
  EXPECT_EQ(ChooseSweepUse(covariance, config), SweepUse::kFuse);
  covariance(kStateY, kStateY) = 0.2 * 0.2;
  EXPECT_EQ(ChooseSweepUse(covariance, config), SweepUse::kScreenThenFuse);
  covariance(kStateX, kStateX) = 0.6 * 0.6;
  EXPECT_EQ(ChooseSweepUse(covariance, config), SweepUse::kFixOnly);
  covariance(kStateX, kStateX) = 0.5 * 0.5;  // at the threshold: not above it
  EXPECT_EQ(ChooseSweepUse(covariance, config), SweepUse::kScreenThenFuse);
}

TEST(UwbScreenTest, FixFromRangesPlacesAConsistentSweepAndRefusesTwoOutliers) {
  Config config;
  UwbReading sweep = ExactSweep(config, 1.5, 2.5);
  const auto fix = FixFromRanges(GatherRanges(config.arena, sweep), config);
  ASSERT_TRUE(fix.ok());
  EXPECT_NEAR(fix.value()[0], 1.5, 1e-3);
  EXPECT_NEAR(fix.value()[1], 2.5, 1e-3);

  sweep.range_m[0] += 1.5f;
  sweep.range_m[1] += 1.0f;
  EXPECT_FALSE(FixFromRanges(GatherRanges(config.arena, sweep), config).ok());
}

TEST(UwbScreenTest, ScreenRangesNamesTheOutlierByItsArenaIndex) {
  Config config;
  UwbReading sweep = ExactSweep(config, 2.0, 1.0);
  sweep.range_m[2] += 1.5f;  // non-line-of-sight: long
  const Ekf<double> filter = FilterAt(config, 2.1, 1.1, 0.3);
  EXPECT_EQ(ScreenRanges(filter.state(), GatherRanges(config.arena, sweep), config), 2);

  sweep.valid_mask &= ~(1u << 0);  // three ranges: an outlier can be seen, not named
  EXPECT_EQ(ScreenRanges(filter.state(), GatherRanges(config.arena, sweep), config), -1);
}

TEST(UwbScreenTest, ScreenRangesPassesAConsistentSweep) {
  Config config;
  const UwbReading sweep = ExactSweep(config, 2.0, 1.0);
  const Ekf<double> filter = FilterAt(config, 2.1, 1.1, 0.3);
  EXPECT_EQ(ScreenRanges(filter.state(), GatherRanges(config.arena, sweep), config), -1);
}

TEST(UwbScreenTest, TrackConsistencyCountsSweepsWithTwoRejectionsInARow) {
  EXPECT_EQ(TrackConsistency(0, 2, 5).inconsistent_sweeps, 1);
  EXPECT_EQ(TrackConsistency(3, 4, 5).inconsistent_sweeps, 4);
  EXPECT_FALSE(TrackConsistency(3, 4, 5).relocalize);
  EXPECT_EQ(TrackConsistency(3, 1, 5).inconsistent_sweeps, 0);  // one outlier is common: the run ends
  EXPECT_FALSE(TrackConsistency(3, 1, 5).relocalize);
}

TEST(UwbScreenTest, TrackConsistencyRelocalizesAtTheLimitAndStartsAgain) {
  const ConsistencyUpdate update = TrackConsistency(4, 2, 5);
  EXPECT_TRUE(update.relocalize);
  EXPECT_EQ(update.inconsistent_sweeps, 0);
}

TEST(UwbScreenTest, StartFilterSetsPoseAtRestWithTheConfiguredSigmas) {
  Config config;
  config.initial_velocity_sigma_mps = 0.4;
  config.initial_gyro_bias_sigma_radps = 0.03;
  Ekf<double> filter(config.filter);
  const InitialPose<double> pose{1.0, 2.0, 0.5, 0.2, 0.1};
  StartFilter(filter, pose, config);
  EXPECT_EQ(filter.state()[kStateX], 1.0);
  EXPECT_EQ(filter.state()[kStateY], 2.0);
  EXPECT_EQ(filter.state()[kStateVx], 0.0);
  EXPECT_EQ(filter.state()[kStateHeading], 0.5);
  EXPECT_NEAR(filter.covariance()(kStateX, kStateX), 0.04, 1e-12);
  EXPECT_NEAR(filter.covariance()(kStateVy, kStateVy), 0.16, 1e-12);
  EXPECT_NEAR(filter.covariance()(kStateHeading, kStateHeading), 0.01, 1e-12);
  EXPECT_NEAR(filter.covariance()(kStateGyroBias, kStateGyroBias), 0.0009, 1e-12);
}

TEST(UwbScreenTest, PoseFromFixTakesHeadingAndSigmasFromTheConfig) {
  Config config;
  config.initial_heading_rad = 1.0;
  const InitialPose<double> pose = PoseFromFix(Vector2<double>(3.0, 0.5), config);
  EXPECT_EQ(pose.x_m, 3.0);
  EXPECT_EQ(pose.y_m, 0.5);
  EXPECT_EQ(pose.heading_rad, 1.0);
  EXPECT_EQ(pose.position_sigma_m, config.initial_position_sigma_m);
  EXPECT_EQ(pose.heading_sigma_rad, config.initial_heading_sigma_rad);
}

TEST(UwbScreenTest, StartFilterFromSweepLeavesTheFilterAloneWithoutAFix) {
  Config config;
  Ekf<double> filter = FilterAt(config, 1.0, 1.0, 0.1);
  UwbReading sweep = ExactSweep(config, 3.0, 3.0);
  sweep.range_m[0] += 1.5f;
  sweep.range_m[3] += 1.0f;
  EXPECT_FALSE(StartFilterFromSweep(filter, sweep, config));
  EXPECT_EQ(filter.state()[kStateX], 1.0);

  EXPECT_TRUE(StartFilterFromSweep(filter, ExactSweep(config, 3.0, 3.0), config));
  EXPECT_NEAR(filter.state()[kStateX], 3.0, 1e-3);
  EXPECT_NEAR(filter.state()[kStateY], 3.0, 1e-3);
}

TEST(UwbScreenTest, ApplySweepWhenLostOnlyAFixMovesTheRobot) {
  Config config;
  Ekf<double> filter = FilterAt(config, 0.5, 0.5, 1.0);  // lost: 1 m > 0.5 m
  int inconsistent_sweeps = 3;
  const SweepOutcome outcome = ApplySweep(filter, inconsistent_sweeps, ExactSweep(config, 3.0, 2.0), config);
  EXPECT_TRUE(outcome.fixed);
  EXPECT_EQ(outcome.fused, 0);  // the fix replaces the updates
  EXPECT_EQ(inconsistent_sweeps, 0);
  EXPECT_NEAR(filter.state()[kStateX], 3.0, 1e-3);
  EXPECT_NEAR(std::sqrt(filter.covariance()(kStateX, kStateX)), config.initial_position_sigma_m, 1e-9);
}

TEST(UwbScreenTest, ApplySweepWhenLostIgnoresASweepWithoutAFix) {
  Config config;
  Ekf<double> filter = FilterAt(config, 0.5, 0.5, 1.0);
  UwbReading sweep = ExactSweep(config, 3.0, 2.0);
  sweep.valid_mask = 0b0011u;  // two ranges cannot place a robot
  ASSERT_FALSE(FixFromRanges(GatherRanges(config.arena, sweep), config).ok());
  int inconsistent_sweeps = 3;
  const SweepOutcome outcome = ApplySweep(filter, inconsistent_sweeps, sweep, config);
  EXPECT_FALSE(outcome.fixed);
  EXPECT_EQ(outcome.fused + outcome.rejected, 0);
  EXPECT_EQ(inconsistent_sweeps, 3);
  EXPECT_EQ(filter.state()[kStateX], 0.5);
}

TEST(UwbScreenTest, ApplySweepWhenUncertainDropsTheScreenedRangeAndFusesTheRest) {
  Config config;
  Ekf<double> filter = FilterAt(config, 2.1, 1.1, 0.3);  // uncertain: 0.1 m < 0.3 m <= 0.5 m
  UwbReading sweep = ExactSweep(config, 2.0, 1.0);
  sweep.range_m[2] += 1.5f;
  int inconsistent_sweeps = 0;
  const SweepOutcome outcome = ApplySweep(filter, inconsistent_sweeps, sweep, config);
  EXPECT_EQ(outcome.rejected, 1);
  EXPECT_EQ(outcome.fused, 3);
  EXPECT_EQ(inconsistent_sweeps, 0);  // one range out is not inconsistent
  EXPECT_NEAR(filter.state()[kStateX], 2.0, 0.05);
}

TEST(UwbScreenTest, ApplySweepWhenSteadyGatesEachRange) {
  Config config;
  Ekf<double> filter = FilterAt(config, 2.0, 1.0, 0.05);  // steady: no screen
  int inconsistent_sweeps = 0;
  const SweepOutcome outcome = ApplySweep(filter, inconsistent_sweeps, ExactSweep(config, 2.0, 1.0), config);
  EXPECT_EQ(outcome.fused, 4);
  EXPECT_EQ(outcome.rejected, 0);
  EXPECT_FALSE(outcome.fixed);
}

TEST(UwbScreenTest, ApplySweepInflatesTheVarianceAfterTooManyInconsistentSweeps) {
  Config config;
  config.max_inconsistent_sweeps = 2;
  Ekf<double> filter = FilterAt(config, 2.0, 1.0, 0.05);
  UwbReading sweep = ExactSweep(config, 2.0, 1.0);
  sweep.range_m[0] += 1.5f;  // two ranges far outside a 5 cm filter's gate
  sweep.range_m[3] += 1.5f;
  int inconsistent_sweeps = 0;
  const SweepOutcome first = ApplySweep(filter, inconsistent_sweeps, sweep, config);
  EXPECT_EQ(first.rejected, 2);
  EXPECT_FALSE(first.relocalized);
  EXPECT_EQ(inconsistent_sweeps, 1);
  const double variance_before = filter.covariance()(kStateX, kStateX);
  const SweepOutcome second = ApplySweep(filter, inconsistent_sweeps, sweep, config);
  EXPECT_TRUE(second.relocalized);
  EXPECT_EQ(inconsistent_sweeps, 0);
  EXPECT_GT(filter.covariance()(kStateX, kStateX), variance_before + 0.5 * config.relocalization_variance_m2);
}

}  // namespace
}  // namespace syrof::estimation
