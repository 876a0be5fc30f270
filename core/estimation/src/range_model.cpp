#include "syrof/estimation/range_model.h"

#include <cmath>

namespace syrof::estimation {
namespace {

// Below this predicted range the direction to the anchor is meaningless.
template <typename Scalar>
constexpr Scalar kMinPredictedRangeM = static_cast<Scalar>(1e-3);

}  // namespace

template <typename Scalar>
Scalar PredictRange(const StateVector<Scalar>& state, const Vector3<Scalar>& anchor, Scalar tag_height_m) {
  const Scalar dx = state[kStateX] - anchor[0];
  const Scalar dy = state[kStateY] - anchor[1];
  const Scalar dz = tag_height_m - anchor[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

template <typename Scalar>
Eigen::Matrix<Scalar, 1, kStateSize> RangeJacobian(const StateVector<Scalar>& state, const Vector3<Scalar>& anchor,
                                                   Scalar tag_height_m) {
  Eigen::Matrix<Scalar, 1, kStateSize> jacobian = Eigen::Matrix<Scalar, 1, kStateSize>::Zero();
  const Scalar range = PredictRange(state, anchor, tag_height_m);
  if (range > 0) {
    jacobian(0, kStateX) = (state[kStateX] - anchor[0]) / range;
    jacobian(0, kStateY) = (state[kStateY] - anchor[1]) / range;
  }
  return jacobian;
}

template <typename Scalar>
base::Result<ScalarMeasurement<Scalar>, EstimationError> RangeMeasurement(const StateVector<Scalar>& state,
                                                                          const Vector3<Scalar>& anchor,
                                                                          Scalar tag_height_m, Scalar range_m,
                                                                          Scalar sigma_m) {
  if (!std::isfinite(range_m) || range_m < 0 || !(sigma_m > 0) || !std::isfinite(sigma_m)) {
    return EstimationError::kInvalidMeasurement;
  }
  const Scalar dx = state[kStateX] - anchor[0];
  const Scalar dy = state[kStateY] - anchor[1];
  const Scalar dz = tag_height_m - anchor[2];
  const Scalar predicted = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (!(predicted >= kMinPredictedRangeM<Scalar>)) return EstimationError::kDegenerateGeometry;
  ScalarMeasurement<Scalar> measurement;
  measurement.innovation = range_m - predicted;
  measurement.variance = sigma_m * sigma_m;
  measurement.count = 2;
  measurement.index[0] = kStateX;
  measurement.index[1] = kStateY;
  const Scalar inverse_range = 1 / predicted;
  measurement.jacobian[0] = dx * inverse_range;
  measurement.jacobian[1] = dy * inverse_range;
  return measurement;
}

template <typename Scalar>
EstimationError FuseRange(Ekf<Scalar>& filter, const Vector3<Scalar>& anchor, Scalar tag_height_m, Scalar range_m,
                          Scalar sigma_m, Scalar gate_sigma) {
  const auto measurement = RangeMeasurement(filter.state(), anchor, tag_height_m, range_m, sigma_m);
  if (!measurement.ok()) return measurement.error();
  return filter.Update(measurement.value(), gate_sigma);
}

template <typename Scalar>
int FindInconsistentRange(const StateVector<Scalar>& state, std::span<const Vector3<Scalar>> anchors,
                          std::span<const Scalar> ranges_m, Scalar tag_height_m, Scalar sigma_m,
                          Scalar threshold_sigma) {
  constexpr int kMaxRanges = 16;
  const size_t count = anchors.size();
  if (count < 4 || count > kMaxRanges || ranges_m.size() != count || !(sigma_m > 0)) return -1;
  Scalar jacobian[kMaxRanges][2];
  Scalar innovation[kMaxRanges];
  // Normal equations of the offset: N = sum H_i^T H_i, g = sum H_i^T nu_i.
  Scalar n_xx = 0;
  Scalar n_xy = 0;
  Scalar n_yy = 0;
  Scalar g_x = 0;
  Scalar g_y = 0;
  for (size_t i = 0; i < count; ++i) {
    const auto measurement = RangeMeasurement(state, anchors[i], tag_height_m, ranges_m[i], sigma_m);
    if (!measurement) return -1;
    jacobian[i][0] = measurement.value().jacobian[0];
    jacobian[i][1] = measurement.value().jacobian[1];
    innovation[i] = measurement.value().innovation;
    n_xx += jacobian[i][0] * jacobian[i][0];
    n_xy += jacobian[i][0] * jacobian[i][1];
    n_yy += jacobian[i][1] * jacobian[i][1];
    g_x += jacobian[i][0] * innovation[i];
    g_y += jacobian[i][1] * innovation[i];
  }
  const Scalar determinant = n_xx * n_yy - n_xy * n_xy;
  const Scalar trace = n_xx + n_yy;
  if (!(determinant > static_cast<Scalar>(1e-3) * trace * trace)) return -1;  // anchors nearly in a line
  const Scalar inverse_xx = n_yy / determinant;
  const Scalar inverse_xy = -n_xy / determinant;
  const Scalar inverse_yy = n_xx / determinant;
  const Scalar offset_x = inverse_xx * g_x + inverse_xy * g_y;
  const Scalar offset_y = inverse_xy * g_x + inverse_yy * g_y;

  int worst = -1;
  Scalar worst_statistic = threshold_sigma * threshold_sigma * sigma_m * sigma_m;
  for (size_t i = 0; i < count; ++i) {
    const Scalar hx = jacobian[i][0];
    const Scalar hy = jacobian[i][1];
    const Scalar residual = innovation[i] - (hx * offset_x + hy * offset_y);
    const Scalar leverage = hx * (inverse_xx * hx + inverse_xy * hy) + hy * (inverse_xy * hx + inverse_yy * hy);
    const Scalar redundancy = 1 - leverage;
    if (!(redundancy > static_cast<Scalar>(0.05))) continue;  // this range alone fixes a direction
    // Standardized residual squared, times sigma^2.
    const Scalar statistic = residual * residual / redundancy;
    if (statistic > worst_statistic) {
      worst_statistic = statistic;
      worst = static_cast<int>(i);
    }
  }
  return worst;
}

#define SYROF_INSTANTIATE_RANGE_MODEL(Scalar)                                                                   \
  template Scalar PredictRange<Scalar>(const StateVector<Scalar>&, const Vector3<Scalar>&, Scalar);             \
  template Eigen::Matrix<Scalar, 1, kStateSize> RangeJacobian<Scalar>(const StateVector<Scalar>&,               \
                                                                      const Vector3<Scalar>&, Scalar);          \
  template base::Result<ScalarMeasurement<Scalar>, EstimationError> RangeMeasurement<Scalar>(                    \
      const StateVector<Scalar>&, const Vector3<Scalar>&, Scalar, Scalar, Scalar);                              \
  template EstimationError FuseRange<Scalar>(Ekf<Scalar>&, const Vector3<Scalar>&, Scalar, Scalar, Scalar, Scalar); \
  template int FindInconsistentRange<Scalar>(const StateVector<Scalar>&, std::span<const Vector3<Scalar>>,     \
                                             std::span<const Scalar>, Scalar, Scalar, Scalar);

SYROF_INSTANTIATE_RANGE_MODEL(float)
SYROF_INSTANTIATE_RANGE_MODEL(double)

}  // namespace syrof::estimation
