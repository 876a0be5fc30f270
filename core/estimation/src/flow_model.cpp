#include "syrof/estimation/flow_model.h"

#include <cmath>

namespace syrof::estimation {

template <typename Scalar>
Scalar FlowBeta(const FlowGeometry<Scalar>& geometry) {
  return (kPi<Scalar> - geometry.viewing_angle_rad) / 2 - geometry.mounting_angle_rad;
}

template <typename Scalar>
Scalar FlowFarEdgeDistance(const FlowGeometry<Scalar>& geometry) {
  return geometry.height_m / std::tan(FlowBeta(geometry));
}

template <typename Scalar>
Scalar FlowNearEdgeDistance(const FlowGeometry<Scalar>& geometry) {
  return geometry.height_m * std::tan(geometry.mounting_angle_rad - geometry.viewing_angle_rad / 2);
}

template <typename Scalar>
Scalar FlowMetresPerPixel(const FlowGeometry<Scalar>& geometry) {
  return (FlowFarEdgeDistance(geometry) - FlowNearEdgeDistance(geometry)) / geometry.pixels;
}

template <typename Scalar>
base::Result<BodyVelocity<Scalar>, EstimationError> FlowToBodyVelocity(const FlowReading& reading,
                                                                      Scalar metres_per_pixel, Scalar sigma_px) {
  if (reading.interval_ns == 0 || !(sigma_px > 0) || !std::isfinite(sigma_px) || !(metres_per_pixel > 0) ||
      !std::isfinite(metres_per_pixel)) {
    return EstimationError::kInvalidMeasurement;
  }
  const Scalar interval_s = static_cast<Scalar>(reading.interval_ns) * static_cast<Scalar>(1e-9);
  const Scalar scale = metres_per_pixel / interval_s;
  return BodyVelocity<Scalar>{static_cast<Scalar>(reading.delta_x_px) * scale,
                              static_cast<Scalar>(reading.delta_y_px) * scale, sigma_px * scale};
}

template <typename Scalar>
base::Result<BodyVelocity<Scalar>, EstimationError> FlowToBodyVelocity(const FlowReading& reading,
                                                                      const FlowGeometry<Scalar>& geometry,
                                                                      Scalar sigma_px) {
  const Scalar beta = FlowBeta(geometry);
  // Past pi/2 the far ray points behind the sensor; at 0 it runs along the floor.
  if (!(geometry.height_m > 0) || !(geometry.pixels > 0) || !(geometry.viewing_angle_rad > 0) || !(beta > 0) ||
      beta > kPi<Scalar> / 2) {
    return EstimationError::kInvalidMeasurement;
  }
  return FlowToBodyVelocity(reading, FlowMetresPerPixel(geometry), sigma_px);
}

template <typename Scalar>
Vector2<Scalar> PredictBodyVelocity(const StateVector<Scalar>& state) {
  const Scalar cos_heading = std::cos(state[kStateHeading]);
  const Scalar sin_heading = std::sin(state[kStateHeading]);
  return Vector2<Scalar>(cos_heading * state[kStateVx] + sin_heading * state[kStateVy],
                         -sin_heading * state[kStateVx] + cos_heading * state[kStateVy]);
}

template <typename Scalar>
Eigen::Matrix<Scalar, 2, kStateSize> BodyVelocityJacobian(const StateVector<Scalar>& state) {
  const Scalar cos_heading = std::cos(state[kStateHeading]);
  const Scalar sin_heading = std::sin(state[kStateHeading]);
  const Vector2<Scalar> body = PredictBodyVelocity(state);
  Eigen::Matrix<Scalar, 2, kStateSize> jacobian = Eigen::Matrix<Scalar, 2, kStateSize>::Zero();
  jacobian(0, kStateVx) = cos_heading;
  jacobian(0, kStateVy) = sin_heading;
  jacobian(0, kStateHeading) = body[1];
  jacobian(1, kStateVx) = -sin_heading;
  jacobian(1, kStateVy) = cos_heading;
  jacobian(1, kStateHeading) = -body[0];
  return jacobian;
}

template <typename Scalar>
EstimationError FuseBodyVelocity(Ekf<Scalar>& filter, const BodyVelocity<Scalar>& velocity, Scalar gate_sigma,
                                 Scalar heading_min_speed_mps) {
  if (!std::isfinite(velocity.forward_mps) || !std::isfinite(velocity.left_mps) || !(velocity.sigma_mps > 0) ||
      !std::isfinite(velocity.sigma_mps)) {
    return EstimationError::kInvalidMeasurement;
  }
  const StateVector<Scalar> prior = filter.state();
  const Scalar cos_heading = std::cos(prior[kStateHeading]);
  const Scalar sin_heading = std::sin(prior[kStateHeading]);
  const Scalar forward = cos_heading * prior[kStateVx] + sin_heading * prior[kStateVy];
  const Scalar left = -sin_heading * prior[kStateVx] + cos_heading * prior[kStateVy];
  const Scalar squared_speed = forward * forward + left * left;
  const bool sees_heading = squared_speed >= heading_min_speed_mps * heading_min_speed_mps;
  Scalar variance = velocity.sigma_mps * velocity.sigma_mps;
  if (!sees_heading) variance += squared_speed * filter.covariance()(kStateHeading, kStateHeading);

  ScalarMeasurement<Scalar> measurement;
  measurement.variance = variance;
  measurement.count = sees_heading ? 3 : 2;
  measurement.index[0] = kStateVx;
  measurement.index[1] = kStateVy;
  measurement.index[2] = kStateHeading;
  measurement.innovation = velocity.forward_mps - forward;
  measurement.jacobian[0] = cos_heading;
  measurement.jacobian[1] = sin_heading;
  measurement.jacobian[2] = left;
  const EstimationError forward_error = filter.Update(measurement, gate_sigma);

  // The left axis, linearized at the same prior: h(x1) ~ h(x0) + H (x1 - x0).
  const StateVector<Scalar>& posterior = filter.state();
  measurement.jacobian[0] = -sin_heading;
  measurement.jacobian[1] = cos_heading;
  measurement.jacobian[2] = sees_heading ? -forward : Scalar{0};
  const Scalar heading_change = WrapAngle<Scalar>(posterior[kStateHeading] - prior[kStateHeading]);
  const Scalar predicted_left = left + measurement.jacobian[0] * (posterior[kStateVx] - prior[kStateVx]) +
                                measurement.jacobian[1] * (posterior[kStateVy] - prior[kStateVy]) +
                                measurement.jacobian[2] * heading_change;
  measurement.innovation = velocity.left_mps - predicted_left;
  const EstimationError left_error = filter.Update(measurement, gate_sigma);
  return forward_error != EstimationError::kOk ? forward_error : left_error;
}

#define SYROF_INSTANTIATE_FLOW_MODEL(Scalar)                                                                  \
  template Scalar FlowBeta<Scalar>(const FlowGeometry<Scalar>&);                                              \
  template Scalar FlowFarEdgeDistance<Scalar>(const FlowGeometry<Scalar>&);                                   \
  template Scalar FlowNearEdgeDistance<Scalar>(const FlowGeometry<Scalar>&);                                  \
  template Scalar FlowMetresPerPixel<Scalar>(const FlowGeometry<Scalar>&);                                    \
  template base::Result<BodyVelocity<Scalar>, EstimationError> FlowToBodyVelocity<Scalar>(                    \
      const FlowReading&, Scalar, Scalar);                                                                    \
  template base::Result<BodyVelocity<Scalar>, EstimationError> FlowToBodyVelocity<Scalar>(                    \
      const FlowReading&, const FlowGeometry<Scalar>&, Scalar);                                               \
  template Vector2<Scalar> PredictBodyVelocity<Scalar>(const StateVector<Scalar>&);                          \
  template Eigen::Matrix<Scalar, 2, kStateSize> BodyVelocityJacobian<Scalar>(const StateVector<Scalar>&);    \
  template EstimationError FuseBodyVelocity<Scalar>(Ekf<Scalar>&, const BodyVelocity<Scalar>&, Scalar, Scalar);

SYROF_INSTANTIATE_FLOW_MODEL(float)
SYROF_INSTANTIATE_FLOW_MODEL(double)

}  // namespace syrof::estimation
