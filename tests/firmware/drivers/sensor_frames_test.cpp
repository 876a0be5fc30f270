// The sensor link's conversions between frames and the estimator's and the
// motion task's messages (sensor_frames.h).
#include "syrof/firmware/drivers/sensor_frames.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace syrof::firmware::drivers {
namespace {

TEST(SensorFramesTest, ImuAndFlowKeepEveryValueAndTakeTheReceiversTime) {
  const estimation::ImuReading imu{123, {0.1f, -0.2f, 0.98f}, {1.5f, -2.5f, 90.0f}};
  const estimation::ImuReading back = ToReading(ToPayload(imu), 777);
  EXPECT_EQ(back.timestamp_ns, 777);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(back.accel_g[i], imu.accel_g[i]);
    EXPECT_EQ(back.gyro_dps[i], imu.gyro_dps[i]);
  }
  const estimation::FlowReading flow{5, 20'000'000, -12, 40};
  const estimation::FlowReading flow_back = ToReading(ToPayload(flow), 9);
  EXPECT_EQ(flow_back.timestamp_ns, 9);
  EXPECT_EQ(flow_back.interval_ns, flow.interval_ns);
  EXPECT_EQ(flow_back.delta_x_px, -12);
  EXPECT_EQ(flow_back.delta_y_px, 40);
}

TEST(SensorFramesTest, UwbRangesAreWholeMillimetresAndOutOfRangeOnesAreNotValid) {
  estimation::UwbReading uwb{};
  uwb.range_m[0] = 1.23449f;
  uwb.range_m[1] = 70.0f;  // beyond 65.535 m
  uwb.range_m[2] = std::numeric_limits<float>::quiet_NaN();
  uwb.range_m[3] = 2.0f;
  uwb.range_m[4] = 3.0f;  // its bit is clear
  uwb.valid_mask = 0x0F;
  uwb.sweep = 0x1234;
  const UwbPayload payload = ToPayload(uwb);
  EXPECT_EQ(payload.valid_mask, 0x09);
  EXPECT_EQ(payload.sweep, 0x34);
  EXPECT_EQ(payload.range_mm[0], 1234);
  EXPECT_EQ(payload.range_mm[1], 0);
  EXPECT_EQ(payload.range_mm[4], 0);
  const estimation::UwbReading back = ToReading(payload, 50);
  EXPECT_EQ(back.valid_mask, 0x09u);
  EXPECT_NEAR(back.range_m[0], 1.234f, 1e-6f);
  EXPECT_EQ(back.range_m[3], 2.0f);
  EXPECT_EQ(back.range_m[1], 0.0f);
}

TEST(SensorFramesTest, DriveRoundTripsAndANonFiniteCommandBecomesAStop) {
  motion::DriveCommand command;
  command.kind = motion::DriveKind::kWheels;
  command.left_mps = 0.3f;
  command.right_mps = -0.1f;
  const motion::DriveCommand back = ToCommand(ToPayload(command), 42);
  EXPECT_EQ(back.timestamp_ns, 42);
  EXPECT_EQ(back.kind, motion::DriveKind::kWheels);
  EXPECT_EQ(back.left_mps, 0.3f);
  EXPECT_EQ(back.right_mps, -0.1f);
  command.vx_mps = std::numeric_limits<float>::infinity();
  const DrivePayload stop = ToPayload(command);
  EXPECT_EQ(stop.kind, 1);
  EXPECT_EQ(stop.left_mps, 0.0f);
  EXPECT_EQ(stop.vx_mps, 0.0f);
}

}  // namespace
}  // namespace syrof::firmware::drivers
