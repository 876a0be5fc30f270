// The motion model: IMU-driven dead reckoning on the plane.
//
// Over one step of length dt the body-frame acceleration (a_fwd, a_left) and
// the yaw rate w (both from the MPU-9250) are held constant. The robot turns
// while it accelerates, so the acceleration is rotated into the arena frame
// at the heading halfway through the step (the midpoint rule; the heading at
// the start would lag by w dt / 2 and bias the velocity on every curve):
//   a = R(theta + (w - b) dt / 2) (a_fwd, a_left),  R(h) = [cos -sin; sin cos]
// and the state moves as
//   p'     = p + v dt + a dt^2 / 2
//   v'     = v + a dt
//   theta' = wrap(theta + (w - b) dt)
//   b'     = b                        (b: gyro bias, a random walk)
// This replaces the paper's x + dt xdot^2 / 2 (see docs/estimation.md).
// Without IMU data, the same model runs with a = 0 and w - b = 0 (constant
// velocity, constant heading) and a larger process noise.
//
// These functions are the reference the filter's structured (sparse)
// prediction must agree with; they build dense matrices and are meant for
// tests, tools and documentation, not the 100 Hz loop.
#pragma once

#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// The IMU's contribution to one prediction step, SI units, body frame.
template <typename Scalar>
struct ImuInput {
  Scalar accel_forward_mps2 = 0;  ///< specific force along body x, gravity excluded (the robot stays level)
  Scalar accel_left_mps2 = 0;     ///< specific force along body y
  Scalar yaw_rate_radps = 0;      ///< gyro z as measured (bias included), CCW positive
};

/// Process noise, as continuous-time densities: the variance a quantity
/// gains over dt is density^2 * dt.
template <typename Scalar>
struct ProcessNoise {
  /// Accelerometer noise plus what the model leaves out (accelerometer bias,
  /// tilt), m/s^2/sqrt(Hz). Enters as white acceleration.
  Scalar accel_noise_density = static_cast<Scalar>(0.05);
  /// Gyro white noise, rad/s/sqrt(Hz).
  Scalar gyro_noise_density = static_cast<Scalar>(3.0e-4);
  /// Gyro bias random walk, rad/s/sqrt(s).
  Scalar gyro_bias_walk = static_cast<Scalar>(1.0e-4);
  /// Acceleration density when predicting without the IMU (constant-velocity
  /// model): how hard the robot may accelerate unseen, m/s^2/sqrt(Hz).
  Scalar unmeasured_accel_density = static_cast<Scalar>(1.0);
  /// Heading rate density without the IMU, rad/s/sqrt(Hz).
  Scalar unmeasured_yaw_rate_density = static_cast<Scalar>(1.0);
};

/// The state after dt seconds under `imu` (see the model above).
template <typename Scalar>
StateVector<Scalar> PropagateState(const StateVector<Scalar>& state, const ImuInput<Scalar>& imu, Scalar dt_s);

/// The state after dt seconds without IMU data: constant velocity, constant
/// heading, constant bias.
template <typename Scalar>
StateVector<Scalar> PropagateState(const StateVector<Scalar>& state, Scalar dt_s);

/// d PropagateState / d state at (state, imu, dt), dense.
template <typename Scalar>
StateCovariance<Scalar> ProcessJacobian(const StateVector<Scalar>& state, const ImuInput<Scalar>& imu,
                                        Scalar dt_s);

/// d PropagateState / d state without IMU data, dense.
template <typename Scalar>
StateCovariance<Scalar> ProcessJacobian(Scalar dt_s);

/// The non-zero entries of Q over dt, once: ProcessNoiseCovariance lays them
/// out densely, the filter's sparse predict adds them in place.
template <typename Scalar>
struct ProcessNoiseTerms {
  Scalar position = 0;           // Q(x, x) and Q(y, y)
  Scalar position_velocity = 0;  // Q(x, vx) and Q(y, vy), symmetric
  Scalar velocity = 0;           // Q(vx, vx) and Q(vy, vy)
  Scalar heading = 0;            // Q(theta, theta)
  Scalar heading_bias = 0;       // Q(theta, b), symmetric; zero without the IMU
  Scalar bias = 0;               // Q(b, b)
};

/// The entries of ProcessNoiseCovariance(noise, dt_s, with_imu).
template <typename Scalar>
ProcessNoiseTerms<Scalar> ProcessNoiseEntries(const ProcessNoise<Scalar>& noise, Scalar dt_s, bool with_imu);

/// The process noise covariance Q over dt: white acceleration (position and
/// velocity blocks, the standard dt^3/3, dt^2/2, dt terms), white heading
/// rate, and the gyro bias walk (which also reaches the heading, since the
/// heading integrates w - b). `with_imu` selects the IMU densities; without
/// the IMU the unmeasured densities apply and the bias, which then enters no
/// equation, only walks.
template <typename Scalar>
StateCovariance<Scalar> ProcessNoiseCovariance(const ProcessNoise<Scalar>& noise, Scalar dt_s, bool with_imu);

}  // namespace syrof::estimation
