// The robot's receive edge under a concurrent producer: a thread feeds frames
// through ReceiveBytes (as a DDS listener or a UART interrupt would) while
// the robot's tasks run on the POSIX port. Run it under ThreadSanitizer with
// `make tsan`.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string_view>
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
  std::array<wire::Beacon, Robot::kReceiveBanks * kSwarm> storage{};  // a swarm's worth per bank
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
  std::array<wire::Beacon, Robot::kReceiveBanks * kSwarm> storage{};
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

// A port the test drives by hand, on one thread: it steps the round task at
// the times it chooses, and after each Unlock() it may run a hook, as if a
// producer thread took the lock the moment the round task let go of it.
class InterleavingPort final : public os::Port {
 public:
  base::Result<os::TaskId, os::PortError> AddTask(os::Task& task, const os::TaskConfig& config) override {
    if (std::string_view(config.name) == "runtime.round") round_task = &task;
    return base::Result<os::TaskId, os::PortError>(static_cast<os::TaskId>(next_id_++));
  }
  os::PortError Start() override { return os::PortError::kOk; }
  os::PortError Stop() override { return os::PortError::kOk; }
  void Notify(os::TaskId) override {}
  int64_t now_ns() const override { return now; }
  void Lock() override {}
  void Unlock() override {
    if (after_unlock && !in_hook_) {
      in_hook_ = true;
      after_unlock();
      in_hook_ = false;
    }
  }

  os::Task* round_task = nullptr;
  int64_t now = 0;
  std::function<void()> after_unlock;

 private:
  size_t next_id_ = 0;
  bool in_hook_ = false;
};

// A beacon that arrives at a round's boundary is stepped the round after,
// from the bank it was received in. A producer that writes the moment the
// next swap releases the lock must not write over it: with two banks it
// did (the bank holding the deferred beacon was the next to receive), and
// the step saw the producer's frame in its place.
TEST(RobotReceiveEdgeTest, ABeaconDeferredAtABoundarySurvivesAProducerWritingAfterTheNextSwap) {
  InterleavingPort port;
  pubsub::StaticBroker<8, 12> broker{port};
  pubsub::Publisher<estimation::ImuReading> imu;
  pubsub::Publisher<estimation::FlowReading> flow;
  pubsub::Publisher<estimation::UwbReading> uwb;
  ASSERT_EQ(imu.Advertise(broker, estimation::kImuTopic), pubsub::BrokerError::kOk);
  ASSERT_EQ(flow.Advertise(broker, estimation::kFlowTopic), pubsub::BrokerError::kOk);
  ASSERT_EQ(uwb.Advertise(broker, estimation::kUwbTopic), pubsub::BrokerError::kOk);

  RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(kSwarm, 0);
  config.radio_round_ns = kRoundNs;
  config.maneuver_rounds = 4;
  IdleApp app;
  CountingRadio radio;
  std::array<wire::Beacon, Robot::kReceiveBanks * kSwarm> storage{};
  Robot robot(config, app, radio, storage);
  ASSERT_EQ(robot.Attach(port, broker), RobotSetupError::kOk);
  ASSERT_NE(port.round_task, nullptr);

  const auto frame_from = [](uint16_t sender, bool presence_only) {
    wire::Beacon beacon;
    beacon.robot_id = sender;
    beacon.presence_only = presence_only;
    Frame frame;
    const auto size = wire::Encode(beacon, kSwarm, frame.bytes);
    EXPECT_TRUE(size.ok());
    frame.size = size.value();
    return frame;
  };
  const Frame from_one = frame_from(1, false);
  const Frame from_two = frame_from(2, false);
  const Frame presence = frame_from(3, true);
  const auto receive = [&](const Frame& frame) {
    robot.ReceiveBytes(std::span<const uint8_t>(frame.bytes.data(), frame.size));
  };

  // Robot 1's beacon arrives exactly at the first boundary: deferred.
  port.now = kRoundNs;
  receive(from_one);
  port.round_task->Step(kRoundNs);
  EXPECT_EQ(robot.counters().beacons_deferred, 1u);
  EXPECT_EQ(robot.counters().beacons_stepped, 0u);

  // Robot 2's beacon arrives within the second round; at its boundary a
  // producer writes presence reports after every unlock, the swap's too.
  port.now = kRoundNs + kRoundNs / 2;
  receive(from_two);
  port.now = 2 * kRoundNs;
  port.after_unlock = [&] { receive(presence); };
  port.round_task->Step(2 * kRoundNs);
  port.after_unlock = nullptr;

  // Both robots' beacons were stepped: the deferred one was not replaced.
  EXPECT_EQ(robot.counters().beacons_stepped, 2u);
}

// With alignment, a beacon belongs to the round whose boundary it follows
// by the link's delay give or take half a round. A DDS robot sends right
// after its boundary, so a sender 250 us early (its beacon arrives 100 us
// before this robot's boundary, the link's delay being 150 us) sent the
// beacon of the round now ending, and it is stepped in the next round; at
// the boundary alone it was stepped a round early, and the sender then
// looked silent for the round after (the DDS swarm with --align-rounds lost
// COOPERATIVE epochs that way). Without alignment the split stays at the
// boundary.
TEST(RobotReceiveEdgeTest, WithAlignmentABeaconJustBeforeTheBoundaryBelongsToTheNextRound) {
  for (const bool align : {false, true}) {
    SCOPED_TRACE(align ? "aligned" : "not aligned");
    InterleavingPort port;
    pubsub::StaticBroker<8, 12> broker{port};
    pubsub::Publisher<estimation::ImuReading> imu;
    pubsub::Publisher<estimation::FlowReading> flow;
    pubsub::Publisher<estimation::UwbReading> uwb;
    ASSERT_EQ(imu.Advertise(broker, estimation::kImuTopic), pubsub::BrokerError::kOk);
    ASSERT_EQ(flow.Advertise(broker, estimation::kFlowTopic), pubsub::BrokerError::kOk);
    ASSERT_EQ(uwb.Advertise(broker, estimation::kUwbTopic), pubsub::BrokerError::kOk);

    RobotConfig config;
    config.sync = sync::SyncConfig::ForSwarm(kSwarm, 0);
    config.radio_round_ns = kRoundNs;
    config.maneuver_rounds = 4;
    config.align_rounds = align;
    config.beacon_delay_ns = 150'000;
    IdleApp app;
    CountingRadio radio;
    std::array<wire::Beacon, Robot::kReceiveBanks * kSwarm> storage{};
    Robot robot(config, app, radio, storage);
    ASSERT_EQ(robot.Attach(port, broker), RobotSetupError::kOk);
    ASSERT_NE(port.round_task, nullptr);
    const auto receive_from = [&](uint16_t sender) {
      wire::Beacon beacon;
      beacon.robot_id = sender;
      Frame frame;
      const auto size = wire::Encode(beacon, kSwarm, frame.bytes);
      ASSERT_TRUE(size.ok());
      robot.ReceiveBytes(std::span<const uint8_t>(frame.bytes.data(), size.value()));
    };

    // Robot 2's beacon arrives mid-round, robot 1's 100 us before the boundary.
    port.now = kRoundNs / 2;
    receive_from(2);
    port.now = kRoundNs - 100'000;
    receive_from(1);
    port.now = kRoundNs + 300'000;  // the round task wakes a little late
    port.round_task->Step(kRoundNs);

    EXPECT_EQ(robot.counters().beacons_stepped, align ? 1u : 2u);
    EXPECT_EQ(robot.counters().beacons_deferred, align ? 1u : 0u);
    port.now = 2 * kRoundNs + 300'000;
    port.round_task->Step(2 * kRoundNs);
    EXPECT_EQ(robot.counters().beacons_stepped, 2u);
  }
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
