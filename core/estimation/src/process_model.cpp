#include "syrof/estimation/process_model.h"

#include <cmath>

namespace syrof::estimation {

namespace {

// The body acceleration turned into the arena frame at the heading halfway
// through the step (the midpoint rule: the robot turns while it accelerates).
template <typename Scalar>
Vector2<Scalar> ArenaAcceleration(const StateVector<Scalar>& state, const ImuInput<Scalar>& imu, Scalar dt_s) {
  const Scalar heading = state[kStateHeading] + (imu.yaw_rate_radps - state[kStateGyroBias]) * (dt_s / 2);
  const Scalar cos_heading = std::cos(heading);
  const Scalar sin_heading = std::sin(heading);
  return Vector2<Scalar>(cos_heading * imu.accel_forward_mps2 - sin_heading * imu.accel_left_mps2,
                         sin_heading * imu.accel_forward_mps2 + cos_heading * imu.accel_left_mps2);
}

}  // namespace

template <typename Scalar>
StateVector<Scalar> PropagateState(const StateVector<Scalar>& state, const ImuInput<Scalar>& imu, Scalar dt_s) {
  const Vector2<Scalar> accel = ArenaAcceleration(state, imu, dt_s);
  const Scalar half_dt2 = dt_s * dt_s / 2;
  StateVector<Scalar> next = state;
  next[kStateX] += state[kStateVx] * dt_s + accel[0] * half_dt2;
  next[kStateY] += state[kStateVy] * dt_s + accel[1] * half_dt2;
  next[kStateVx] += accel[0] * dt_s;
  next[kStateVy] += accel[1] * dt_s;
  next[kStateHeading] = WrapAngle<Scalar>(state[kStateHeading] + (imu.yaw_rate_radps - state[kStateGyroBias]) * dt_s);
  return next;
}

template <typename Scalar>
StateVector<Scalar> PropagateState(const StateVector<Scalar>& state, Scalar dt_s) {
  StateVector<Scalar> next = state;
  next[kStateX] += state[kStateVx] * dt_s;
  next[kStateY] += state[kStateVy] * dt_s;
  return next;
}

template <typename Scalar>
StateCovariance<Scalar> ProcessJacobian(const StateVector<Scalar>& state, const ImuInput<Scalar>& imu,
                                        Scalar dt_s) {
  const Vector2<Scalar> accel = ArenaAcceleration(state, imu, dt_s);
  StateCovariance<Scalar> jacobian = StateCovariance<Scalar>::Identity();
  jacobian(kStateX, kStateVx) = dt_s;
  jacobian(kStateY, kStateVy) = dt_s;
  // d(R(h) a)/d h = (-a_y, a_x): the acceleration turns with the heading h,
  // which is theta + (w - b) dt / 2, so the bias turns it too, by -dt/2.
  const Scalar heading_column[4] = {-accel[1] * dt_s * dt_s / 2, accel[0] * dt_s * dt_s / 2, -accel[1] * dt_s,
                                    accel[0] * dt_s};
  for (int row = 0; row < 4; ++row) {
    jacobian(row, kStateHeading) = heading_column[row];
    jacobian(row, kStateGyroBias) = -heading_column[row] * dt_s / 2;
  }
  jacobian(kStateHeading, kStateGyroBias) = -dt_s;
  return jacobian;
}

template <typename Scalar>
StateCovariance<Scalar> ProcessJacobian(Scalar dt_s) {
  StateCovariance<Scalar> jacobian = StateCovariance<Scalar>::Identity();
  jacobian(kStateX, kStateVx) = dt_s;
  jacobian(kStateY, kStateVy) = dt_s;
  return jacobian;
}

template <typename Scalar>
ProcessNoiseTerms<Scalar> ProcessNoiseEntries(const ProcessNoise<Scalar>& noise, Scalar dt_s, bool with_imu) {
  const Scalar accel_density = with_imu ? noise.accel_noise_density : noise.unmeasured_accel_density;
  const Scalar heading_density = with_imu ? noise.gyro_noise_density : noise.unmeasured_yaw_rate_density;
  const Scalar accel_power = accel_density * accel_density;
  const Scalar bias_power = noise.gyro_bias_walk * noise.gyro_bias_walk;
  const Scalar dt2 = dt_s * dt_s;
  const Scalar dt3 = dt2 * dt_s;
  ProcessNoiseTerms<Scalar> terms;
  terms.position = accel_power * dt3 / 3;
  terms.position_velocity = accel_power * dt2 / 2;
  terms.velocity = accel_power * dt_s;
  terms.heading = heading_density * heading_density * dt_s;
  if (with_imu) {
    // The heading integrates -b, so the bias walk reaches it too.
    terms.heading += bias_power * dt3 / 3;
    terms.heading_bias = -bias_power * dt2 / 2;
  }
  terms.bias = bias_power * dt_s;
  return terms;
}

template <typename Scalar>
StateCovariance<Scalar> ProcessNoiseCovariance(const ProcessNoise<Scalar>& noise, Scalar dt_s, bool with_imu) {
  const ProcessNoiseTerms<Scalar> terms = ProcessNoiseEntries(noise, dt_s, with_imu);
  StateCovariance<Scalar> q = StateCovariance<Scalar>::Zero();
  for (const int axis : {0, 1}) {
    const int position = kStateX + axis;
    const int velocity = kStateVx + axis;
    q(position, position) = terms.position;
    q(position, velocity) = terms.position_velocity;
    q(velocity, position) = terms.position_velocity;
    q(velocity, velocity) = terms.velocity;
  }
  q(kStateHeading, kStateHeading) = terms.heading;
  q(kStateHeading, kStateGyroBias) = terms.heading_bias;
  q(kStateGyroBias, kStateHeading) = terms.heading_bias;
  q(kStateGyroBias, kStateGyroBias) = terms.bias;
  return q;
}

#define SYROF_INSTANTIATE_PROCESS_MODEL(Scalar)                                                              \
  template StateVector<Scalar> PropagateState<Scalar>(const StateVector<Scalar>&, const ImuInput<Scalar>&,   \
                                                      Scalar);                                               \
  template StateVector<Scalar> PropagateState<Scalar>(const StateVector<Scalar>&, Scalar);                   \
  template StateCovariance<Scalar> ProcessJacobian<Scalar>(const StateVector<Scalar>&, const ImuInput<Scalar>&, \
                                                           Scalar);                                          \
  template StateCovariance<Scalar> ProcessJacobian<Scalar>(Scalar);                                          \
  template ProcessNoiseTerms<Scalar> ProcessNoiseEntries<Scalar>(const ProcessNoise<Scalar>&, Scalar, bool);    \
  template StateCovariance<Scalar> ProcessNoiseCovariance<Scalar>(const ProcessNoise<Scalar>&, Scalar, bool);

SYROF_INSTANTIATE_PROCESS_MODEL(float)
SYROF_INSTANTIATE_PROCESS_MODEL(double)

}  // namespace syrof::estimation
