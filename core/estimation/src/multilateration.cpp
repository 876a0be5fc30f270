#include "syrof/estimation/multilateration.h"

#include <Eigen/LU>
#include <cmath>
#include <limits>

namespace syrof::estimation {
namespace {

template <typename Scalar>
bool ValidRanges(std::span<const Scalar> ranges_m) {
  for (const Scalar range : ranges_m) {
    if (!std::isfinite(range) || range < 0) return false;
  }
  return true;
}

template <typename Scalar>
bool ValidAnchors(std::span<const Vector3<Scalar>> anchors) {
  for (const Vector3<Scalar>& anchor : anchors) {
    if (!anchor.allFinite()) return false;
  }
  return true;
}

// A normal matrix is treated as singular when its determinant is tiny next to
// the cube (or square) of its mean eigenvalue: the anchors are coplanar
// (collinear) up to rounding.
template <typename Scalar, int N>
bool WellConditioned(const Eigen::Matrix<Scalar, N, N>& normal) {
  const Scalar mean_eigenvalue = normal.trace() / N;
  const Scalar scale = N == 3 ? mean_eigenvalue * mean_eigenvalue * mean_eigenvalue : mean_eigenvalue * mean_eigenvalue;
  const Scalar determinant = normal.determinant();
  return std::isfinite(determinant) && scale > 0 &&
         std::abs(determinant) > std::sqrt(std::numeric_limits<Scalar>::epsilon()) * scale;
}

// Step size below which Gauss-Newton has converged: the square root of the
// precision at the problem's scale (the next step would be far smaller still,
// since convergence is quadratic for consistent ranges).
template <typename Scalar>
Scalar ConvergenceTolerance(std::span<const Scalar> ranges_m) {
  Scalar largest = 0;
  for (const Scalar range : ranges_m) largest = range > largest ? range : largest;
  return std::sqrt(std::numeric_limits<Scalar>::epsilon()) * (1 + largest);
}

}  // namespace

template <typename Scalar>
base::Result<Vector3<Scalar>, EstimationError> ClosedFormPosition(const FourAnchorLayout<Scalar>& layout,
                                                                  const Scalar (&ranges_m)[4]) {
  if (!(layout.side_m > 0) || !(layout.height_m > 0)) return EstimationError::kDegenerateGeometry;
  if (!ValidRanges(std::span<const Scalar>(ranges_m))) return EstimationError::kInvalidMeasurement;
  const Scalar side = layout.side_m;
  const Scalar height = layout.height_m;
  const Scalar d0 = ranges_m[0] * ranges_m[0];
  const Scalar d1 = ranges_m[1] * ranges_m[1];
  const Scalar d2 = ranges_m[2] * ranges_m[2];
  const Scalar d3 = ranges_m[3] * ranges_m[3];
  return Vector3<Scalar>((d0 - d1 + d2 - d3) / (4 * side) + side / 2, (d0 - d1 - d2 + d3) / (4 * side) + side / 2,
                         (d0 + d1 - d2 - d3) / (4 * height) + height / 2);
}

template <typename Scalar>
base::Result<Vector3<Scalar>, EstimationError> Multilaterate(std::span<const Vector3<Scalar>> anchors,
                                                             std::span<const Scalar> ranges_m, int max_iterations) {
  using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;
  if (anchors.size() != ranges_m.size() || !ValidRanges(ranges_m) || !ValidAnchors(anchors)) {
    return EstimationError::kInvalidMeasurement;
  }
  if (anchors.size() < 4) return EstimationError::kTooFewAnchors;

  // Linear start: the plane equations against anchor 0, in least squares.
  const Vector3<Scalar>& reference = anchors[0];
  const Scalar reference_term = ranges_m[0] * ranges_m[0] - reference.squaredNorm();
  Matrix3 normal = Matrix3::Zero();
  Vector3<Scalar> right = Vector3<Scalar>::Zero();
  for (size_t i = 1; i < anchors.size(); ++i) {
    const Vector3<Scalar> row = 2 * (anchors[i] - reference);
    const Scalar value = reference_term - ranges_m[i] * ranges_m[i] + anchors[i].squaredNorm();
    normal += row * row.transpose();
    right += row * value;
  }
  if (!WellConditioned(normal)) return EstimationError::kDegenerateGeometry;
  Vector3<Scalar> position = normal.inverse() * right;

  const Scalar tolerance = ConvergenceTolerance(ranges_m);
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    Matrix3 gauss_newton = Matrix3::Zero();
    Vector3<Scalar> gradient = Vector3<Scalar>::Zero();
    for (size_t i = 0; i < anchors.size(); ++i) {
      const Vector3<Scalar> offset = position - anchors[i];
      const Scalar distance = offset.norm();
      if (!(distance > 0)) continue;  // on an anchor: that range gives no direction
      const Vector3<Scalar> direction = offset / distance;
      gauss_newton += direction * direction.transpose();
      gradient += direction * (ranges_m[i] - distance);
    }
    if (!WellConditioned(gauss_newton)) return EstimationError::kDegenerateGeometry;
    const Vector3<Scalar> step = gauss_newton.inverse() * gradient;
    position += step;
    if (!position.allFinite()) return EstimationError::kNoConvergence;
    if (step.norm() <= tolerance) return position;
  }
  return EstimationError::kNoConvergence;
}

template <typename Scalar>
base::Result<Vector2<Scalar>, EstimationError> MultilaterateOnPlane(std::span<const Vector3<Scalar>> anchors,
                                                                    std::span<const Scalar> ranges_m,
                                                                    Scalar height_m, int max_iterations) {
  using Matrix2 = Eigen::Matrix<Scalar, 2, 2>;
  if (anchors.size() != ranges_m.size() || !ValidRanges(ranges_m) || !ValidAnchors(anchors) ||
      !std::isfinite(height_m)) {
    return EstimationError::kInvalidMeasurement;
  }
  if (anchors.size() < 3) return EstimationError::kTooFewAnchors;

  // Plane equations against anchor 0 with z = height known:
  // 2 (a_i - a_0)_xy . p_xy = d_0^2 - d_i^2 + |a_i|^2 - |a_0|^2 - 2 (a_i.z - a_0.z) height.
  const Vector3<Scalar>& reference = anchors[0];
  const Scalar reference_term = ranges_m[0] * ranges_m[0] - reference.squaredNorm();
  Matrix2 normal = Matrix2::Zero();
  Vector2<Scalar> right = Vector2<Scalar>::Zero();
  for (size_t i = 1; i < anchors.size(); ++i) {
    const Vector2<Scalar> row = 2 * (anchors[i] - reference).template head<2>();
    const Scalar value = reference_term - ranges_m[i] * ranges_m[i] + anchors[i].squaredNorm() -
                         2 * (anchors[i][2] - reference[2]) * height_m;
    normal += row * row.transpose();
    right += row * value;
  }
  if (!WellConditioned(normal)) return EstimationError::kDegenerateGeometry;
  Vector2<Scalar> position = normal.inverse() * right;

  const Scalar tolerance = ConvergenceTolerance(ranges_m);
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    Matrix2 gauss_newton = Matrix2::Zero();
    Vector2<Scalar> gradient = Vector2<Scalar>::Zero();
    for (size_t i = 0; i < anchors.size(); ++i) {
      const Vector3<Scalar> offset(position[0] - anchors[i][0], position[1] - anchors[i][1],
                                   height_m - anchors[i][2]);
      const Scalar distance = offset.norm();
      if (!(distance > 0)) continue;
      const Vector2<Scalar> direction = offset.template head<2>() / distance;
      gauss_newton += direction * direction.transpose();
      gradient += direction * (ranges_m[i] - distance);
    }
    if (!WellConditioned(gauss_newton)) return EstimationError::kDegenerateGeometry;
    const Vector2<Scalar> step = gauss_newton.inverse() * gradient;
    position += step;
    if (!position.allFinite()) return EstimationError::kNoConvergence;
    if (step.norm() <= tolerance) return position;
  }
  return EstimationError::kNoConvergence;
}

namespace {

template <typename Scalar>
Scalar LargestResidual(std::span<const Vector3<Scalar>> anchors, std::span<const Scalar> ranges_m,
                       const Vector2<Scalar>& position, Scalar height_m) {
  Scalar largest = 0;
  for (size_t i = 0; i < anchors.size(); ++i) {
    const Vector3<Scalar> offset(position[0] - anchors[i][0], position[1] - anchors[i][1], height_m - anchors[i][2]);
    const Scalar residual = std::abs(ranges_m[i] - offset.norm());
    largest = residual > largest ? residual : largest;
  }
  return largest;
}

}  // namespace

template <typename Scalar>
base::Result<Vector2<Scalar>, EstimationError> MultilaterateOnPlaneRobust(std::span<const Vector3<Scalar>> anchors,
                                                                          std::span<const Scalar> ranges_m,
                                                                          Scalar height_m, Scalar tolerance_m) {
  if (anchors.size() > static_cast<size_t>(kMaxAnchors)) return EstimationError::kInvalidMeasurement;
  const auto all = MultilaterateOnPlane<Scalar>(anchors, ranges_m, height_m);
  if (all.ok() && LargestResidual(anchors, ranges_m, all.value(), height_m) <= tolerance_m) return all;
  if (all.error() == EstimationError::kInvalidMeasurement || all.error() == EstimationError::kTooFewAnchors) {
    return all.error();
  }
  const size_t count = anchors.size();
  if (count < 4) return EstimationError::kInconsistentRanges;
  Vector3<Scalar> subset_anchors[kMaxAnchors];
  Scalar subset_ranges[kMaxAnchors];
  Vector2<Scalar> found = Vector2<Scalar>::Zero();
  int fitting = 0;
  for (size_t left_out = 0; left_out < count; ++left_out) {
    size_t used = 0;
    for (size_t i = 0; i < count; ++i) {
      if (i == left_out) continue;
      subset_anchors[used] = anchors[i];
      subset_ranges[used] = ranges_m[i];
      ++used;
    }
    const std::span<const Vector3<Scalar>> subset(subset_anchors, used);
    const std::span<const Scalar> subset_range_span(subset_ranges, used);
    const auto fix = MultilaterateOnPlane<Scalar>(subset, subset_range_span, height_m);
    if (!fix.ok() || LargestResidual(subset, subset_range_span, fix.value(), height_m) > tolerance_m) continue;
    found = fix.value();
    ++fitting;
  }
  if (fitting != 1) return EstimationError::kInconsistentRanges;
  return found;
}

#define SYROF_INSTANTIATE_MULTILATERATION(Scalar)                                                          \
  template base::Result<Vector3<Scalar>, EstimationError> ClosedFormPosition<Scalar>(                       \
      const FourAnchorLayout<Scalar>&, const Scalar (&)[4]);                                                \
  template base::Result<Vector3<Scalar>, EstimationError> Multilaterate<Scalar>(                            \
      std::span<const Vector3<Scalar>>, std::span<const Scalar>, int);                                      \
  template base::Result<Vector2<Scalar>, EstimationError> MultilaterateOnPlane<Scalar>(                     \
      std::span<const Vector3<Scalar>>, std::span<const Scalar>, Scalar, int);                              \
  template base::Result<Vector2<Scalar>, EstimationError> MultilaterateOnPlaneRobust<Scalar>(               \
      std::span<const Vector3<Scalar>>, std::span<const Scalar>, Scalar, Scalar);

SYROF_INSTANTIATE_MULTILATERATION(float)
SYROF_INSTANTIATE_MULTILATERATION(double)

}  // namespace syrof::estimation
