// The MPU-9250 measurement model (paper, section "Implementation"): the
// sensor reports acceleration in g and angular rate in degrees per second;
// the filter wants m/s^2 and rad/s. The paper multiplies by G = 9.81 m/s^2,
// which this model keeps (standard gravity is 9.80665; the 0.035 % gap is far
// inside the MPU-9250's +-3 % sensitivity tolerance).
//
// The IMU drives the prediction (process_model.h) rather than being fused as
// a measurement: on a planar robot only body x and y acceleration and the
// z rate matter; the rest is carried for completeness.
#pragma once

#include "syrof/base/result.h"
#include "syrof/estimation/estimation_error.h"
#include "syrof/estimation/messages.h"
#include "syrof/estimation/process_model.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// The paper's G, m/s^2 per g.
template <typename Scalar>
inline constexpr Scalar kPaperGravity = static_cast<Scalar>(9.81);

/// Acceleration in g to m/s^2 (times G = 9.81).
template <typename Scalar>
constexpr Scalar MetresPerSecondSquaredFromG(Scalar g) {
  return g * kPaperGravity<Scalar>;
}

/// Angular rate in deg/s to rad/s.
template <typename Scalar>
constexpr Scalar RadiansPerSecondFromDegrees(Scalar degrees_per_second) {
  return degrees_per_second * (kPi<Scalar> / 180);
}

/// An IMU sample in SI units, body frame.
template <typename Scalar>
struct ImuSample {
  Vector3<Scalar> accel_mps2 = Vector3<Scalar>::Zero();  ///< specific force, m/s^2
  Vector3<Scalar> rate_radps = Vector3<Scalar>::Zero();  ///< angular rate, rad/s
};

/// The reading in SI units; kInvalidMeasurement if any field is not finite.
template <typename Scalar>
base::Result<ImuSample<Scalar>, EstimationError> ConvertImuReading(const ImuReading& reading);

/// What the planar prediction uses of a sample: body x, y acceleration and
/// the z rate.
template <typename Scalar>
ImuInput<Scalar> PlanarImuInput(const ImuSample<Scalar>& sample);

}  // namespace syrof::estimation
