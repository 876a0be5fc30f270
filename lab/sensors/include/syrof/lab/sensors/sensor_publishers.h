// Puts a SensorBank's readings on a robot's broker, on the very topics the
// firmware drivers publish (core/estimation's topics.h), and a task that
// samples a bank along a scripted trajectory.
#pragma once

#include <cstdint>

#include "syrof/estimation/messages.h"
#include "syrof/estimation/topics.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sensors/trajectory.h"
#include "syrof/os/port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/registry/tasks.h"

namespace syrof::lab::sensors {

/// A ReadingSink that publishes each reading on kImuTopic, kFlowTopic or
/// kUwbTopic.
class SensorPublishers final : public ReadingSink {
 public:
  /// Registers the three publishers. Before anyone subscribes to them (the
  /// broker registers publishers first).
  pubsub::BrokerError Advertise(pubsub::Broker& broker);

  void OnImu(const estimation::ImuReading& reading) override;
  void OnFlow(const estimation::FlowReading& reading) override;
  void OnUwb(const estimation::UwbReading& reading) override;

  /// Readings published so far, and publishes the broker refused (only
  /// before Advertise()).
  uint64_t published() const { return published_; }
  uint64_t failed() const { return failed_; }

 private:
  void Count(pubsub::BrokerError error);

  pubsub::Publisher<estimation::ImuReading> imu_;
  pubsub::Publisher<estimation::FlowReading> flow_;
  pubsub::Publisher<estimation::UwbReading> uwb_;
  uint64_t published_ = 0;
  uint64_t failed_ = 0;
};

/// A periodic task that, at every activation, evaluates the trajectory and
/// lets the bank emit what is due into the sink: the simulated drivers of one
/// robot whose path is scripted. Its period should divide every sensor
/// period (the default, 10 ms, divides the default rates).
class SimulatedSensorsTask final : public os::Task {
 public:
  SimulatedSensorsTask(const Trajectory& trajectory, SensorBank& bank, ReadingSink& sink)
      : trajectory_(trajectory), bank_(bank), sink_(sink) {}

  /// How to add this task to a port: periodic at period_ns, with the
  /// drivers' priority (syrof/registry/tasks.h).
  static os::TaskConfig Config(int64_t period_ns = registry::kImuPeriodNs);

  void Step(int64_t now_ns) override;

 private:
  const Trajectory& trajectory_;
  SensorBank& bank_;
  ReadingSink& sink_;
};

}  // namespace syrof::lab::sensors
