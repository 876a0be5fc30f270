#include "syrof/estimation/ekf.h"

#include <cmath>

namespace syrof::estimation {
namespace {

template <typename Scalar>
bool IsFinite(Scalar value) {
  return std::isfinite(value);
}

}  // namespace

template <typename Scalar>
Ekf<Scalar>::Ekf(const EkfParams<Scalar>& params)
    : params_(params), state_(StateVector<Scalar>::Zero()), covariance_(StateCovariance<Scalar>::Identity()) {}

template <typename Scalar>
void Ekf<Scalar>::Reset(const StateVector<Scalar>& state, const StateVector<Scalar>& sigma) {
  state_ = state;
  state_[kStateHeading] = WrapAngle(state_[kStateHeading]);
  covariance_ = sigma.cwiseProduct(sigma).asDiagonal();
  last_innovation_squared_ = 0;
  last_innovation_variance_ = 1;
}

template <typename Scalar>
void Ekf<Scalar>::ResetWithCovariance(const StateVector<Scalar>& state, const StateCovariance<Scalar>& covariance) {
  state_ = state;
  state_[kStateHeading] = WrapAngle(state_[kStateHeading]);
  covariance_ = covariance;
  last_innovation_squared_ = 0;
  last_innovation_variance_ = 1;
}

template <typename Scalar>
void Ekf<Scalar>::Predict(Scalar dt_s, const ImuInput<Scalar>& imu) {
  if (!(dt_s > 0) || !IsFinite(dt_s)) return;
  if (!IsFinite(imu.accel_forward_mps2) || !IsFinite(imu.accel_left_mps2) || !IsFinite(imu.yaw_rate_radps)) {
    PredictWithoutImu(dt_s);
    return;
  }
  StateVector<Scalar>& s = state_;
  const Scalar turn = (imu.yaw_rate_radps - s[kStateGyroBias]) * dt_s;
  // Midpoint rule (process_model.h): the heading halfway through the step.
  const Scalar mid_heading = s[kStateHeading] + turn / 2;
  const Scalar cos_heading = std::cos(mid_heading);
  const Scalar sin_heading = std::sin(mid_heading);
  const Scalar accel_x = cos_heading * imu.accel_forward_mps2 - sin_heading * imu.accel_left_mps2;
  const Scalar accel_y = sin_heading * imu.accel_forward_mps2 + cos_heading * imu.accel_left_mps2;
  const Scalar half_dt2 = dt_s * dt_s / 2;
  // Non-identity entries of F in the heading column (ProcessJacobian); the
  // bias column holds the same times -dt/2 in these rows.
  const Scalar jacobian_heading[4] = {-accel_y * half_dt2, accel_x * half_dt2, -accel_y * dt_s, accel_x * dt_s};
  PropagateCovariance(jacobian_heading, -dt_s, dt_s, /*with_imu=*/true);

  s[kStateX] += s[kStateVx] * dt_s + accel_x * half_dt2;
  s[kStateY] += s[kStateVy] * dt_s + accel_y * half_dt2;
  s[kStateVx] += accel_x * dt_s;
  s[kStateVy] += accel_y * dt_s;
  s[kStateHeading] = WrapAngle<Scalar>(s[kStateHeading] + turn);
}

template <typename Scalar>
void Ekf<Scalar>::PredictWithoutImu(Scalar dt_s) {
  if (!(dt_s > 0) || !IsFinite(dt_s)) return;
  const Scalar no_heading_terms[4] = {0, 0, 0, 0};
  PropagateCovariance(no_heading_terms, 0, dt_s, /*with_imu=*/false);
  state_[kStateX] += state_[kStateVx] * dt_s;
  state_[kStateY] += state_[kStateVy] * dt_s;
}

// P = F P F^T + Q with F = I + E, where E has the entries
//   E(x, vx) = E(y, vy) = dt, E(x..vy, heading) = jacobian_heading[0..3],
//   E(x..vy, bias) = jacobian_heading[0..3] * bias_to_heading / 2,
//   E(heading, bias) = bias_to_heading (= -dt; 0 without the IMU).
// The heading and bias columns of rows x..vy are proportional, so they enter
// through one combined row w = P(heading) + (bias_to_heading / 2) P(bias).
// First A = F P row by row (each row of F mixes at most three rows of P and
// w), then the upper triangle of A F^T column by column, mirrored below.
// About 150 multiply-adds instead of the 432 of two dense 6x6 products.
template <typename Scalar>
void Ekf<Scalar>::PropagateCovariance(const Scalar (&jacobian_heading)[4], Scalar bias_to_heading, Scalar dt_s,
                                      bool with_imu) {
  constexpr int n = kStateSize;
  StateCovariance<Scalar>& p = covariance_;
  const Scalar half_bias = bias_to_heading / 2;
  Scalar a[n][n];
  for (int k = 0; k < n; ++k) {
    const Scalar p_heading = p(kStateHeading, k);
    const Scalar p_bias = p(kStateGyroBias, k);
    const Scalar w = p_heading + half_bias * p_bias;
    a[kStateX][k] = p(kStateX, k) + dt_s * p(kStateVx, k) + jacobian_heading[0] * w;
    a[kStateY][k] = p(kStateY, k) + dt_s * p(kStateVy, k) + jacobian_heading[1] * w;
    a[kStateVx][k] = p(kStateVx, k) + jacobian_heading[2] * w;
    a[kStateVy][k] = p(kStateVy, k) + jacobian_heading[3] * w;
    a[kStateHeading][k] = p_heading + bias_to_heading * p_bias;
    a[kStateGyroBias][k] = p_bias;
  }
  for (int i = 0; i < n; ++i) {
    const Scalar* row = a[i];
    const Scalar w = row[kStateHeading] + half_bias * row[kStateGyroBias];
    // Column j of F^T is row j of F.
    if (i <= kStateX) p(i, kStateX) = row[kStateX] + dt_s * row[kStateVx] + jacobian_heading[0] * w;
    if (i <= kStateY) p(i, kStateY) = row[kStateY] + dt_s * row[kStateVy] + jacobian_heading[1] * w;
    if (i <= kStateVx) p(i, kStateVx) = row[kStateVx] + jacobian_heading[2] * w;
    if (i <= kStateVy) p(i, kStateVy) = row[kStateVy] + jacobian_heading[3] * w;
    if (i <= kStateHeading) p(i, kStateHeading) = row[kStateHeading] + bias_to_heading * row[kStateGyroBias];
    p(i, kStateGyroBias) = row[kStateGyroBias];
  }

  // Q, added in place (the upper triangle; mirrored below).
  const ProcessNoiseTerms<Scalar> q = ProcessNoiseEntries(params_.process_noise, dt_s, with_imu);
  p(kStateX, kStateX) += q.position;
  p(kStateY, kStateY) += q.position;
  p(kStateX, kStateVx) += q.position_velocity;
  p(kStateY, kStateVy) += q.position_velocity;
  p(kStateVx, kStateVx) += q.velocity;
  p(kStateVy, kStateVy) += q.velocity;
  p(kStateHeading, kStateHeading) += q.heading;
  p(kStateHeading, kStateGyroBias) += q.heading_bias;
  p(kStateGyroBias, kStateGyroBias) += q.bias;

  for (int i = 1; i < n; ++i) {
    for (int j = 0; j < i; ++j) p(i, j) = p(j, i);
  }
  ApplyVarianceCeiling();
}

template <typename Scalar>
void Ekf<Scalar>::ApplyVarianceCeiling() {
  constexpr int n = kStateSize;
  for (int i = 0; i < n; ++i) {
    const Scalar variance = covariance_(i, i);
    const Scalar ceiling = params_.max_variance[i];
    if (!(variance > ceiling)) continue;
    // D P D with D = diag(1, .., scale, .., 1) is positive definite whenever
    // P is; clamping the diagonal alone would not be.
    const Scalar scale = std::sqrt(ceiling / variance);
    for (int k = 0; k < n; ++k) {
      covariance_(i, k) *= scale;
      covariance_(k, i) *= scale;
    }
    covariance_(i, i) = ceiling;
  }
}

template <typename Scalar>
EstimationError Ekf<Scalar>::Update(const ScalarMeasurement<Scalar>& measurement, Scalar gate_sigma) {
  constexpr int n = kStateSize;
  const int count = measurement.count;
  if (count < 1 || count > ScalarMeasurement<Scalar>::kMaxNonZeros) return EstimationError::kInvalidMeasurement;
  if (!IsFinite(measurement.innovation) || !IsFinite(measurement.variance) || !(measurement.variance > 0)) {
    return EstimationError::kInvalidMeasurement;
  }
  for (int m = 0; m < count; ++m) {
    const int index = measurement.index[m];
    if (index < 0 || index >= n || !IsFinite(measurement.jacobian[m])) return EstimationError::kInvalidMeasurement;
    for (int other = 0; other < m; ++other) {
      if (measurement.index[other] == index) return EstimationError::kInvalidMeasurement;
    }
  }

  StateCovariance<Scalar>& p = covariance_;
  // b = P H^T, touching only H's non-zero columns.
  // (Sums start from their first term: in software floating point every
  // addition of a zero costs as much as any other.)
  Scalar b[n];
  for (int i = 0; i < n; ++i) {
    Scalar sum = p(i, measurement.index[0]) * measurement.jacobian[0];
    for (int m = 1; m < count; ++m) sum += p(i, measurement.index[m]) * measurement.jacobian[m];
    b[i] = sum;
  }
  Scalar predicted_variance = measurement.jacobian[0] * b[measurement.index[0]];  // H P H^T
  for (int m = 1; m < count; ++m) predicted_variance += measurement.jacobian[m] * b[measurement.index[m]];
  const Scalar innovation_variance = predicted_variance + measurement.variance;
  if (!(innovation_variance > 0) || !IsFinite(innovation_variance)) return EstimationError::kNumericalFailure;

  const Scalar innovation = measurement.innovation;
  const Scalar innovation_squared = innovation * innovation;
  last_innovation_squared_ = innovation_squared;
  last_innovation_variance_ = innovation_variance;
  if (gate_sigma > 0 && innovation_squared > gate_sigma * gate_sigma * innovation_variance) {
    return EstimationError::kRejectedByGate;
  }

  const Scalar inverse_variance = 1 / innovation_variance;
  Scalar gain[n];
  Scalar residual[n];  // b - S K: zero in exact arithmetic, the gain's rounding otherwise
  for (int i = 0; i < n; ++i) {
    gain[i] = b[i] * inverse_variance;
    residual[i] = b[i] - innovation_variance * gain[i];
    state_[i] += gain[i] * innovation;
  }
  state_[kStateHeading] = WrapAngle(state_[kStateHeading]);

  // Joseph form, P' = (I - K H) P (I - K H)^T + K R K^T, expanded for a
  // scalar measurement: P' = P - K b^T - b K^T + S K K^T, whose (i, j) entry
  // is P_ij - b_i K_j - K_i (b_j - S K_j). Computed on the upper triangle and
  // mirrored, so P' is symmetric by construction; as a Joseph form its error
  // is second order in any error of K.
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j) {
      const Scalar value = p(i, j) - (b[i] * gain[j] + gain[i] * residual[j]);
      p(i, j) = value;
      p(j, i) = value;
    }
  }
  return EstimationError::kOk;
}

template <typename Scalar>
void Ekf<Scalar>::InflatePositionVariance(Scalar variance_m2) {
  if (!(variance_m2 > 0) || !IsFinite(variance_m2)) return;
  covariance_(kStateX, kStateX) += variance_m2;
  covariance_(kStateY, kStateY) += variance_m2;
  ApplyVarianceCeiling();
}

template <typename Scalar>
void Ekf<Scalar>::ResetPosition(Scalar x_m, Scalar y_m, Scalar sigma_m) {
  if (!IsFinite(x_m) || !IsFinite(y_m) || !(sigma_m > 0) || !IsFinite(sigma_m)) return;
  state_[kStateX] = x_m;
  state_[kStateY] = y_m;
  // Block diagonal with positive definite blocks: still positive definite.
  for (int k = 0; k < kStateSize; ++k) {
    for (const int position : {static_cast<int>(kStateX), static_cast<int>(kStateY)}) {
      covariance_(position, k) = 0;
      covariance_(k, position) = 0;
    }
  }
  covariance_(kStateX, kStateX) = sigma_m * sigma_m;
  covariance_(kStateY, kStateY) = sigma_m * sigma_m;
}

template class Ekf<float>;
template class Ekf<double>;

}  // namespace syrof::estimation
