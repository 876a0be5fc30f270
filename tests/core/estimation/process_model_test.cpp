#include "syrof/estimation/process_model.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "estimation_test_support.h"
#include "syrof/estimation/ekf.h"

namespace syrof::estimation {
namespace {

using testing::NumericalJacobian;
using testing::RandomCovariance;
using testing::RandomState;

ImuInput<double> RandomImu(std::mt19937_64& random) {
  std::uniform_real_distribution<double> accel(-2.0, 2.0);
  std::uniform_real_distribution<double> rate(-3.0, 3.0);
  return ImuInput<double>{accel(random), accel(random), rate(random)};
}

TEST(ProcessModelTest, JacobianMatchesNumericalDifferentiation) {
  std::mt19937_64 random(7);
  for (int trial = 0; trial < 50; ++trial) {
    const StateVector<double> state = RandomState(random);
    const ImuInput<double> imu = RandomImu(random);
    const double dt = 0.01 * (1 + trial % 5);
    const auto propagate = [&](const StateVector<double>& x) {
      StateVector<double> next = PropagateState(x, imu, dt);
      // Compare headings relative to the unperturbed result, so a wrap
      // across pi does not show as a jump of 2 pi.
      next[kStateHeading] = WrapAngle(next[kStateHeading] - PropagateState(state, imu, dt)[kStateHeading]);
      return next;
    };
    const StateCovariance<double> numerical = NumericalJacobian<kStateSize>(propagate, state);
    EXPECT_LT((ProcessJacobian(state, imu, dt) - numerical).cwiseAbs().maxCoeff(), 1e-8) << "trial " << trial;
  }
}

TEST(ProcessModelTest, JacobianWithoutImuMatchesNumericalDifferentiation) {
  std::mt19937_64 random(8);
  const StateVector<double> state = RandomState(random);
  const auto propagate = [](const StateVector<double>& x) { return PropagateState(x, 0.02); };
  EXPECT_LT((ProcessJacobian(0.02) - NumericalJacobian<kStateSize>(propagate, state)).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(ProcessModelTest, IntegratesTheBodyAccelerationInTheArenaFrame) {
  StateVector<double> state;
  state << 1.0, 2.0, 0.5, 0.0, kPi<double> / 2, 0.01;  // facing +y
  const ImuInput<double> imu{1.0, 0.0, 0.01};           // accelerating forward, the gyro reads only its bias
  const StateVector<double> next = PropagateState(state, imu, 0.1);
  EXPECT_NEAR(next[kStateX], 1.05, 1e-12);
  EXPECT_NEAR(next[kStateY], 2.0 + 0.5 * 1.0 * 0.01, 1e-12);  // forward is +y
  EXPECT_NEAR(next[kStateVx], 0.5, 1e-12);
  EXPECT_NEAR(next[kStateVy], 0.1, 1e-12);
  EXPECT_NEAR(next[kStateHeading], kPi<double> / 2, 1e-12);
  EXPECT_EQ(next[kStateGyroBias], 0.01);
}

TEST(ProcessModelTest, TurnsTheAccelerationAtTheHeadingHalfwayThroughTheStep) {
  StateVector<double> state = StateVector<double>::Zero();  // facing +x, at rest
  const ImuInput<double> imu{0.0, 2.0, 1.0};               // pushed left while turning left at 1 rad/s
  const double dt = 0.2;
  const StateVector<double> next = PropagateState(state, imu, dt);
  // Halfway, the heading is 0.1 rad: "left" points at 0.1 + pi/2.
  EXPECT_NEAR(next[kStateVx], 2.0 * std::cos(0.1 + kPi<double> / 2) * dt, 1e-12);
  EXPECT_NEAR(next[kStateVy], 2.0 * std::sin(0.1 + kPi<double> / 2) * dt, 1e-12);
  EXPECT_NEAR(next[kStateHeading], 0.2, 1e-12);
}

TEST(ProcessModelTest, HeadingWrapsAcrossPi) {
  StateVector<double> state = StateVector<double>::Zero();
  state[kStateHeading] = kPi<double> - 0.01;
  const StateVector<double> next = PropagateState(state, ImuInput<double>{0, 0, 1.0}, 0.02);
  EXPECT_NEAR(next[kStateHeading], -kPi<double> + 0.01, 1e-12);
}

TEST(ProcessModelTest, WrapAngleKeepsAnglesInMinusPiToPi) {
  EXPECT_DOUBLE_EQ(WrapAngle(0.5), 0.5);
  EXPECT_NEAR(WrapAngle(kPi<double> + 0.5), -kPi<double> + 0.5, 1e-12);
  EXPECT_NEAR(WrapAngle(-kPi<double> - 0.5), kPi<double> - 0.5, 1e-12);
  EXPECT_NEAR(WrapAngle(7 * kPi<double> + 0.25), -kPi<double> + 0.25, 1e-9);
  EXPECT_NEAR(WrapAngle(3.5f), 3.5f - 2 * kPi<float>, 1e-6f);
}

TEST(ProcessModelTest, NoiseCovarianceIsSymmetricPositiveSemidefinite) {
  const ProcessNoise<double> noise;
  for (const bool with_imu : {true, false}) {
    const StateCovariance<double> q = ProcessNoiseCovariance(noise, 0.01, with_imu);
    EXPECT_EQ(q, q.transpose());
    const Eigen::SelfAdjointEigenSolver<StateCovariance<double>> eigen(q);
    EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-18);
  }
}

// The filter's structured prediction against the dense reference
// P' = F P F^T + Q, in both scalars.
template <typename Scalar>
void ExpectStructuredPredictionMatchesDense(double tolerance) {
  std::mt19937_64 random(11);
  for (int trial = 0; trial < 20; ++trial) {
    const StateVector<double> state = RandomState(random);
    const StateCovariance<double> covariance = RandomCovariance(random);
    const ImuInput<double> imu = RandomImu(random);
    const bool with_imu = trial % 4 != 3;
    const double dt = 0.01;

    Ekf<Scalar> filter;
    filter.ResetWithCovariance(state.cast<Scalar>(), covariance.cast<Scalar>());
    const ImuInput<Scalar> imu_scalar{static_cast<Scalar>(imu.accel_forward_mps2),
                                      static_cast<Scalar>(imu.accel_left_mps2),
                                      static_cast<Scalar>(imu.yaw_rate_radps)};
    if (with_imu) {
      filter.Predict(static_cast<Scalar>(dt), imu_scalar);
    } else {
      filter.PredictWithoutImu(static_cast<Scalar>(dt));
    }

    const StateCovariance<double> jacobian = with_imu ? ProcessJacobian(state, imu, dt) : ProcessJacobian(dt);
    const StateCovariance<double> expected_covariance =
        jacobian * covariance * jacobian.transpose() + ProcessNoiseCovariance(ProcessNoise<double>{}, dt, with_imu);
    const StateVector<double> expected_state = with_imu ? PropagateState(state, imu, dt) : PropagateState(state, dt);
    EXPECT_LT((filter.covariance().template cast<double>() - expected_covariance).cwiseAbs().maxCoeff(), tolerance);
    EXPECT_LT((filter.state().template cast<double>() - expected_state).cwiseAbs().maxCoeff(), tolerance);
    EXPECT_EQ(filter.covariance(), filter.covariance().transpose());
  }
}

TEST(EkfPredictTest, StructuredPredictionMatchesDenseFPFtPlusQInDouble) {
  ExpectStructuredPredictionMatchesDense<double>(1e-14);
}

TEST(EkfPredictTest, StructuredPredictionMatchesDenseFPFtPlusQInFloat) {
  ExpectStructuredPredictionMatchesDense<float>(1e-5);
}

TEST(EkfPredictTest, IgnoresNonPositiveOrNonFiniteSteps) {
  Ekf<float> filter;
  StateVector<float> state;
  state << 1, 1, 0.5f, 0, 0, 0;
  filter.Reset(state, StateVector<float>::Constant(0.1f));
  const StateCovariance<float> before = filter.covariance();
  filter.Predict(0.0f, ImuInput<float>{});
  filter.Predict(-0.01f, ImuInput<float>{});
  filter.Predict(std::nanf(""), ImuInput<float>{});
  filter.PredictWithoutImu(0.0f);
  EXPECT_EQ(filter.state(), state);
  EXPECT_EQ(filter.covariance(), before);
}

TEST(EkfPredictTest, NonFiniteImuFallsBackToConstantVelocity) {
  Ekf<double> with_nan;
  Ekf<double> without_imu;
  StateVector<double> state;
  state << 1, 1, 0.5, 0.2, 0.3, 0;
  with_nan.Reset(state, StateVector<double>::Constant(0.1));
  without_imu.Reset(state, StateVector<double>::Constant(0.1));
  with_nan.Predict(0.01, ImuInput<double>{std::nan(""), 0, 0});
  without_imu.PredictWithoutImu(0.01);
  EXPECT_EQ(with_nan.state(), without_imu.state());
  EXPECT_EQ(with_nan.covariance(), without_imu.covariance());
}

TEST(EkfPredictTest, VarianceCeilingKeepsCovariancePositiveDefinite) {
  Ekf<float> filter;
  filter.Reset(StateVector<float>::Zero(), StateVector<float>::Constant(0.1f));
  for (int step = 0; step < 20000; ++step) filter.PredictWithoutImu(0.1f);  // 2000 s blind
  const StateCovariance<float>& covariance = filter.covariance();
  for (int i = 0; i < kStateSize; ++i) EXPECT_LE(covariance(i, i), filter.params().max_variance[i] * 1.0001f);
  EXPECT_EQ(covariance, covariance.transpose());
  EXPECT_EQ(Eigen::LLT<StateCovariance<double>>(covariance.cast<double>()).info(), Eigen::Success);
}

}  // namespace
}  // namespace syrof::estimation
