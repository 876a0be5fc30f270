// Simulated sensors on a robot's broker, run by the simulation port: they
// publish on the drivers' topics, and the estimator cannot tell.
#include "syrof/lab/sensors/sensor_publishers.h"

#include <gtest/gtest.h>

#include <cmath>

#include "syrof/estimation/estimator.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"

namespace syrof::lab::sensors {
namespace {

constexpr int64_t kPublishMs = 1'000'000;

class CountingTask final : public os::Task {
 public:
  void Step(int64_t /*now_ns*/) override {
    estimation::ImuReading imu_reading{};
    while (imu.Take(imu_reading)) ++imu_count;
    estimation::FlowReading flow_reading{};
    while (flow.Take(flow_reading)) ++flow_count;
    estimation::UwbReading uwb_reading{};
    while (uwb.Take(uwb_reading)) ++uwb_count;
  }
  pubsub::Subscriber<estimation::ImuReading, 4> imu;
  pubsub::Subscriber<estimation::FlowReading, 4> flow;
  pubsub::Subscriber<estimation::UwbReading, 4> uwb;
  int imu_count = 0;
  int flow_count = 0;
  int uwb_count = 0;
};

TEST(SensorPublishersTest, PublishesOnTheDriversTopicsAtTheirRates) {
  os::SimScheduler scheduler(4);
  os::SimPort port(scheduler, "robot");
  pubsub::StaticBroker<4, 4> broker(port);
  const FigureEight eight(FigureEight::Params{});
  SensorBank bank(SensorBankConfig{}, 1);
  SensorPublishers publishers;
  SimulatedSensorsTask sensors(eight, bank, publishers);
  CountingTask counter;
  ASSERT_TRUE(port.AddTask(sensors, SimulatedSensorsTask::Config()));
  const auto counter_id = port.AddTask(counter, {"counter", os::Trigger::notified(), 1});
  ASSERT_TRUE(counter_id);
  ASSERT_EQ(publishers.Advertise(broker), pubsub::BrokerError::kOk);
  ASSERT_EQ(counter.imu.Subscribe(broker, estimation::kImuTopic, counter_id.value()), pubsub::BrokerError::kOk);
  ASSERT_EQ(counter.flow.Subscribe(broker, estimation::kFlowTopic, counter_id.value()), pubsub::BrokerError::kOk);
  ASSERT_EQ(counter.uwb.Subscribe(broker, estimation::kUwbTopic, counter_id.value()), pubsub::BrokerError::kOk);
  ASSERT_EQ(port.Start(), os::PortError::kOk);
  scheduler.RunUntil(995 * kPublishMs);
  EXPECT_EQ(counter.imu_count, 100);
  EXPECT_EQ(counter.flow_count, 50);
  EXPECT_EQ(counter.uwb_count, 10);
  EXPECT_EQ(publishers.published(), 160u);
  EXPECT_EQ(publishers.failed(), 0u);
}

TEST(SensorPublishersTest, CountsReadingsPublishedBeforeAdvertising) {
  SensorPublishers publishers;
  publishers.OnImu(estimation::ImuReading{});
  EXPECT_EQ(publishers.failed(), 1u);
  EXPECT_EQ(publishers.published(), 0u);
}

TEST(SensorPublishersTest, FeedTheEstimatorOnTheSameBroker) {
  os::SimScheduler scheduler(4);
  os::SimPort port(scheduler, "robot");
  pubsub::StaticBroker<8, 8> broker(port);
  const StraightLine standing = Stationary(2.5, 1.5, 0.0);
  SensorBank bank(SensorBankConfig{}, 2);
  SensorPublishers publishers;
  SimulatedSensorsTask sensors(standing, bank, publishers);
  estimation::Estimator<float> estimator;
  ASSERT_TRUE(port.AddTask(sensors, SimulatedSensorsTask::Config()));
  ASSERT_EQ(publishers.Advertise(broker), pubsub::BrokerError::kOk);
  ASSERT_EQ(estimator.Attach(port, broker), estimation::EstimatorSetupError::kOk);
  ASSERT_EQ(port.Start(), os::PortError::kOk);
  scheduler.RunUntil(10'000 * kPublishMs);
  ASSERT_TRUE(estimator.initialized());
  EXPECT_NEAR(estimator.last_estimate().x_m, 2.5f, 0.05f);
  EXPECT_NEAR(estimator.last_estimate().y_m, 1.5f, 0.05f);
  EXPECT_EQ(estimator.counters().steps, 1001u);
}

}  // namespace
}  // namespace syrof::lab::sensors
