// The typed wrappers, driven by real tasks on the simulation port: the way
// robot code uses the broker.
#include "syrof/pubsub/topic.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "recording_port.h"
#include "syrof/os/sim_port.h"

namespace syrof::pubsub {
namespace {

constexpr int64_t kMillisecond = 1'000'000;

struct ImuSample {
  int64_t time_ns;
  float gyro_z_rad_s;
};
struct RangeSample {
  int64_t time_ns;
  uint8_t anchor;
  float range_m;
};

constexpr Topic<ImuSample> kImuTopic{1, "imu"};
constexpr Topic<RangeSample> kRangeTopic{2, "range"};

// Publishes one IMU sample per step, and every fourth step a burst of four
// ranges (one per anchor), as a UWB driver would.
class DriverTask final : public os::Task {
 public:
  void Step(int64_t now_ns) override {
    EXPECT_EQ(imu.Publish(ImuSample{now_ns, 0.5f * static_cast<float>(steps_)}), BrokerError::kOk);
    if (steps_ % 4 == 0) {
      for (uint8_t anchor = 0; anchor < 4; ++anchor) {
        EXPECT_EQ(ranges.Publish(RangeSample{now_ns, anchor, 1.0f + anchor}), BrokerError::kOk);
      }
    }
    ++steps_;
  }
  Publisher<ImuSample> imu;
  Publisher<RangeSample> ranges;

 private:
  int steps_ = 0;
};

// Collects everything it is notified of, like the paper's state task.
class StateTask final : public os::Task {
 public:
  void Step(int64_t now_ns) override {
    ++activations;
    ImuSample imu_sample{};
    while (imu.Take(imu_sample)) {
      EXPECT_EQ(imu_sample.time_ns, now_ns);  // delivered at the instant it was published
      imu_samples.push_back(imu_sample);
    }
    RangeSample range{};
    while (ranges.Take(range)) range_samples.push_back(range);
  }
  Subscriber<ImuSample, 2> imu;
  Subscriber<RangeSample, 8> ranges;
  int activations = 0;
  std::vector<ImuSample> imu_samples;
  std::vector<RangeSample> range_samples;
};

TEST(TopicTest, DriverAndStateTaskExchangeTypedTuplesInVirtualTime) {
  os::SimScheduler scheduler(4);
  os::SimPort port(scheduler, "robot");
  StaticBroker<4, 4> broker(port);
  DriverTask driver;
  StateTask state;
  ASSERT_TRUE(port.AddTask(driver, {"driver", os::Trigger::periodic(10 * kMillisecond), 2}));
  const os::TaskId state_id = port.AddTask(state, {"state", os::Trigger::notified(), 1}).value();
  ASSERT_EQ(driver.imu.Advertise(broker, kImuTopic), BrokerError::kOk);
  ASSERT_EQ(driver.ranges.Advertise(broker, kRangeTopic), BrokerError::kOk);
  ASSERT_EQ(state.imu.Subscribe(broker, kImuTopic, state_id), BrokerError::kOk);
  ASSERT_EQ(state.ranges.Subscribe(broker, kRangeTopic, state_id), BrokerError::kOk);
  ASSERT_EQ(port.Start(), os::PortError::kOk);

  scheduler.RunUntil(79 * kMillisecond);

  // One activation per driver step although two topics arrive together.
  EXPECT_EQ(state.activations, 8);
  ASSERT_EQ(state.imu_samples.size(), 8u);
  for (size_t i = 0; i < state.imu_samples.size(); ++i) {
    EXPECT_EQ(state.imu_samples[i].time_ns, static_cast<int64_t>(i) * 10 * kMillisecond);
    EXPECT_FLOAT_EQ(state.imu_samples[i].gyro_z_rad_s, 0.5f * static_cast<float>(i));
  }
  ASSERT_EQ(state.range_samples.size(), 8u);
  for (size_t i = 0; i < state.range_samples.size(); ++i) {
    EXPECT_EQ(state.range_samples[i].anchor, i % 4);
  }
  EXPECT_EQ(state.imu.overwritten(), 0u);
  EXPECT_EQ(broker.published(driver.imu.index()), 8u);
}

TEST(TopicTest, PublishBeforeAdvertiseAndTakeBeforeSubscribeFailCleanly) {
  Publisher<ImuSample> publisher;
  Subscriber<ImuSample> subscriber;
  ImuSample sample{};

  EXPECT_EQ(publisher.Publish(sample), BrokerError::kUnregisteredIndex);
  EXPECT_FALSE(subscriber.Take(sample));
  EXPECT_FALSE(subscriber.TakeLatest(sample));
  EXPECT_FALSE(publisher.advertised());
  EXPECT_FALSE(subscriber.subscribed());
}

TEST(TopicTest, AdvertiseAndSubscribeReportBrokerErrors) {
  os::SimScheduler scheduler(1);
  os::SimPort port(scheduler);
  StaticBroker<1, 1> broker(port);
  Publisher<ImuSample> first, second;
  Subscriber<ImuSample> a, b;
  Subscriber<RangeSample> wrong_topic;

  ASSERT_EQ(first.Advertise(broker, kImuTopic), BrokerError::kOk);
  EXPECT_EQ(second.Advertise(broker, kImuTopic), BrokerError::kDuplicatePublisher);
  EXPECT_EQ(wrong_topic.Subscribe(broker, kRangeTopic, 0), BrokerError::kUnknownTopic);
  ASSERT_EQ(a.Subscribe(broker, kImuTopic, 0), BrokerError::kOk);
  EXPECT_EQ(b.Subscribe(broker, kImuTopic, 0), BrokerError::kCapacityExhausted);
  EXPECT_FALSE(b.subscribed());
}

}  // namespace
}  // namespace syrof::pubsub
