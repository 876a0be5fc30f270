#include "syrof/wire/fixed_point.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace syrof::wire {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kPi = 3.14159265358979f;

TEST(ToMillimetresTest, RoundsToNearestTiesAwayFromZero) {
  EXPECT_EQ(ToMillimetres(1.2344f), 1234);
  EXPECT_EQ(ToMillimetres(1.2346f), 1235);
  EXPECT_EQ(ToMillimetres(0.0625f), 63);
  EXPECT_EQ(ToMillimetres(-0.0625f), -63);
  EXPECT_EQ(ToMillimetres(0.0f), 0);
}

TEST(ToMillimetresTest, SaturatesAtTheInt16Bounds) {
  EXPECT_EQ(ToMillimetres(32.767f), 32767);
  EXPECT_EQ(ToMillimetres(40.0f), 32767);
  EXPECT_EQ(ToMillimetres(-32.768f), -32768);
  EXPECT_EQ(ToMillimetres(-1.0e9f), -32768);
  EXPECT_EQ(ToMillimetres(kInfinity), 32767);
  EXPECT_EQ(ToMillimetres(-kInfinity), -32768);
}

TEST(ToMillimetresTest, MapsNaNToZero) { EXPECT_EQ(ToMillimetres(kNaN), 0); }

TEST(ToMillimetresPerSecondTest, RoundsAndSaturates) {
  EXPECT_EQ(ToMillimetresPerSecond(0.25f), 250);
  EXPECT_EQ(ToMillimetresPerSecond(-100.0f), -32768);
  EXPECT_EQ(ToMillimetresPerSecond(kNaN), 0);
}

TEST(ToMilliradiansTest, KeepsAnglesWithinPi) {
  EXPECT_EQ(ToMilliradians(0.5f), 500);
  EXPECT_EQ(ToMilliradians(-1.0f), -1000);
  EXPECT_EQ(ToMilliradians(kPi), 3142);
  EXPECT_EQ(ToMilliradians(-kPi), -3142);
}

TEST(ToMilliradiansTest, WrapsAnglesBeyondPi) {
  EXPECT_EQ(ToMilliradians(2.0f * kPi + 0.5f), 500);
  EXPECT_EQ(ToMilliradians(-2.0f * kPi - 0.5f), -500);
  EXPECT_EQ(ToMilliradians(kPi + 0.5f), ToMilliradians(-kPi + 0.5f));
}

TEST(ToMilliradiansTest, StaysInTheWireRangeForAnyAngle) {
  for (float radians = -100.0f; radians <= 100.0f; radians += 0.001f) {
    const int16_t milliradians = ToMilliradians(radians);
    ASSERT_GE(milliradians, -3142) << radians;
    ASSERT_LE(milliradians, 3142) << radians;
  }
}

TEST(ToMilliradiansTest, MapsNonFiniteToZero) {
  EXPECT_EQ(ToMilliradians(kNaN), 0);
  EXPECT_EQ(ToMilliradians(kInfinity), 0);
  EXPECT_EQ(ToMilliradians(-kInfinity), 0);
}

TEST(FromFixedPointTest, DividesByAThousand) {
  EXPECT_FLOAT_EQ(ToMetres(-1500), -1.5f);
  EXPECT_FLOAT_EQ(ToMetresPerSecond(250), 0.25f);
  EXPECT_FLOAT_EQ(ToRadians(3142), 3.142f);
}

TEST(FromFixedPointTest, RoundTripsEveryMillimetreValue) {
  for (int millimetres = -32768; millimetres <= 32767; ++millimetres) {
    const auto value = static_cast<int16_t>(millimetres);
    ASSERT_EQ(ToMillimetres(ToMetres(value)), value);
  }
}

}  // namespace
}  // namespace syrof::wire
