#include "syrof/estimation/multilateration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "syrof/estimation/arena.h"

namespace syrof::estimation {
namespace {

template <typename Scalar>
void RangesTo(const FourAnchorLayout<Scalar>& layout, const Vector3<Scalar>& point, Scalar (&ranges)[4]) {
  for (int i = 0; i < 4; ++i) ranges[i] = (point - layout.anchor(i)).norm();
}

Vector3<double> RandomPoint(std::mt19937_64& random, double side, double height) {
  std::uniform_real_distribution<double> horizontal(-0.2 * side, 1.2 * side);
  std::uniform_real_distribution<double> vertical(-0.2 * height, 1.2 * height);
  return Vector3<double>(horizontal(random), horizontal(random), vertical(random));
}

TEST(FourAnchorLayoutTest, ThePapersUnitLayoutAndTheDefaultArena) {
  const FourAnchorLayout<double> paper{1, 1};
  EXPECT_EQ(paper.anchor(0), Vector3<double>(0, 0, 0));
  EXPECT_EQ(paper.anchor(1), Vector3<double>(1, 1, 0));
  EXPECT_EQ(paper.anchor(2), Vector3<double>(0, 1, 1));
  EXPECT_EQ(paper.anchor(3), Vector3<double>(1, 0, 1));
  const Arena<double> arena = DefaultArena<double>();
  EXPECT_EQ(arena.anchor_count, 4);
  EXPECT_EQ(arena.anchors[1], Vector3<double>(4, 4, 0));
  EXPECT_EQ(arena.anchors[2], Vector3<double>(0, 4, 2));
  EXPECT_EQ(arena.anchors[3], Vector3<double>(4, 0, 2));
  EXPECT_DOUBLE_EQ(arena.tag_height_m, 0.1);
  EXPECT_DOUBLE_EQ(arena.width_m, 4.0);
}

TEST(ClosedFormTest, RecoversPointsFromNoiselessRangesInThePapersLayoutAndTheArena) {
  std::mt19937_64 random(41);
  for (const FourAnchorLayout<double> layout : {FourAnchorLayout<double>{1, 1}, DefaultAnchorLayout<double>()}) {
    for (int trial = 0; trial < 100; ++trial) {
      const Vector3<double> point = RandomPoint(random, layout.side_m, layout.height_m);
      double ranges[4];
      RangesTo(layout, point, ranges);
      const auto position = ClosedFormPosition(layout, ranges);
      ASSERT_TRUE(position.ok());
      EXPECT_LT((position.value() - point).norm(), 1e-9);
    }
  }
}

// The paper's printed formulas, taken literally with its m_{0,1} and
// m_{2,3} and, "similarly", m_{i,j} = (d_i^2 - d_j^2 + 2)/2 for the pairs
// (0,2), (0,3) and m_{i,j} = 1 - (d_i^2 - d_j^2 + 2)/2 for (1,3), (1,2):
// x and y come out swapped, and the second z formula repeats y's right-hand
// side, which gives x. docs/estimation.md lists the corrections.
TEST(ClosedFormTest, ThePapersPrintedFormulasSwapXAndYAndMisprintZ) {
  const FourAnchorLayout<double> paper{1, 1};
  const Vector3<double> point(0.2, 0.7, 0.4);
  double d[4];
  RangesTo(paper, point, d);
  const auto near_line = [&](int i, int j) { return (d[i] * d[i] - d[j] * d[j] + 2) / 2; };
  const auto far_line = [&](int i, int j) { return 1 - (d[i] * d[i] - d[j] * d[j] + 2) / 2; };
  const double m01 = near_line(0, 1), m23 = far_line(2, 3);
  const double m02 = near_line(0, 2), m13 = far_line(1, 3);
  const double m03 = near_line(0, 3), m12 = far_line(1, 2);

  const double printed_x = (m01 + m23) / 2;
  const double printed_x_again = (m02 + m13) / 2;
  const double printed_y = (m01 - m23) / 2;
  const double printed_y_again = (m03 + m12) / 2;
  const double printed_z = (m02 - m13) / 2;
  const double printed_z_again = (m03 + m12) / 2;
  EXPECT_NEAR(printed_x, point.y(), 1e-12);
  EXPECT_NEAR(printed_x_again, point.y(), 1e-12);
  EXPECT_NEAR(printed_y, point.x(), 1e-12);
  EXPECT_NEAR(printed_y_again, point.x(), 1e-12);
  EXPECT_NEAR(printed_z, point.z(), 1e-12);
  EXPECT_NEAR(printed_z_again, point.x(), 1e-12);  // should be (m03 - m12)/2 = z
  EXPECT_NEAR((m03 - m12) / 2, point.z(), 1e-12);

  const auto corrected = ClosedFormPosition(paper, d);
  ASSERT_TRUE(corrected.ok());
  EXPECT_LT((corrected.value() - point).norm(), 1e-12);
}

TEST(ClosedFormTest, RefusesBadLayoutsAndRanges) {
  const double ranges[4] = {1, 1, 1, 1};
  EXPECT_EQ(ClosedFormPosition(FourAnchorLayout<double>{0, 1}, ranges).error(), EstimationError::kDegenerateGeometry);
  EXPECT_EQ(ClosedFormPosition(FourAnchorLayout<double>{1, 0}, ranges).error(), EstimationError::kDegenerateGeometry);
  const double negative[4] = {1, -1, 1, 1};
  EXPECT_EQ(ClosedFormPosition(FourAnchorLayout<double>{1, 1}, negative).error(),
            EstimationError::kInvalidMeasurement);
}

TEST(MultilaterateTest, AgreesWithTheClosedFormOnNoiselessRanges) {
  std::mt19937_64 random(42);
  const FourAnchorLayout<double> layout = DefaultAnchorLayout<double>();
  const Vector3<double> anchors[4] = {layout.anchor(0), layout.anchor(1), layout.anchor(2), layout.anchor(3)};
  for (int trial = 0; trial < 100; ++trial) {
    const Vector3<double> point = RandomPoint(random, layout.side_m, layout.height_m);
    double ranges[4];
    RangesTo(layout, point, ranges);
    const auto closed = ClosedFormPosition(layout, ranges);
    const auto least_squares = Multilaterate<double>(anchors, ranges);
    ASSERT_TRUE(closed.ok());
    ASSERT_TRUE(least_squares.ok()) << ToString(least_squares.error());
    EXPECT_LT((least_squares.value() - closed.value()).norm(), 1e-9);
    EXPECT_LT((least_squares.value() - point).norm(), 1e-9);
  }
}

TEST(MultilaterateTest, AgreesWithTheClosedFormWithinTheNoiseOnNoisyRanges) {
  std::mt19937_64 random(43);
  std::normal_distribution<double> noise(0.0, 0.01);
  const FourAnchorLayout<double> layout = DefaultAnchorLayout<double>();
  const Vector3<double> anchors[4] = {layout.anchor(0), layout.anchor(1), layout.anchor(2), layout.anchor(3)};
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3<double> point(1 + 2 * trial / 50.0, 2.0, 0.1);
    double ranges[4];
    RangesTo(layout, point, ranges);
    for (double& range : ranges) range += noise(random);
    const auto closed = ClosedFormPosition(layout, ranges);
    const auto least_squares = Multilaterate<double>(anchors, ranges);
    ASSERT_TRUE(closed.ok() && least_squares.ok());
    // Four ranges, three unknowns: one degree of freedom of disagreement.
    EXPECT_LT((least_squares.value() - closed.value()).norm(), 0.1);
  }
}

TEST(MultilaterateTest, SolvesAnyLayoutWithMoreAnchors) {
  std::mt19937_64 random(44);
  std::uniform_real_distribution<double> coordinate(0.0, 5.0);
  for (int trial = 0; trial < 20; ++trial) {
    Vector3<double> anchors[6];
    double ranges[6];
    const Vector3<double> point(coordinate(random), coordinate(random), coordinate(random) / 2);
    for (int i = 0; i < 6; ++i) {
      anchors[i] = Vector3<double>(coordinate(random), coordinate(random), coordinate(random));
      ranges[i] = (point - anchors[i]).norm();
    }
    const auto position = Multilaterate<double>(anchors, ranges);
    ASSERT_TRUE(position.ok()) << ToString(position.error());
    EXPECT_LT((position.value() - point).norm(), 1e-8);
  }
}

TEST(MultilaterateTest, WorksInFloat) {
  const FourAnchorLayout<float> layout = DefaultAnchorLayout<float>();
  const Vector3<float> anchors[4] = {layout.anchor(0), layout.anchor(1), layout.anchor(2), layout.anchor(3)};
  const Vector3<float> point(1.3f, 2.9f, 0.1f);
  float ranges[4];
  RangesTo(layout, point, ranges);
  const auto position = Multilaterate<float>(anchors, ranges);
  ASSERT_TRUE(position.ok());
  EXPECT_LT((position.value() - point).norm(), 1e-3f);
  const auto closed = ClosedFormPosition(layout, ranges);
  ASSERT_TRUE(closed.ok());
  EXPECT_LT((closed.value() - point).norm(), 1e-3f);
}

TEST(MultilaterateTest, RefusesTooFewCoplanarOrMismatchedInputs) {
  const Vector3<double> flat[4] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {4, 4, 0}};
  const double ranges[4] = {2, 3, 3, 4};
  EXPECT_EQ(Multilaterate<double>(flat, ranges).error(), EstimationError::kDegenerateGeometry);
  EXPECT_EQ(Multilaterate<double>(std::span<const Vector3<double>>(flat, 3), std::span<const double>(ranges, 3)).error(),
            EstimationError::kTooFewAnchors);
  EXPECT_EQ(Multilaterate<double>(std::span<const Vector3<double>>(flat, 4), std::span<const double>(ranges, 3)).error(),
            EstimationError::kInvalidMeasurement);
  const double bad[4] = {2, std::nan(""), 3, 4};
  EXPECT_EQ(Multilaterate<double>(flat, bad).error(), EstimationError::kInvalidMeasurement);
}

TEST(MultilaterateOnPlaneTest, RecoversThePositionAtTheAntennaHeight) {
  const Arena<double> arena = DefaultArena<double>();
  std::mt19937_64 random(45);
  std::uniform_real_distribution<double> coordinate(0.2, 3.8);
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3<double> point(coordinate(random), coordinate(random), arena.tag_height_m);
    double ranges[4];
    for (int i = 0; i < 4; ++i) ranges[i] = (point - arena.anchors[i]).norm();
    const auto position =
        MultilaterateOnPlane<double>(std::span<const Vector3<double>>(arena.anchors, 4), ranges, arena.tag_height_m);
    ASSERT_TRUE(position.ok()) << ToString(position.error());
    EXPECT_LT((position.value() - point.head<2>()).norm(), 1e-9);
    // Any three anchors suffice on the plane.
    const auto from_three = MultilaterateOnPlane<double>(std::span<const Vector3<double>>(arena.anchors + 1, 3),
                                                         std::span<const double>(ranges + 1, 3), arena.tag_height_m);
    ASSERT_TRUE(from_three.ok());
    EXPECT_LT((from_three.value() - point.head<2>()).norm(), 1e-9);
  }
}

TEST(MultilaterateOnPlaneRobustTest, AcceptsConsistentRangesNamesAnOutlierOrRefuses) {
  const Arena<float> arena = DefaultArena<float>();
  const std::span<const Vector3<float>> anchors(arena.anchors, 4);
  const Vector3<float> point(1.5f, 2.5f, arena.tag_height_m);
  float ranges[4];
  for (int i = 0; i < 4; ++i) ranges[i] = (point - arena.anchors[i]).norm();
  const auto clean = MultilaterateOnPlaneRobust<float>(anchors, ranges, arena.tag_height_m, 0.3f);
  ASSERT_TRUE(clean.ok());
  EXPECT_LT((clean.value() - point.head<2>()).norm(), 1e-4f);

  ranges[3] += 1.5f;  // only the subset without anchor 3 fits
  const auto named = MultilaterateOnPlaneRobust<float>(anchors, ranges, arena.tag_height_m, 0.3f);
  ASSERT_TRUE(named.ok());
  EXPECT_LT((named.value() - point.head<2>()).norm(), 1e-4f);

  ranges[3] -= 1.5f;
  ranges[1] += 1.5f;  // from here two subsets fit: which range is wrong cannot be told
  EXPECT_EQ(MultilaterateOnPlaneRobust<float>(anchors, ranges, arena.tag_height_m, 0.3f).error(),
            EstimationError::kInconsistentRanges);
  // Three ranges can show an outlier but not name it.
  EXPECT_EQ(MultilaterateOnPlaneRobust<float>(anchors.first(3), std::span<const float>(ranges, 3), arena.tag_height_m,
                                              0.3f)
                .error(),
            EstimationError::kInconsistentRanges);
}

TEST(MultilaterateOnPlaneTest, RefusesCollinearAnchorsAndTooFewRanges) {
  const Vector3<double> collinear[3] = {{0, 0, 0}, {1, 1, 2}, {3, 3, 0}};
  const double ranges[3] = {1, 1, 2};
  EXPECT_EQ(MultilaterateOnPlane<double>(collinear, ranges, 0.1).error(), EstimationError::kDegenerateGeometry);
  EXPECT_EQ(MultilaterateOnPlane<double>(std::span<const Vector3<double>>(collinear, 2),
                                         std::span<const double>(ranges, 2), 0.1)
                .error(),
            EstimationError::kTooFewAnchors);
}

}  // namespace
}  // namespace syrof::estimation
