// The robot's receive edge under a concurrent producer: a thread feeds frames
// through ReceiveBytes (as a DDS listener or a UART interrupt would) while
// the robot's tasks run on the POSIX port. Run it under ThreadSanitizer with
// `make tsan`.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/base/split_mix64.h"
#include "syrof/estimation/topics.h"
#include "syrof/motion/drive.h"
#include "syrof/os/posix_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/runtime/robot.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::runtime {
namespace {

constexpr uint16_t kSwarm = 4;
constexpr int64_t kRoundNs = 2'000'000;  // 2 ms: many swaps while the producer runs

class IdleApp final : public app::App {
 public:
  const char* name() const override { return "idle"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform&, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command&, const syrof_ldmap&, uint8_t&, uint32_t) override {
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }
};

class CountingRadio final : public Radio {
 public:
  void Broadcast(const wire::Beacon&) override { sent.fetch_add(1, std::memory_order_relaxed); }
  std::atomic<uint32_t> sent{0};
};

struct Frame {
  std::array<uint8_t, wire::kMaxBeaconBytes> bytes{};
  size_t size = 0;
};

// Well-formed beacons from the other robots, and malformed frames (truncated
// or with a sender outside the swarm), in a seeded order.
std::vector<Frame> MakeFrames(size_t count, size_t& malformed) {
  base::SplitMix64 random(11);
  std::vector<Frame> frames(count);
  malformed = 0;
  for (size_t i = 0; i < count; ++i) {
    wire::Beacon beacon;
    beacon.robot_id = static_cast<uint16_t>(1 + random.Next() % (kSwarm - 1));
    beacon.epoch = static_cast<uint16_t>(i);
    beacon.snapshot.x_mm = static_cast<int16_t>(random.Next() % 4000);
    Frame& frame = frames[i];
    const auto size = wire::Encode(beacon, kSwarm, frame.bytes);
    EXPECT_TRUE(size.ok());
    frame.size = size.value();
    if (random.Next() % 7 == 0) {
      frame.size /= 2;  // truncated: does not decode
      ++malformed;
    }
  }
  return frames;
}

// A robot's POSIX port and broker with the sensor topics advertised (the
// robot's estimator subscribes to them), as a robot process sets them up.
class RobotThreadsTest : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(imu.Advertise(broker, estimation::kImuTopic), pubsub::BrokerError::kOk);
    ASSERT_EQ(flow.Advertise(broker, estimation::kFlowTopic), pubsub::BrokerError::kOk);
    ASSERT_EQ(uwb.Advertise(broker, estimation::kUwbTopic), pubsub::BrokerError::kOk);
  }

  os::PosixPort port;
  pubsub::StaticBroker<8, 12> broker{port};
  pubsub::Publisher<estimation::ImuReading> imu;
  pubsub::Publisher<estimation::FlowReading> flow;
  pubsub::Publisher<estimation::UwbReading> uwb;
};

TEST_F(RobotThreadsTest, EveryFrameFromAProducerThreadIsCountedOnceWhileTheRoundTaskRuns) {
  size_t malformed = 0;
  const std::vector<Frame> frames = MakeFrames(3000, malformed);

  RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(kSwarm, 0);
  config.radio_round_ns = kRoundNs;
  config.maneuver_rounds = 4;
  IdleApp app;
  CountingRadio radio;
  std::array<wire::Beacon, 2 * kSwarm> storage{};  // two banks of a swarm's worth
  Robot robot(config, app, radio, storage);
  ASSERT_EQ(robot.Attach(port, broker), RobotSetupError::kOk);
  ASSERT_EQ(port.Start(), os::PortError::kOk);

  std::thread producer([&] {
    for (size_t i = 0; i < frames.size(); ++i) {
      robot.ReceiveBytes(std::span<const uint8_t>(frames[i].bytes.data(), frames[i].size));
      // Bursts of six (more than a bank holds) with a pause: some frames
      // overflow, most are stepped, and swaps fall inside bursts.
      if (i % 6 == 5) std::this_thread::sleep_for(std::chrono::microseconds(300));
    }
  });
  producer.join();
  // Let the round task take the last bank before stopping.
  std::this_thread::sleep_for(std::chrono::nanoseconds(50 * kRoundNs));
  ASSERT_EQ(port.Stop(), os::PortError::kOk);

  const RobotCounters& counters = robot.counters();
  EXPECT_EQ(counters.beacons_malformed, malformed);
  EXPECT_EQ(counters.beacons_received + counters.beacons_overflow, frames.size() - malformed);
  EXPECT_EQ(counters.beacons_stepped, counters.beacons_received);  // none lost or stepped twice
  EXPECT_GT(counters.beacons_received, 0u);
  EXPECT_GT(counters.rounds, 0u);
}

TEST_F(RobotThreadsTest, FramesBeyondABankInOneRoundOverflow) {
  RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(kSwarm, 0);
  config.radio_round_ns = 1'000'000'000;  // no round ends during the burst
  IdleApp app;
  CountingRadio radio;
  std::array<wire::Beacon, 2 * kSwarm> storage{};
  Robot robot(config, app, radio, storage);
  ASSERT_EQ(robot.Attach(port, broker), RobotSetupError::kOk);
  ASSERT_EQ(port.Start(), os::PortError::kOk);

  size_t malformed = 0;
  const std::vector<Frame> frames = MakeFrames(20, malformed);
  std::thread producer([&] {
    for (const Frame& frame : frames) robot.ReceiveBytes(std::span<const uint8_t>(frame.bytes.data(), frame.size));
  });
  producer.join();
  ASSERT_EQ(port.Stop(), os::PortError::kOk);

  EXPECT_EQ(robot.counters().beacons_received, kSwarm);
  EXPECT_EQ(robot.counters().beacons_overflow, frames.size() - malformed - kSwarm);
  EXPECT_EQ(robot.counters().beacons_malformed, malformed);
}

// Moves on every new round: the round task hands commands to the motion
// task, which runs on another thread on the POSIX port.
class MovingApp final : public app::App {
 public:
  const char* name() const override { return "moving"; }
  app::CallStatus Init(const syrof_app_info&, app::Platform&, uint8_t& global_state) override {
    global_state = 0;
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t&, uint32_t) override {
    command.kind = SYROF_COMMAND_MOVE_TO;
    command.x_m = 1.0f + 0.1f * static_cast<float>(ldmap.epoch % 5);
    command.y_m = 1.0f;
    command.speed_mps = 0.2f;
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap&, uint8_t&, uint32_t) override { return app::CallStatus::Ok(); }
};

TEST_F(RobotThreadsTest, CommandsCrossFromTheRoundTaskToTheMotionTaskThread) {
  RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(1, 0);  // alone: an epoch every few rounds
  config.radio_round_ns = 1'000'000;
  config.maneuver_rounds = config.sync.vote_rounds;
  MovingApp app;
  CountingRadio radio;
  Robot robot(config, app, radio);
  ASSERT_EQ(robot.Attach(port, broker), RobotSetupError::kOk);
  pubsub::Subscriber<motion::DriveCommand> drives;  // the actuator driver, polled
  ASSERT_EQ(drives.Subscribe(broker, motion::kDriveTopic, UINT16_MAX), pubsub::BrokerError::kOk);

  ASSERT_EQ(port.Start(), os::PortError::kOk);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(port.Stop(), os::PortError::kOk);

  EXPECT_GT(robot.counters().new_rounds, 5u);
  EXPECT_GT(robot.counters().end_of_rounds, 4u);
  motion::DriveCommand drive{};
  EXPECT_TRUE(drives.TakeLatest(drive));
}

}  // namespace
}  // namespace syrof::runtime
