// The filter's state vector and the types every part of the estimator shares.
//
// Frames: the arena frame is right-handed with z up; the robot moves on the
// plane z = const. Heading is measured counter-clockwise from the arena's +x
// axis, in [-pi, pi] (as the beacon carries it, see core/wire). The body frame
// has x forward, y left, z up.
#pragma once

#include <Eigen/Core>

namespace syrof::estimation {

/// Positions of the quantities in the state vector.
enum StateIndex : int {
  kStateX = 0,         ///< position along arena x, m
  kStateY = 1,         ///< position along arena y, m
  kStateVx = 2,        ///< velocity along arena x, m/s
  kStateVy = 3,        ///< velocity along arena y, m/s
  kStateHeading = 4,   ///< heading, rad, CCW from +x, in [-pi, pi]
  kStateGyroBias = 5,  ///< yaw-rate gyro bias, rad/s (measured rate = true rate + bias)
};

/// Number of entries in the state vector.
inline constexpr int kStateSize = 6;

template <typename Scalar>
using StateVector = Eigen::Matrix<Scalar, kStateSize, 1>;
template <typename Scalar>
using StateCovariance = Eigen::Matrix<Scalar, kStateSize, kStateSize>;
template <typename Scalar>
using Vector2 = Eigen::Matrix<Scalar, 2, 1>;
template <typename Scalar>
using Vector3 = Eigen::Matrix<Scalar, 3, 1>;

template <typename Scalar>
inline constexpr Scalar kPi = static_cast<Scalar>(3.14159265358979323846);

/// `radians` wrapped into [-pi, pi]. Exact for |radians| < 3 pi (one
/// subtraction or addition), which covers every use in the filter: heading
/// plus one step's rotation or correction. Larger inputs are reduced with
/// remainder().
template <typename Scalar>
Scalar WrapAngle(Scalar radians);

}  // namespace syrof::estimation
