#include "syrof/estimation/range_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "estimation_test_support.h"
#include "syrof/estimation/arena.h"

namespace syrof::estimation {
namespace {

using testing::NumericalJacobian;
using testing::RandomState;

TEST(RangeModelTest, PredictsTheThreeDimensionalDistanceFromTheAntennaPlane) {
  StateVector<double> state = StateVector<double>::Zero();
  state[kStateX] = 3.0;
  state[kStateY] = 4.0;
  EXPECT_DOUBLE_EQ(PredictRange(state, Vector3<double>(0, 0, 0), 0.0), 5.0);
  // 2 m above the antenna plane at 0.1 m: sqrt(9 + 16 + 1.9^2).
  EXPECT_DOUBLE_EQ(PredictRange(state, Vector3<double>(0, 0, 2.0), 0.1), std::sqrt(25.0 + 1.9 * 1.9));
}

TEST(RangeModelTest, JacobianMatchesNumericalDifferentiationForEveryAnchor) {
  const Arena<double> arena = DefaultArena<double>();
  std::mt19937_64 random(21);
  for (int trial = 0; trial < 30; ++trial) {
    const StateVector<double> state = RandomState(random);
    for (int i = 0; i < arena.anchor_count; ++i) {
      const auto range = [&](const StateVector<double>& x) {
        return Eigen::Matrix<double, 1, 1>(PredictRange(x, arena.anchors[i], arena.tag_height_m));
      };
      const auto numerical = NumericalJacobian<1>(range, state);
      EXPECT_LT((RangeJacobian(state, arena.anchors[i], arena.tag_height_m) - numerical).cwiseAbs().maxCoeff(), 1e-8);
    }
  }
}

TEST(RangeModelTest, MeasurementCarriesInnovationVarianceAndSparseJacobian) {
  StateVector<double> state = StateVector<double>::Zero();
  state[kStateX] = 3.0;
  state[kStateY] = 4.0;
  const auto measurement = RangeMeasurement(state, Vector3<double>(0, 0, 0), 0.0, 5.25, 0.1);
  ASSERT_TRUE(measurement.ok());
  EXPECT_DOUBLE_EQ(measurement.value().innovation, 0.25);
  EXPECT_DOUBLE_EQ(measurement.value().variance, 0.01);
  ASSERT_EQ(measurement.value().count, 2);
  EXPECT_EQ(measurement.value().index[0], kStateX);
  EXPECT_EQ(measurement.value().index[1], kStateY);
  EXPECT_DOUBLE_EQ(measurement.value().jacobian[0], 0.6);
  EXPECT_DOUBLE_EQ(measurement.value().jacobian[1], 0.8);
}

TEST(RangeModelTest, RefusesInvalidRangesAndTheAnchorItself) {
  const StateVector<double> at_anchor = StateVector<double>::Zero();
  StateVector<double> away = at_anchor;
  away[kStateX] = 1.0;
  const Vector3<double> anchor(0, 0, 0);
  EXPECT_EQ(RangeMeasurement(away, anchor, 0.0, -0.1, 0.1).error(), EstimationError::kInvalidMeasurement);
  EXPECT_EQ(RangeMeasurement(away, anchor, 0.0, std::nan(""), 0.1).error(), EstimationError::kInvalidMeasurement);
  EXPECT_EQ(RangeMeasurement(away, anchor, 0.0, 1.0, 0.0).error(), EstimationError::kInvalidMeasurement);
  EXPECT_EQ(RangeMeasurement(at_anchor, anchor, 0.0, 1.0, 0.1).error(), EstimationError::kDegenerateGeometry);
}

TEST(FuseRangeTest, PullsThePositionAlongTheLineToTheAnchor) {
  Ekf<double> filter;
  StateVector<double> state = StateVector<double>::Zero();
  state[kStateX] = 2.0;
  state[kStateY] = 1.0;
  filter.Reset(state, StateVector<double>::Constant(0.5));
  const Vector3<double> anchor(0, 1, 0);  // straight along -x
  ASSERT_EQ(FuseRange(filter, anchor, 0.0, 2.5, 0.1, 0.0), EstimationError::kOk);
  EXPECT_GT(filter.state()[kStateX], 2.4);  // moved most of the way to 2.5
  EXPECT_DOUBLE_EQ(filter.state()[kStateY], 1.0);  // across the line: unchanged
  EXPECT_LT(filter.covariance()(kStateX, kStateX), 0.25 / 20);
  EXPECT_DOUBLE_EQ(filter.covariance()(kStateY, kStateY), 0.25);
}

TEST(FuseRangeTest, GateRejectsAnOutlierAndLeavesTheFilterUntouched) {
  Ekf<float> filter;
  StateVector<float> state = StateVector<float>::Zero();
  state[kStateX] = 2.0f;
  state[kStateY] = 2.0f;
  filter.Reset(state, StateVector<float>::Constant(0.05f));
  const Vector3<float> anchor(0, 0, 0);
  const float true_range = std::sqrt(8.0f);
  const StateVector<float> state_before = filter.state();
  const StateCovariance<float> covariance_before = filter.covariance();
  // Innovation variance 0.05^2 + 0.1^2: 1.5 m is about 13 sigma.
  EXPECT_EQ(FuseRange(filter, anchor, 0.0f, true_range + 1.5f, 0.1f, 3.5f), EstimationError::kRejectedByGate);
  EXPECT_EQ(filter.state(), state_before);
  EXPECT_EQ(filter.covariance(), covariance_before);
  EXPECT_GT(filter.last_normalized_innovation_squared(), 3.5f * 3.5f);
  EXPECT_EQ(FuseRange(filter, anchor, 0.0f, true_range + 0.2f, 0.1f, 3.5f), EstimationError::kOk);
}

// Ranges from (x, y) on the antenna plane to every anchor of the default arena.
void ExactRanges(const Arena<double>& arena, double x, double y, double (&ranges)[4]) {
  for (int i = 0; i < 4; ++i) {
    ranges[i] = (Vector3<double>(x, y, arena.tag_height_m) - arena.anchors[i]).norm();
  }
}

TEST(FindInconsistentRangeTest, PointsAtTheOutlierEvenFromAnUncertainPosition) {
  const Arena<double> arena = DefaultArena<double>();
  const std::span<const Vector3<double>> anchors(arena.anchors, 4);
  StateVector<double> state = StateVector<double>::Zero();
  state[kStateX] = 1.6;  // linearized 0.5 m away from the truth at (1.3, 2.6)
  state[kStateY] = 2.2;
  for (int outlier = 0; outlier < 4; ++outlier) {
    double ranges[4];
    ExactRanges(arena, 1.3, 2.6, ranges);
    EXPECT_EQ(FindInconsistentRange<double>(state, anchors, ranges, arena.tag_height_m, 0.1, 3.5), -1);
    ranges[outlier] += 1.0;
    EXPECT_EQ(FindInconsistentRange<double>(state, anchors, ranges, arena.tag_height_m, 0.1, 3.5), outlier);
  }
}

TEST(FindInconsistentRangeTest, NeedsTwoRangesToSpare) {
  const Arena<float> arena = DefaultArena<float>();
  StateVector<float> state = StateVector<float>::Zero();
  state[kStateX] = 2.0f;
  state[kStateY] = 2.0f;
  const float ranges[3] = {1.0f, 5.0f, 1.0f};
  EXPECT_EQ(FindInconsistentRange<float>(state, std::span<const Vector3<float>>(arena.anchors, 3), ranges,
                                         arena.tag_height_m, 0.1f, 3.5f),
            -1);
}

}  // namespace
}  // namespace syrof::estimation
