#include "syrof/estimation/ekf.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>

#include "estimation_test_support.h"
#include "syrof/estimation/arena.h"
#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/range_model.h"

namespace syrof::estimation {
namespace {

using testing::RandomCovariance;
using testing::RandomState;

ScalarMeasurement<double> PositionXMeasurement(double innovation, double variance) {
  ScalarMeasurement<double> measurement;
  measurement.innovation = innovation;
  measurement.variance = variance;
  measurement.count = 1;
  measurement.index[0] = kStateX;
  measurement.jacobian[0] = 1.0;
  return measurement;
}

TEST(EkfTest, ResetSetsStateAndDiagonalCovariance) {
  Ekf<double> filter;
  StateVector<double> state;
  state << 1, 2, 0.1, 0.2, 4.0, 0.01;  // heading beyond pi
  StateVector<double> sigma;
  sigma << 0.5, 0.5, 0.2, 0.2, 0.1, 0.01;
  filter.Reset(state, sigma);
  EXPECT_NEAR(filter.state()[kStateHeading], 4.0 - 2 * kPi<double>, 1e-12);
  EXPECT_EQ(filter.covariance().diagonal(), sigma.cwiseProduct(sigma));
  EXPECT_EQ(filter.covariance()(0, 1), 0.0);
}

// With the optimal gain, the Joseph form equals the textbook P - K H P.
TEST(EkfUpdateTest, MatchesTheTextbookUpdateForAnySparseMeasurement) {
  std::mt19937_64 random(51);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const StateVector<double> state = RandomState(random);
    const StateCovariance<double> covariance = RandomCovariance(random);
    ScalarMeasurement<double> measurement;
    measurement.count = 1 + trial % 3;
    const int indices[3] = {trial % kStateSize, (trial + 2) % kStateSize, (trial + 3) % kStateSize};
    Eigen::Matrix<double, 1, kStateSize> h = Eigen::Matrix<double, 1, kStateSize>::Zero();
    for (int m = 0; m < measurement.count; ++m) {
      measurement.index[m] = indices[m];
      measurement.jacobian[m] = value(random);
      h(0, indices[m]) = measurement.jacobian[m];
    }
    measurement.innovation = 0.1 * value(random);
    measurement.variance = 0.01;

    Ekf<double> filter;
    filter.ResetWithCovariance(state, covariance);
    ASSERT_EQ(filter.Update(measurement, 0.0), EstimationError::kOk);

    const double innovation_variance = (h * covariance * h.transpose())(0, 0) + measurement.variance;
    const StateVector<double> gain = covariance * h.transpose() / innovation_variance;
    StateVector<double> expected_state = state + gain * measurement.innovation;
    expected_state[kStateHeading] = WrapAngle(expected_state[kStateHeading]);
    const StateCovariance<double> expected = (StateCovariance<double>::Identity() - gain * h) * covariance;
    EXPECT_LT((filter.state() - expected_state).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((filter.covariance() - expected).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_EQ(filter.covariance(), filter.covariance().transpose());
    EXPECT_NEAR(filter.last_normalized_innovation_squared(),
                measurement.innovation * measurement.innovation / innovation_variance, 1e-14);
  }
}

TEST(EkfUpdateTest, RefusesMalformedMeasurementsWithoutChangingAnything) {
  Ekf<double> filter;
  filter.Reset(StateVector<double>::Zero(), StateVector<double>::Constant(0.1));
  const StateCovariance<double> before = filter.covariance();

  ScalarMeasurement<double> no_entries = PositionXMeasurement(0.1, 0.01);
  no_entries.count = 0;
  ScalarMeasurement<double> bad_index = PositionXMeasurement(0.1, 0.01);
  bad_index.index[0] = kStateSize;
  ScalarMeasurement<double> duplicate = PositionXMeasurement(0.1, 0.01);
  duplicate.count = 2;
  duplicate.index[1] = kStateX;
  duplicate.jacobian[1] = 1.0;
  const ScalarMeasurement<double> nan_innovation = PositionXMeasurement(std::nan(""), 0.01);
  const ScalarMeasurement<double> zero_variance = PositionXMeasurement(0.1, 0.0);
  ScalarMeasurement<double> infinite_jacobian = PositionXMeasurement(0.1, 0.01);
  infinite_jacobian.jacobian[0] = INFINITY;

  for (const ScalarMeasurement<double>& measurement :
       {no_entries, bad_index, duplicate, nan_innovation, zero_variance, infinite_jacobian}) {
    EXPECT_EQ(filter.Update(measurement, 3.0), EstimationError::kInvalidMeasurement);
  }
  EXPECT_EQ(filter.state(), StateVector<double>::Zero());
  EXPECT_EQ(filter.covariance(), before);
}

TEST(EkfUpdateTest, GateRejectsBeyondItsSigmasAndAcceptsWithin) {
  Ekf<double> filter;
  filter.Reset(StateVector<double>::Zero(), StateVector<double>::Constant(0.3));  // P_xx 0.09
  // Innovation variance 0.09 + 0.01 = 0.1; 3 sigma is 0.949.
  EXPECT_EQ(filter.Update(PositionXMeasurement(1.0, 0.01), 3.0), EstimationError::kRejectedByGate);
  EXPECT_NEAR(filter.last_normalized_innovation_squared(), 10.0, 1e-12);
  EXPECT_EQ(filter.state()[kStateX], 0.0);
  EXPECT_EQ(filter.Update(PositionXMeasurement(0.9, 0.01), 3.0), EstimationError::kOk);
  EXPECT_NEAR(filter.state()[kStateX], 0.9 * 0.9, 1e-12);
  // A gate of zero accepts anything.
  EXPECT_EQ(filter.Update(PositionXMeasurement(100.0, 0.01), 0.0), EstimationError::kOk);
}

TEST(EkfUpdateTest, InflatingThePositionVarianceReopensTheGate) {
  Ekf<double> filter;
  filter.Reset(StateVector<double>::Zero(), StateVector<double>::Constant(0.05));
  EXPECT_EQ(filter.Update(PositionXMeasurement(1.0, 0.01), 3.5), EstimationError::kRejectedByGate);
  filter.InflatePositionVariance(1.0);
  EXPECT_NEAR(filter.covariance()(kStateX, kStateX), 1.0025, 1e-12);
  EXPECT_NEAR(filter.covariance()(kStateY, kStateY), 1.0025, 1e-12);
  EXPECT_EQ(filter.Update(PositionXMeasurement(1.0, 0.01), 3.5), EstimationError::kOk);
}

// Float, as on the Teensy: a long run of predictions and every kind of
// update keeps P exactly symmetric and positive definite, including after
// the outage of one sensor and the other.
TEST(EkfFloatTest, CovarianceStaysSymmetricPositiveDefiniteOverALongRun) {
  const Arena<float> arena = DefaultArena<float>();
  std::mt19937_64 random(52);
  std::normal_distribution<float> range_noise(0.0f, 0.1f);
  std::normal_distribution<float> velocity_noise(0.0f, 0.15f);
  Ekf<float> filter;
  StateVector<float> state;
  state << 3.0f, 2.0f, 0.0f, 0.5f, kPi<float> / 2, 0.0f;
  filter.Reset(state, StateVector<float>::Constant(0.3f));
  constexpr float kDt = 0.01f;
  constexpr float kRadius = 1.0f;
  constexpr float kSpeed = 0.5f;
  int failures = 0;
  for (int step = 1; step <= 13000; ++step) {  // 130 s, ending 10 s after an outage
    const float angle = kSpeed / kRadius * kDt * static_cast<float>(step);
    const float x = 2.0f + kRadius * std::cos(angle);
    const float y = 2.0f + kRadius * std::sin(angle);
    filter.Predict(kDt, ImuInput<float>{0.0f, kSpeed * kSpeed / kRadius, kSpeed / kRadius});
    const bool uwb_out = step % 6000 > 4000;  // 20 s without ranges every 60 s
    const bool flow_out = step % 4500 > 3500;  // 10 s without flow every 45 s
    if (!flow_out && step % 2 == 0) {
      (void)FuseBodyVelocity(filter, BodyVelocity<float>{kSpeed + velocity_noise(random), velocity_noise(random), 0.15f},
                             5.0f);
    }
    if (!uwb_out && step % 10 == 0) {
      for (int i = 0; i < arena.anchor_count; ++i) {
        const Vector3<float> offset(x - arena.anchors[i][0], y - arena.anchors[i][1],
                                    arena.tag_height_m - arena.anchors[i][2]);
        (void)FuseRange(filter, arena.anchors[i], arena.tag_height_m, offset.norm() + range_noise(random), 0.1f, 3.5f);
      }
    }
    const StateCovariance<float>& covariance = filter.covariance();
    if (covariance != covariance.transpose() || Eigen::LLT<StateCovariance<float>>(covariance).info() != Eigen::Success ||
        !filter.state().allFinite()) {
      ++failures;
    }
  }
  EXPECT_EQ(failures, 0);
  EXPECT_LT(std::hypot(filter.state()[kStateX] - (2.0f + kRadius * std::cos(65.0f)),
                       filter.state()[kStateY] - (2.0f + kRadius * std::sin(65.0f))),
            0.2f);
}

}  // namespace
}  // namespace syrof::estimation
