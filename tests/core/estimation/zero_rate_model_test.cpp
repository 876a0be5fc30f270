#include "syrof/estimation/zero_rate_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "syrof/estimation/ekf.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {
namespace {

constexpr int64_t kStepNs = 10'000'000;  // the Kalman task's 100 Hz

TEST(ZeroRateDetectorTest, CallsTheRobotStillOnlyAfterTheQuietPeriod) {
  const ZeroRateConfig<double> config;  // 0.02 rad/s for 200 ms
  ZeroRateDetector<double> detector;
  int64_t now_ns = 0;
  for (; now_ns < config.after_ns; now_ns += kStepNs) {
    EXPECT_FALSE(detector.Step(config, 0.001, now_ns)) << now_ns;
  }
  EXPECT_TRUE(detector.Step(config, 0.001, now_ns));
  EXPECT_TRUE(detector.Step(config, -0.019, now_ns + kStepNs));
}

TEST(ZeroRateDetectorTest, ATurnStartsTheQuietPeriodAgain) {
  const ZeroRateConfig<double> config;
  ZeroRateDetector<double> detector;
  int64_t now_ns = 0;
  for (; now_ns <= config.after_ns; now_ns += kStepNs) (void)detector.Step(config, 0.0, now_ns);
  ASSERT_TRUE(detector.Step(config, 0.0, now_ns));
  EXPECT_FALSE(detector.Step(config, 0.3, now_ns += kStepNs));     // turning
  EXPECT_FALSE(detector.Step(config, -0.02, now_ns += kStepNs));   // the threshold itself is a turn
  EXPECT_FALSE(detector.Step(config, 0.0, now_ns += kStepNs));     // quiet again, but only just
  const int64_t quiet_since_ns = now_ns;
  for (now_ns += kStepNs; now_ns < quiet_since_ns + config.after_ns; now_ns += kStepNs) {
    EXPECT_FALSE(detector.Step(config, 0.0, now_ns));
  }
  EXPECT_TRUE(detector.Step(config, 0.0, now_ns));
}

TEST(ZeroRateDetectorTest, ResetDisabledAndNonFiniteRatesNeverCallItStill) {
  ZeroRateConfig<double> config;
  ZeroRateDetector<double> detector;
  for (int64_t now_ns = 0; now_ns <= config.after_ns; now_ns += kStepNs) (void)detector.Step(config, 0.0, now_ns);
  detector.Reset();
  EXPECT_FALSE(detector.Step(config, 0.0, config.after_ns + kStepNs));

  ZeroRateDetector<double> fresh;
  EXPECT_FALSE(fresh.Step(config, std::numeric_limits<double>::quiet_NaN(), 0));

  config.enabled = false;
  ZeroRateDetector<double> disabled;
  for (int64_t now_ns = 0; now_ns <= 10 * config.after_ns; now_ns += kStepNs) {
    EXPECT_FALSE(disabled.Step(config, 0.0, now_ns));
  }
}

Ekf<double> FilterWithBias(double bias_radps, double bias_sigma_radps) {
  Ekf<double> filter;
  StateVector<double> state;
  state << 1, 2, 0, 0, 0.5, bias_radps;
  StateVector<double> sigma;
  sigma << 0.05, 0.05, 0.05, 0.05, 0.1, bias_sigma_radps;
  filter.Reset(state, sigma);
  return filter;
}

TEST(FuseZeroRateTest, MeasuresTheBiasAndTouchesNothingItIsNotCorrelatedWith) {
  const ZeroRateConfig<double> config;
  Ekf<double> filter = FilterWithBias(0.0, 0.02);
  const StateVector<double> before = filter.state();
  // The gyro reads 0.012 rad/s while the robot stands: that is the bias.
  for (int step = 0; step < 100; ++step) ASSERT_EQ(FuseZeroRate(filter, 0.012, config), EstimationError::kOk);
  EXPECT_NEAR(filter.state()[kStateGyroBias], 0.012, 1e-4);
  EXPECT_LT(std::sqrt(filter.covariance()(kStateGyroBias, kStateGyroBias)), 0.001);
  for (int index = 0; index < kStateGyroBias; ++index) EXPECT_EQ(filter.state()[index], before[index]) << index;
}

TEST(FuseZeroRateTest, OneUpdateMovesTheBiasByTheKalmanGainOnly) {
  const ZeroRateConfig<double> config;
  Ekf<double> filter = FilterWithBias(0.0, 0.005);
  ASSERT_EQ(FuseZeroRate(filter, 0.01, config), EstimationError::kOk);
  // Equal prior and measurement variances (0.005^2 each): half way.
  EXPECT_NEAR(filter.state()[kStateGyroBias], 0.005, 1e-9);
}

TEST(FuseZeroRateTest, TheGateRejectsARateThatIsATurnAndChangesNothing) {
  const ZeroRateConfig<double> config;
  Ekf<double> filter = FilterWithBias(0.0, 0.001);
  const StateVector<double> before = filter.state();
  EXPECT_EQ(FuseZeroRate(filter, 0.5, config), EstimationError::kRejectedByGate);
  EXPECT_EQ(filter.state(), before);
}

}  // namespace
}  // namespace syrof::estimation
