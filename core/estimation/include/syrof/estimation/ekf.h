// The extended Kalman filter over (x, y, vx, vy, heading, gyro bias): pure
// math on explicit state, no OS, broker or clock. The tasks that feed it live
// in estimator.h; the measurement models that call Update() live one per file
// (range_model.h, flow_model.h), like the Crazyflie's kalman_core and mm_*.
//
// Every measurement is folded in as a scalar: one range, one flow axis. A
// sensor's readings are fused when they arrive, whatever the other sensors'
// rates, and no matrix is ever inverted. The covariance update is the Joseph
// form, written for a scalar measurement with a sparse Jacobian so that it is
// symmetric by construction and insensitive to rounding in the gain (see
// docs/estimation.md for the derivation). Each call does a fixed amount of
// work and allocates nothing.
//
// Templated on the scalar: the Teensy runs Ekf<float> in software floating
// point; the host may use Ekf<double>. Both are compiled in the library.
#pragma once

#include <cstdint>

#include "syrof/estimation/estimation_error.h"
#include "syrof/estimation/process_model.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// The filter's tuning, fixed at construction.
template <typename Scalar>
struct EkfParams {
  ProcessNoise<Scalar> process_noise{};
  /// Ceiling on each variance (diagonal of P), reached only after a long
  /// time without a sensor. A variance above its ceiling is scaled down
  /// together with its row and column, which keeps P positive definite.
  /// Position 100 m^2, velocity 100 (m/s)^2, heading pi^2, bias 1 (rad/s)^2.
  StateVector<Scalar> max_variance =
      (StateVector<Scalar>() << 100, 100, 100, 100, kPi<Scalar> * kPi<Scalar>, 1).finished();
};

/// One scalar measurement, linearized: z - h(x) and the non-zero entries of
/// its Jacobian H (a row, at most kMaxNonZeros entries).
template <typename Scalar>
struct ScalarMeasurement {
  static constexpr int kMaxNonZeros = 3;
  Scalar innovation = 0;  ///< z - h(x), in the measurement's unit
  Scalar variance = 0;    ///< R, the measurement noise variance, > 0
  int count = 0;          ///< number of non-zero entries of H, 1 .. kMaxNonZeros
  int index[kMaxNonZeros] = {};         ///< their state indices (StateIndex), distinct
  Scalar jacobian[kMaxNonZeros] = {};  ///< their values, d h / d state[index]
};

template <typename Scalar>
class Ekf {
 public:
  explicit Ekf(const EkfParams<Scalar>& params = {});

  /// Sets the state and a diagonal covariance (standard deviations in
  /// `sigma`, each > 0). The heading is wrapped into [-pi, pi].
  void Reset(const StateVector<Scalar>& state, const StateVector<Scalar>& sigma);

  /// Sets the state and a full covariance, which the caller guarantees to be
  /// symmetric positive definite.
  void ResetWithCovariance(const StateVector<Scalar>& state, const StateCovariance<Scalar>& covariance);

  /// Moves the state dt seconds forward under the IMU's body acceleration
  /// and yaw rate (process_model.h), and the covariance with it:
  /// P = F P F^T + Q, computed from F's sparsity (about 130 multiply-adds).
  /// dt <= 0 or not finite does nothing.
  void Predict(Scalar dt_s, const ImuInput<Scalar>& imu);

  /// The same without IMU data (constant velocity and heading, larger noise).
  void PredictWithoutImu(Scalar dt_s);

  /// Folds in one scalar measurement. With gate_sigma > 0, a measurement
  /// whose innovation exceeds gate_sigma standard deviations of its
  /// predicted spread (innovation^2 > gate_sigma^2 * (H P H^T + R)) is
  /// rejected with kRejectedByGate and changes nothing. Also kInvalidMeasurement
  /// (non-finite input, R <= 0, bad indices) and kNumericalFailure.
  EstimationError Update(const ScalarMeasurement<Scalar>& measurement, Scalar gate_sigma);

  /// Adds `variance` to the position variances (x and y): the estimate is
  /// told that it may be further off than it thinks, so that the gate lets
  /// ranges in again after the robot was moved or the filter drifted.
  void InflatePositionVariance(Scalar variance_m2);

  /// Replaces the position with (x, y), each with standard deviation
  /// sigma_m (> 0), and forgets the position's correlations with the rest of
  /// the state (a fix from multilateration, independent of the prior).
  void ResetPosition(Scalar x_m, Scalar y_m, Scalar sigma_m);

  const StateVector<Scalar>& state() const { return state_; }
  const StateCovariance<Scalar>& covariance() const { return covariance_; }
  const EkfParams<Scalar>& params() const { return params_; }
  /// innovation^2 / (H P H^T + R) of the last Update() that got as far as the
  /// gate, fused or not (the normalized innovation squared, for diagnostics).
  Scalar last_normalized_innovation_squared() const { return last_innovation_squared_ / last_innovation_variance_; }

 private:
  void PropagateCovariance(const Scalar (&jacobian_heading)[4], Scalar bias_to_heading, Scalar dt_s,
                           bool with_imu);
  void ApplyVarianceCeiling();

  EkfParams<Scalar> params_;
  StateVector<Scalar> state_;
  StateCovariance<Scalar> covariance_;
  Scalar last_innovation_squared_ = 0;
  Scalar last_innovation_variance_ = 1;
};

extern template class Ekf<float>;
extern template class Ekf<double>;

}  // namespace syrof::estimation
