#include "syrof/estimation/imu_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace syrof::estimation {
namespace {

TEST(ImuModelTest, ConvertsGToMetresPerSecondSquaredWithThePapersG) {
  EXPECT_DOUBLE_EQ(MetresPerSecondSquaredFromG(1.0), 9.81);
  EXPECT_DOUBLE_EQ(MetresPerSecondSquaredFromG(-0.5), -4.905);
  EXPECT_FLOAT_EQ(MetresPerSecondSquaredFromG(2.0f), 19.62f);
}

TEST(ImuModelTest, ConvertsDegreesPerSecondToRadiansPerSecond) {
  EXPECT_DOUBLE_EQ(RadiansPerSecondFromDegrees(180.0), kPi<double>);
  EXPECT_DOUBLE_EQ(RadiansPerSecondFromDegrees(-90.0), -kPi<double> / 2);
  EXPECT_FLOAT_EQ(RadiansPerSecondFromDegrees(57.29578f), 1.0f);
}

TEST(ImuModelTest, ConvertsEveryAxisOfAReading) {
  const ImuReading reading{123, {0.1f, -0.2f, 1.0f}, {1.0f, -2.0f, 90.0f}};
  const auto sample = ConvertImuReading<double>(reading);
  ASSERT_TRUE(sample.ok());
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_DOUBLE_EQ(sample.value().accel_mps2[axis], static_cast<double>(reading.accel_g[axis]) * 9.81);
    EXPECT_DOUBLE_EQ(sample.value().rate_radps[axis], static_cast<double>(reading.gyro_dps[axis]) * kPi<double> / 180);
  }
  const ImuInput<double> input = PlanarImuInput(sample.value());
  EXPECT_DOUBLE_EQ(input.accel_forward_mps2, sample.value().accel_mps2[0]);
  EXPECT_DOUBLE_EQ(input.accel_left_mps2, sample.value().accel_mps2[1]);
  EXPECT_DOUBLE_EQ(input.yaw_rate_radps, kPi<double> / 2);
}

TEST(ImuModelTest, RefusesNonFiniteReadings) {
  ImuReading reading{0, {0, 0, 1}, {0, 0, 0}};
  reading.gyro_dps[2] = std::nanf("");
  EXPECT_EQ(ConvertImuReading<float>(reading).error(), EstimationError::kInvalidMeasurement);
  reading.gyro_dps[2] = 0;
  reading.accel_g[0] = INFINITY;
  EXPECT_EQ(ConvertImuReading<float>(reading).error(), EstimationError::kInvalidMeasurement);
}

}  // namespace
}  // namespace syrof::estimation
