#include "syrof/lab/sensors/gaussian.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace syrof::lab::sensors {
namespace {

constexpr int kSamples = 2'000'000;

// P(|X| > t) for a standard normal.
double TwoSidedTail(double t) { return std::erfc(t / std::sqrt(2.0)); }

TEST(GaussianSourceTest, MomentsMatchTheStandardNormal) {
  GaussianSource source(11);
  double sum = 0, sum2 = 0, sum3 = 0, sum4 = 0;

  for (int i = 0; i < kSamples; ++i) {
    const double x = source.Next();
    sum += x;
    sum2 += x * x;
    sum3 += x * x * x;
    sum4 += x * x * x * x;
  }

  // Standard errors at 2e6 samples: mean 7e-4, variance 1e-3, third moment
  // 1.7e-3, fourth 7e-3; the bounds are about five of them.
  EXPECT_NEAR(sum / kSamples, 0.0, 0.004);
  EXPECT_NEAR(sum2 / kSamples, 1.0, 0.005);
  EXPECT_NEAR(sum3 / kSamples, 0.0, 0.01);
  EXPECT_NEAR(sum4 / kSamples, 3.0, 0.04);
}

TEST(GaussianSourceTest, TailsHaveTheRightWeightIncludingBeyondTheBaseLayer) {
  GaussianSource source(12);
  int beyond_one = 0, beyond_two = 0, beyond_tail_start = 0, beyond_four = 0;

  for (int i = 0; i < kSamples; ++i) {
    const double magnitude = std::fabs(source.Next());
    beyond_one += magnitude > 1.0;
    beyond_two += magnitude > 2.0;
    beyond_tail_start += magnitude > 3.442619855899;  // drawn by the tail method
    beyond_four += magnitude > 4.0;
  }

  const auto fraction = [](int count) { return static_cast<double>(count) / kSamples; };
  EXPECT_NEAR(fraction(beyond_one), TwoSidedTail(1.0), 0.0015);
  EXPECT_NEAR(fraction(beyond_two), TwoSidedTail(2.0), 0.0008);
  EXPECT_NEAR(fraction(beyond_tail_start), TwoSidedTail(3.442619855899), 1.2e-4);  // expected 5.8e-4
  EXPECT_NEAR(fraction(beyond_four), TwoSidedTail(4.0), 4e-5);                     // expected 6.3e-5
  EXPECT_GT(beyond_four, 0);
}

TEST(GaussianSourceTest, BothSignsAndTheWedgesAreUsed) {
  GaussianSource source(13);
  int negative = 0;
  // Values just below a layer edge come only from the wedge test; a
  // histogram in a narrow band around 1.0 checks the density there.
  int near_one = 0;

  for (int i = 0; i < kSamples; ++i) {
    const double x = source.Next();
    negative += x < 0;
    near_one += x > 0.99 && x < 1.01;
  }

  EXPECT_NEAR(static_cast<double>(negative) / kSamples, 0.5, 0.002);
  const double expected = 0.02 * std::exp(-0.5) / std::sqrt(2.0 * 3.14159265358979) * kSamples;  // ~9,680
  EXPECT_NEAR(near_one, expected, 5 * std::sqrt(expected));
}

TEST(GaussianSourceTest, SameSeedSameNumbersOtherSeedOthers) {
  GaussianSource a(5), b(5), c(6);
  bool all_same_as_c = true;
  for (int i = 0; i < 1000; ++i) {
    const double from_a = a.Next();
    EXPECT_EQ(from_a, b.Next());
    all_same_as_c = all_same_as_c && from_a == c.Next();
  }
  EXPECT_FALSE(all_same_as_c);
}

}  // namespace
}  // namespace syrof::lab::sensors
