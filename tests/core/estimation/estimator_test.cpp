// The state and Kalman tasks on the broker, run by the simulation port, fed
// by a scripted driver task that publishes exact readings.
#include "syrof/estimation/estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "syrof/registry/tasks.h"
#include "syrof/estimation/topics.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"

namespace syrof::estimation {
namespace {

constexpr int64_t kMillisecond = 1'000'000;

// A robot standing at (x, y) facing `heading`, as its drivers would report
// it: IMU every 10 ms, flow every 20 ms, a UWB sweep every 100 ms, all
// without noise. A range can be corrupted to test the gate.
class StandingRobotDrivers final : public os::Task {
 public:
  StandingRobotDrivers(const Arena<float>& arena, float x, float y) : arena_(arena), x_(x), y_(y) {}

  void Step(int64_t now_ns) override {
    if (imu_enabled) {
      EXPECT_EQ(imu.Publish(ImuReading{now_ns, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}}), pubsub::BrokerError::kOk);
    }
    if (now_ns % registry::kFlowPeriodNs == 0) {
      EXPECT_EQ(flow.Publish(FlowReading{now_ns, 20'000'000, 0, 0}), pubsub::BrokerError::kOk);
    }
    if (uwb_enabled && now_ns % registry::kUwbPeriodNs == 0) {
      UwbReading sweep{};
      sweep.timestamp_ns = now_ns;
      for (int i = 0; i < arena_.anchor_count; ++i) {
        const float dx = x_ - arena_.anchors[i][0];
        const float dy = y_ - arena_.anchors[i][1];
        const float dz = arena_.tag_height_m - arena_.anchors[i][2];
        sweep.range_m[i] = std::sqrt(dx * dx + dy * dy + dz * dz);
        sweep.valid_mask |= 1u << i;
      }
      if (now_ns == corrupt_at_ns) sweep.range_m[corrupt_anchor] += 1.5f;
      sweep.sweep = sweeps_++;
      EXPECT_EQ(uwb.Publish(sweep), pubsub::BrokerError::kOk);
    }
  }

  pubsub::Publisher<ImuReading> imu;
  pubsub::Publisher<FlowReading> flow;
  pubsub::Publisher<UwbReading> uwb;
  bool imu_enabled = true;
  bool uwb_enabled = true;
  int64_t corrupt_at_ns = -1;
  int corrupt_anchor = 0;

 private:
  const Arena<float>& arena_;
  float x_;
  float y_;
  uint32_t sweeps_ = 0;
};

// Records every published estimate.
class EstimateRecorder final : public os::Task {
 public:
  void Step(int64_t /*now_ns*/) override {
    StateEstimate estimate{};
    while (estimates.Take(estimate)) {
      if (count == 0) first = estimate;
      last = estimate;
      ++count;
    }
  }
  pubsub::Subscriber<StateEstimate, 4> estimates;
  StateEstimate first{};
  StateEstimate last{};
  int count = 0;
};

class EstimatorTest : public ::testing::Test {
 protected:
  EstimatorTest() : port_(scheduler_, "robot"), broker_(port_), drivers_(arena_, 1.5f, 2.5f) {}

  void Wire(Estimator<float>& estimator) {
    ASSERT_TRUE(port_.AddTask(drivers_, {"drivers", os::Trigger::periodic(10 * kMillisecond), registry::kSensorTaskPriority}));
    ASSERT_EQ(drivers_.imu.Advertise(broker_, kImuTopic), pubsub::BrokerError::kOk);
    ASSERT_EQ(drivers_.flow.Advertise(broker_, kFlowTopic), pubsub::BrokerError::kOk);
    ASSERT_EQ(drivers_.uwb.Advertise(broker_, kUwbTopic), pubsub::BrokerError::kOk);
    ASSERT_EQ(estimator.Attach(port_, broker_), EstimatorSetupError::kOk);
    const auto recorder_id = port_.AddTask(recorder_, {"recorder", os::Trigger::notified(), 0});
    ASSERT_TRUE(recorder_id);
    ASSERT_EQ(recorder_.estimates.Subscribe(broker_, kStateEstimateTopic, recorder_id.value()), pubsub::BrokerError::kOk);
  }

  const Arena<float> arena_ = DefaultArena<float>();
  os::SimScheduler scheduler_{8};
  os::SimPort port_;
  pubsub::StaticBroker<8, 8> broker_;
  StandingRobotDrivers drivers_;
  EstimateRecorder recorder_;
};

TEST_F(EstimatorTest, PlacesItselfFromTheFirstSweepAndPublishesAtOneHundredHertz) {
  EstimatorConfig<float> config;
  config.initial_heading_rad = 0.3f;
  Estimator<float> estimator(config);
  Wire(estimator);
  ASSERT_EQ(port_.Start(), os::PortError::kOk);
  scheduler_.RunUntil(1000 * kMillisecond);

  // Steps at 0, 10, ..., 1000 ms; the sweep at 0 ms is collected by the
  // state task before the Kalman task's first step at the same instant.
  EXPECT_EQ(recorder_.count, 101);
  EXPECT_EQ(recorder_.first.timestamp_ns, 0);
  EXPECT_NE(recorder_.first.status & kEstimateInitialized, 0u);
  EXPECT_NEAR(recorder_.first.x_m, 1.5f, 1e-3f);
  EXPECT_NEAR(recorder_.first.y_m, 2.5f, 1e-3f);
  EXPECT_EQ(recorder_.last.timestamp_ns, 1000 * kMillisecond);
  EXPECT_NEAR(recorder_.last.x_m, 1.5f, 1e-3f);
  EXPECT_NEAR(recorder_.last.y_m, 2.5f, 1e-3f);
  EXPECT_NEAR(recorder_.last.heading_rad, 0.3f, 1e-3f);
  EXPECT_LT(recorder_.last.sigma_x_m, 0.1f);
  EXPECT_EQ(recorder_.last.status, static_cast<uint32_t>(kEstimateInitialized));
  // Sweeps at 100 .. 1000 ms are fused (the one at 0 placed the robot).
  EXPECT_EQ(estimator.counters().ranges_fused, 40u);
  EXPECT_EQ(estimator.counters().ranges_rejected, 0u);
  EXPECT_EQ(estimator.counters().flow_fused, 51u);
  EXPECT_EQ(estimator.counters().imu_samples, 101u);
  EXPECT_EQ(estimator.counters().steps, 101u);
  EXPECT_EQ(estimator.counters().readings_dropped, 0u);
  EXPECT_EQ(estimator.last_estimate().timestamp_ns, recorder_.last.timestamp_ns);
  EXPECT_EQ(estimator.last_estimate().ranges_fused, 40u);
}

TEST_F(EstimatorTest, GateRejectsACorruptedRangeAndKeepsThePosition) {
  Estimator<float> estimator;
  drivers_.corrupt_at_ns = 500 * kMillisecond;
  drivers_.corrupt_anchor = 2;
  Wire(estimator);
  ASSERT_EQ(port_.Start(), os::PortError::kOk);
  scheduler_.RunUntil(1000 * kMillisecond);
  EXPECT_EQ(estimator.counters().ranges_rejected, 1u);
  EXPECT_EQ(estimator.counters().ranges_fused, 39u);
  EXPECT_EQ(recorder_.last.ranges_rejected, 1u);
  EXPECT_NEAR(recorder_.last.x_m, 1.5f, 1e-3f);
  EXPECT_NEAR(recorder_.last.y_m, 2.5f, 1e-3f);
}

TEST_F(EstimatorTest, UsesAGivenPoseAndReportsAMissingImu) {
  Estimator<float> estimator;
  drivers_.imu_enabled = false;
  Wire(estimator);
  InitialPose<float> pose;
  pose.x_m = 1.6f;  // 10 cm off
  pose.y_m = 2.5f;
  pose.heading_rad = -1.0f;
  pose.position_sigma_m = 0.2f;
  estimator.SetInitialPose(pose);
  ASSERT_EQ(port_.Start(), os::PortError::kOk);
  scheduler_.RunUntil(1000 * kMillisecond);
  EXPECT_NE(recorder_.first.status & kEstimateInitialized, 0u);
  EXPECT_NE(recorder_.last.status & kEstimateImuMissing, 0u);
  // With the pose given, every sweep is fused, the first one included.
  EXPECT_EQ(estimator.counters().ranges_fused, 44u);
  EXPECT_NEAR(recorder_.last.x_m, 1.5f, 0.01f);
  EXPECT_NEAR(recorder_.last.heading_rad, -1.0f, 1e-3f);
  EXPECT_EQ(estimator.counters().imu_samples, 0u);
}

TEST_F(EstimatorTest, PublishesUninitializedEstimatesUntilTheFirstSweep) {
  Estimator<float> estimator;
  drivers_.uwb_enabled = false;
  Wire(estimator);
  ASSERT_EQ(port_.Start(), os::PortError::kOk);
  scheduler_.RunUntil(250 * kMillisecond);
  EXPECT_EQ(recorder_.count, 26);
  EXPECT_FALSE(estimator.initialized());
  EXPECT_EQ(recorder_.last.status & kEstimateInitialized, 0u);
  drivers_.uwb_enabled = true;
  scheduler_.RunUntil(300 * kMillisecond);  // the sweep at 300 ms places the robot
  EXPECT_TRUE(estimator.initialized());
  EXPECT_NE(recorder_.last.status & kEstimateInitialized, 0u);
  EXPECT_NEAR(recorder_.last.x_m, 1.5f, 1e-3f);
}

TEST_F(EstimatorTest, TheFirstFixDropsAnOutlierItCanName) {
  Estimator<float> estimator;
  drivers_.corrupt_at_ns = 0;  // the first sweep carries an outlier on anchor 3
  drivers_.corrupt_anchor = 3;
  Wire(estimator);
  ASSERT_EQ(port_.Start(), os::PortError::kOk);
  scheduler_.RunUntil(0);
  ASSERT_TRUE(estimator.initialized());
  EXPECT_NEAR(recorder_.first.x_m, 1.5f, 1e-3f);
  EXPECT_NEAR(recorder_.first.y_m, 2.5f, 1e-3f);
  EXPECT_EQ(estimator.counters().fixes, 1u);
}

TEST_F(EstimatorTest, ASweepWithAnOutlierItCannotNamePlacesNobody) {
  Estimator<float> estimator;
  drivers_.corrupt_at_ns = 0;  // from (1.5, 2.5), two subsets fit this one
  drivers_.corrupt_anchor = 1;
  Wire(estimator);
  ASSERT_EQ(port_.Start(), os::PortError::kOk);
  scheduler_.RunUntil(0);
  EXPECT_FALSE(estimator.initialized());
  scheduler_.RunUntil(100 * kMillisecond);  // the next sweep is clean
  ASSERT_TRUE(estimator.initialized());
  EXPECT_NEAR(recorder_.last.x_m, 1.5f, 1e-3f);
  EXPECT_NEAR(recorder_.last.y_m, 2.5f, 1e-3f);
}

TEST_F(EstimatorTest, FindsItselfAgainWhenItsPoseIsWrong) {
  Estimator<float> estimator;
  Wire(estimator);
  InitialPose<float> pose;
  pose.x_m = 3.5f;  // 2 m off, and sure of it
  pose.y_m = 2.5f;
  pose.position_sigma_m = 0.05f;
  estimator.SetInitialPose(pose);
  ASSERT_EQ(port_.Start(), os::PortError::kOk);
  scheduler_.RunUntil(400 * kMillisecond);  // five sweeps, every range rejected
  EXPECT_EQ(estimator.counters().relocalizations, 1u);
  EXPECT_EQ(estimator.counters().ranges_rejected, 20u);
  EXPECT_GT(std::abs(recorder_.last.x_m - 1.5f), 1.0f);
  scheduler_.RunUntil(500 * kMillisecond);  // the sixth sweep places the robot
  EXPECT_EQ(estimator.counters().fixes, 1u);
  EXPECT_NEAR(recorder_.last.x_m, 1.5f, 1e-3f);
  EXPECT_NEAR(recorder_.last.y_m, 2.5f, 1e-3f);
}

TEST(EstimatorSetupTest, ReportsWiringMistakes) {
  os::SimScheduler scheduler(8);
  os::SimPort port(scheduler, "robot");
  pubsub::StaticBroker<8, 8> broker(port);
  Estimator<float> estimator;
  // No driver advertised the sensor topics yet.
  EXPECT_EQ(estimator.Attach(port, broker), EstimatorSetupError::kSubscribeFailed);

  os::SimScheduler other_scheduler(8);
  os::SimPort other_port(other_scheduler, "robot");
  pubsub::StaticBroker<8, 8> other_broker(other_port);
  pubsub::Publisher<ImuReading> imu;
  pubsub::Publisher<FlowReading> flow;
  pubsub::Publisher<UwbReading> uwb;
  ASSERT_EQ(imu.Advertise(other_broker, kImuTopic), pubsub::BrokerError::kOk);
  ASSERT_EQ(flow.Advertise(other_broker, kFlowTopic), pubsub::BrokerError::kOk);
  ASSERT_EQ(uwb.Advertise(other_broker, kUwbTopic), pubsub::BrokerError::kOk);
  Estimator<double> good;
  EXPECT_EQ(good.Attach(other_port, other_broker), EstimatorSetupError::kOk);
  EXPECT_EQ(good.Attach(other_port, other_broker), EstimatorSetupError::kAlreadyAttached);
  Estimator<double> second;  // the estimate topic already has its publisher
  EXPECT_EQ(second.Attach(other_port, other_broker), EstimatorSetupError::kAdvertiseFailed);

  EXPECT_STREQ(ToString(EstimatorSetupError::kSubscribeFailed), "SubscribeFailed");
  EXPECT_STREQ(ToString(EstimationError::kRejectedByGate), "RejectedByGate");
  EXPECT_STREQ(ToString(static_cast<EstimationError>(200)), "?");
}

}  // namespace
}  // namespace syrof::estimation
