#include "syrof/estimation/flow_model.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>

#include "estimation_test_support.h"

namespace syrof::estimation {
namespace {

using testing::NumericalJacobian;
using testing::RandomCovariance;
using testing::RandomState;

constexpr double kDegree = kPi<double> / 180;

TEST(FlowGeometryTest, BetaIsHalfTheRestOfTheViewMinusTheMountingAngle) {
  const FlowGeometry<double> level{25 * kDegree, 30, 0.1, 0};
  EXPECT_NEAR(FlowBeta(level), 77.5 * kDegree, 1e-12);
  const FlowGeometry<double> tilted{25 * kDegree, 30, 0.1, 5 * kDegree};
  EXPECT_NEAR(FlowBeta(tilted), 72.5 * kDegree, 1e-12);
}

TEST(FlowGeometryTest, LevelSensorSeesTwiceHTanHalfTheViewOverThirtyPixels) {
  const FlowGeometry<double> level{25 * kDegree, 30, 0.1, 0};
  EXPECT_NEAR(FlowFarEdgeDistance(level), 0.1 * std::tan(12.5 * kDegree), 1e-15);
  EXPECT_NEAR(FlowNearEdgeDistance(level), -0.1 * std::tan(12.5 * kDegree), 1e-15);
  // (h cot(beta) - a) / 30 = 2 h tan(12.5 deg) / 30 = 1.4779 mm per pixel.
  EXPECT_NEAR(FlowMetresPerPixel(level), 2 * 0.1 * std::tan(12.5 * kDegree) / 30, 1e-15);
  EXPECT_NEAR(FlowMetresPerPixel(level), 1.4779e-3, 1e-7);
}

TEST(FlowGeometryTest, TiltStretchesTheFootprint) {
  const FlowGeometry<double> tilted{25 * kDegree, 30, 0.1, 5 * kDegree};
  EXPECT_NEAR(FlowFarEdgeDistance(tilted), 0.1 * std::tan(17.5 * kDegree), 1e-15);
  EXPECT_NEAR(FlowNearEdgeDistance(tilted), -0.1 * std::tan(7.5 * kDegree), 1e-15);
  EXPECT_GT(FlowMetresPerPixel(tilted), FlowMetresPerPixel(FlowGeometry<double>{25 * kDegree, 30, 0.1, 0}));
}

TEST(FlowToBodyVelocityTest, ScalesPixelsOverTheInterval) {
  const FlowGeometry<double> geometry{};
  const FlowReading reading{0, 20'000'000, 10, -4};
  const auto velocity = FlowToBodyVelocity(reading, geometry, 2.0);
  ASSERT_TRUE(velocity.ok());
  const double scale = FlowMetresPerPixel(geometry) / 0.02;
  EXPECT_NEAR(velocity.value().forward_mps, 10 * scale, 1e-12);
  EXPECT_NEAR(velocity.value().left_mps, -4 * scale, 1e-12);
  EXPECT_NEAR(velocity.value().sigma_mps, 2 * scale, 1e-12);
}

TEST(FlowToBodyVelocityTest, RefusesEmptyIntervalsBadNoiseAndViewsThatMissTheFloor) {
  const FlowGeometry<float> geometry{};
  EXPECT_EQ(FlowToBodyVelocity(FlowReading{0, 0, 1, 1}, geometry, 2.0f).error(), EstimationError::kInvalidMeasurement);
  EXPECT_EQ(FlowToBodyVelocity(FlowReading{0, 20'000'000, 1, 1}, geometry, 0.0f).error(),
            EstimationError::kInvalidMeasurement);
  FlowGeometry<float> tipped = geometry;
  tipped.mounting_angle_rad = 80.0f * kPi<float> / 180;  // beta < 0: the far ray points above the horizon
  EXPECT_EQ(FlowToBodyVelocity(FlowReading{0, 20'000'000, 1, 1}, tipped, 2.0f).error(),
            EstimationError::kInvalidMeasurement);
  EXPECT_EQ(FlowToBodyVelocity(FlowReading{0, 20'000'000, 1, 1}, -1.0f, 2.0f).error(),
            EstimationError::kInvalidMeasurement);
}

TEST(FlowModelTest, PredictsTheVelocityInTheBodyFrame) {
  StateVector<double> state = StateVector<double>::Zero();
  state[kStateVx] = 0.0;
  state[kStateVy] = 0.5;
  state[kStateHeading] = kPi<double> / 2;  // facing +y: moving forward
  const Vector2<double> body = PredictBodyVelocity(state);
  EXPECT_NEAR(body[0], 0.5, 1e-15);
  EXPECT_NEAR(body[1], 0.0, 1e-15);
  state[kStateHeading] = 0;  // facing +x: the motion is to the left
  EXPECT_NEAR(PredictBodyVelocity(state)[1], 0.5, 1e-15);
}

TEST(FlowModelTest, JacobianMatchesNumericalDifferentiation) {
  std::mt19937_64 random(31);
  for (int trial = 0; trial < 50; ++trial) {
    const StateVector<double> state = RandomState(random);
    const auto predict = [](const StateVector<double>& x) { return PredictBodyVelocity(x); };
    EXPECT_LT((BodyVelocityJacobian(state) - NumericalJacobian<2>(predict, state)).cwiseAbs().maxCoeff(), 1e-8);
  }
}

// The pair of scalar updates is the EKF's joint two-dimensional update:
// K = P H^T (H P H^T + R)^-1, both rows linearized at the prior.
TEST(FuseBodyVelocityTest, EqualsTheJointTwoDimensionalUpdate) {
  std::mt19937_64 random(32);
  for (int trial = 0; trial < 20; ++trial) {
    const StateVector<double> prior = RandomState(random);
    const StateCovariance<double> covariance = RandomCovariance(random);
    const BodyVelocity<double> velocity{0.3, -0.1, 0.15};

    Ekf<double> filter;
    filter.ResetWithCovariance(prior, covariance);
    ASSERT_EQ(FuseBodyVelocity(filter, velocity, 0.0), EstimationError::kOk);

    const Eigen::Matrix<double, 2, kStateSize> h = BodyVelocityJacobian(prior);
    const Eigen::Matrix2d r = Eigen::Matrix2d::Identity() * velocity.sigma_mps * velocity.sigma_mps;
    const Eigen::Matrix<double, kStateSize, 2> gain =
        covariance * h.transpose() * (h * covariance * h.transpose() + r).inverse();
    const Vector2<double> innovation = Vector2<double>(velocity.forward_mps, velocity.left_mps) - PredictBodyVelocity(prior);
    StateVector<double> expected_state = prior + gain * innovation;
    expected_state[kStateHeading] = WrapAngle(expected_state[kStateHeading]);
    const StateCovariance<double> expected_covariance =
        (StateCovariance<double>::Identity() - gain * h) * covariance;
    EXPECT_LT((filter.state() - expected_state).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
    EXPECT_LT((filter.covariance() - expected_covariance).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
  }
}

// Below the minimum speed the heading's row and column are untouched (its
// correlations with the velocity may still move it, so the prior here has
// none); above it, the same reading turns the heading.
TEST(FuseBodyVelocityTest, ANearlyStillRobotLearnsNothingOfItsHeading) {
  StateVector<double> prior;
  prior << 1, 1, 0.03, -0.02, 0.4, 0.001;  // 3.6 cm/s of velocity noise at rest
  StateVector<double> sigma;
  sigma << 0.05, 0.05, 0.05, 0.05, 0.3, 0.005;
  const BodyVelocity<double> still{0.02, -0.01, 0.03};  // a noisy reading at rest

  Ekf<double> slow;
  slow.Reset(prior, sigma);
  ASSERT_EQ(FuseBodyVelocity(slow, still, 0.0, 0.1), EstimationError::kOk);
  EXPECT_EQ(slow.state()[kStateHeading], prior[kStateHeading]);
  EXPECT_EQ(slow.covariance()(kStateHeading, kStateHeading), sigma[kStateHeading] * sigma[kStateHeading]);
  EXPECT_LT(std::hypot(slow.state()[kStateVx], slow.state()[kStateVy]), 0.036);  // the velocity is still corrected

  Ekf<double> full;
  full.Reset(prior, sigma);
  ASSERT_EQ(FuseBodyVelocity(full, still, 0.0), EstimationError::kOk);  // 0: the full Jacobian always
  EXPECT_NE(full.state()[kStateHeading], prior[kStateHeading]);
  EXPECT_LT(full.covariance()(kStateHeading, kStateHeading), sigma[kStateHeading] * sigma[kStateHeading]);
}

TEST(FuseBodyVelocityTest, RefusesInvalidVelocities) {
  Ekf<float> filter;
  EXPECT_EQ(FuseBodyVelocity(filter, BodyVelocity<float>{std::nanf(""), 0, 0.1f}, 0.0f),
            EstimationError::kInvalidMeasurement);
  EXPECT_EQ(FuseBodyVelocity(filter, BodyVelocity<float>{0, 0, 0}, 0.0f), EstimationError::kInvalidMeasurement);
}

}  // namespace
}  // namespace syrof::estimation
