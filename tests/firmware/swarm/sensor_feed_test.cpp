// The swarm host's end of the sensor link: the lab's simulated readings go
// out as frames the robot decodes to the same values (UWB to the mm), and
// drive frames from the robot come back as commands.
#include "syrof/firmware/swarm/sensor_feed.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "syrof/firmware/drivers/sensor_frames.h"

namespace syrof::firmware::swarm {
namespace {

// Keeps what the bank produced and passes it on to the feed.
class Tee final : public lab::sensors::ReadingSink {
 public:
  explicit Tee(SensorFeed& feed) : feed_(feed) {}
  void OnImu(const estimation::ImuReading& r) override {
    imu.push_back(r);
    feed_.OnImu(r);
  }
  void OnFlow(const estimation::FlowReading& r) override {
    flow.push_back(r);
    feed_.OnFlow(r);
  }
  void OnUwb(const estimation::UwbReading& r) override {
    uwb.push_back(r);
    feed_.OnUwb(r);
  }
  std::vector<estimation::ImuReading> imu;
  std::vector<estimation::FlowReading> flow;
  std::vector<estimation::UwbReading> uwb;

 private:
  SensorFeed& feed_;
};

TEST(SensorFeedTest, OneSecondOfReadingsArrivesAsFramesWithTheSameValues) {
  lab::sensors::SensorBank bank(lab::sensors::SensorBankConfig{}, /*seed=*/11);
  SensorFeed feed;
  Tee tee(feed);
  lab::sensors::TrueState truth;
  truth.x_m = 1.2;
  truth.y_m = 2.7;
  truth.vx_mps = 0.1;
  for (int64_t t = 0; t <= 1'000'000'000; t += 10'000'000) bank.Sample(t, truth, tee);
  ASSERT_FALSE(tee.imu.empty());
  ASSERT_FALSE(tee.flow.empty());
  ASSERT_FALSE(tee.uwb.empty());

  drivers::FrameDecoder decoder;
  size_t imu = 0, flow = 0, uwb = 0;
  for (const uint8_t byte : feed.bytes()) {
    if (decoder.Push(byte) != drivers::DecodeEvent::kFrame) continue;
    const drivers::Frame& frame = decoder.frame();
    if (frame.kind == drivers::FrameKind::kImu) {
      ASSERT_LT(imu, tee.imu.size());
      const estimation::ImuReading reading = drivers::ToReading(frame.imu, 0);
      for (int i = 0; i < 3; ++i) EXPECT_EQ(reading.accel_g[i], tee.imu[imu].accel_g[i]);
      for (int i = 0; i < 3; ++i) EXPECT_EQ(reading.gyro_dps[i], tee.imu[imu].gyro_dps[i]);
      ++imu;
    } else if (frame.kind == drivers::FrameKind::kFlow) {
      ASSERT_LT(flow, tee.flow.size());
      EXPECT_EQ(frame.flow.delta_x_px, tee.flow[flow].delta_x_px);
      EXPECT_EQ(frame.flow.interval_ns, tee.flow[flow].interval_ns);
      ++flow;
    } else if (frame.kind == drivers::FrameKind::kUwb) {
      ASSERT_LT(uwb, tee.uwb.size());
      const estimation::UwbReading reading = drivers::ToReading(frame.uwb, 0);
      EXPECT_EQ(reading.valid_mask, tee.uwb[uwb].valid_mask);
      for (int i = 0; i < estimation::kMaxAnchors; ++i) {
        if ((reading.valid_mask & (1u << i)) != 0) {
          EXPECT_NEAR(reading.range_m[i], tee.uwb[uwb].range_m[i], 0.0005f);
        }
      }
      ++uwb;
    }
  }
  EXPECT_EQ(imu, tee.imu.size());
  EXPECT_EQ(flow, tee.flow.size());
  EXPECT_EQ(uwb, tee.uwb.size());
  EXPECT_EQ(decoder.counters().rejected, 0u);
  EXPECT_EQ(feed.counters().imu, static_cast<int64_t>(imu));
}

TEST(SensorFeedTest, DriveFramesFromTheRobotBecomeCommandsAndOtherKindsAreCounted) {
  SensorFeed feed;
  drivers::DrivePayload drive;
  drive.vx_mps = 0.2f;
  drive.yaw_rate_radps = -0.5f;
  std::vector<uint8_t> stream(drivers::kMaxWireBytes * 2);
  const size_t first = drivers::EncodeFrame(drivers::MakeHello(0), stream).value();
  const size_t second =
      drivers::EncodeFrame(drivers::MakeDrive(1, drive), std::span<uint8_t>(stream).subspan(first)).value();
  stream.resize(first + second);
  std::vector<motion::DriveCommand> commands;
  for (const uint8_t byte : stream) {
    if (auto command = feed.PushFromRobot(byte, 1234)) commands.push_back(*command);
  }
  ASSERT_EQ(commands.size(), 1u);
  EXPECT_EQ(commands[0].timestamp_ns, 1234);
  EXPECT_EQ(commands[0].vx_mps, 0.2f);
  EXPECT_EQ(commands[0].yaw_rate_radps, -0.5f);
  EXPECT_EQ(feed.counters().drives, 1);
  EXPECT_EQ(feed.counters().refused, 1);  // the Hello
}

}  // namespace
}  // namespace syrof::firmware::swarm
