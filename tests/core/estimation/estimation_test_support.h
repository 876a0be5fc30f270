// Helpers shared by the estimation tests: central-difference Jacobians,
// seeded random states and covariances.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>

#include "syrof/estimation/state.h"

namespace syrof::estimation::testing {

/// d f / d state by central differences, one column per state entry. The
/// heading column is wrapped so that a step across +-pi does not read as 2 pi.
template <int Rows, typename Function>
Eigen::Matrix<double, Rows, kStateSize> NumericalJacobian(Function function, const StateVector<double>& state,
                                                          double step = 1e-6) {
  Eigen::Matrix<double, Rows, kStateSize> jacobian;
  for (int column = 0; column < kStateSize; ++column) {
    StateVector<double> plus = state;
    StateVector<double> minus = state;
    plus[column] += step;
    minus[column] -= step;
    const Eigen::Matrix<double, Rows, 1> difference = function(plus) - function(minus);
    jacobian.col(column) = difference / (2 * step);
  }
  return jacobian;
}

/// A state with position in the arena, speeds up to 1 m/s, any heading and
/// a small bias.
inline StateVector<double> RandomState(std::mt19937_64& random) {
  std::uniform_real_distribution<double> position(0.3, 3.7);
  std::uniform_real_distribution<double> speed(-1.0, 1.0);
  std::uniform_real_distribution<double> heading(-3.1, 3.1);
  std::uniform_real_distribution<double> bias(-0.02, 0.02);
  StateVector<double> state;
  state << position(random), position(random), speed(random), speed(random), heading(random), bias(random);
  return state;
}

/// A random symmetric positive definite covariance of realistic scale.
inline StateCovariance<double> RandomCovariance(std::mt19937_64& random) {
  std::uniform_real_distribution<double> entry(-0.1, 0.1);
  StateCovariance<double> factor;
  for (int i = 0; i < kStateSize; ++i) {
    for (int j = 0; j < kStateSize; ++j) factor(i, j) = entry(random);
  }
  StateCovariance<double> covariance = factor * factor.transpose();
  covariance.diagonal().array() += 1e-3;
  return covariance;
}

}  // namespace syrof::estimation::testing
