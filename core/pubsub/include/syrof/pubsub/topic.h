// Typed wrappers over the broker: application code declares a topic once
// with its tuple type and never handles raw sizes or indices.
//
//   inline constexpr pubsub::Topic<ImuSample> kImuTopic{1, "imu"};
//   pubsub::Publisher<ImuSample> imu;          // in the driver
//   imu.Advertise(broker, kImuTopic);          // at start-up
//   imu.Publish(sample);                       // in its step
//   pubsub::Subscriber<ImuSample, 4> samples;  // in the estimator
//   samples.Subscribe(broker, kImuTopic, estimator_task_id);
//   while (samples.Take(sample)) { ... }       // in its step
#pragma once

#include <cstdint>

#include "syrof/os/port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/queue.h"

namespace syrof::pubsub {

/// A topic: its broker id and, through T, its tuple type. Declare each topic
/// once (a constexpr in a topics header) and use it on both sides.
template <typename T>
struct Topic {
  TopicId id;
  const char* name;
};

/// Publishes tuples of T on one topic.
template <typename T>
class Publisher {
 public:
  /// Registers this publisher for `topic` (RegisterPublisher).
  BrokerError Advertise(Broker& broker, Topic<T> topic) {
    const auto index = broker.RegisterPublisher(topic.id, sizeof(T), queue_);
    if (!index) return index.error();
    broker_ = &broker;
    index_ = index.value();
    return BrokerError::kOk;
  }

  /// Delivers `tuple` to every subscriber and notifies their tasks.
  /// kUnregisteredIndex before a successful Advertise.
  BrokerError Publish(const T& tuple) {
    if (broker_ == nullptr) return BrokerError::kUnregisteredIndex;
    if (const BrokerError error = broker_->Stage(index_, &tuple, sizeof(T)); error != BrokerError::kOk) return error;
    return broker_->Publish(index_);
  }

  bool advertised() const { return broker_ != nullptr; }
  PublisherIndex index() const { return index_; }

 private:
  Broker* broker_ = nullptr;
  PublisherIndex index_ = 0;
  Queue<T, 1> queue_;
};

/// Receives tuples of T from one topic into a queue of `Depth` tuples (the
/// oldest is overwritten when a slow reader lets it fill up).
template <typename T, uint16_t Depth = 1>
class Subscriber {
 public:
  /// Subscribes `task` to `topic`; the task is notified after each publish.
  BrokerError Subscribe(Broker& broker, Topic<T> topic, os::TaskId task) {
    if (const BrokerError error = broker.Subscribe(topic.id, task, queue_); error != BrokerError::kOk) return error;
    broker_ = &broker;
    return BrokerError::kOk;
  }

  /// Pops the oldest unread tuple into `out`; false if there is none.
  bool Take(T& out) { return broker_ != nullptr && broker_->Receive(queue_, &out, sizeof(T)) == BrokerError::kOk; }

  /// Pops every unread tuple, keeping the newest in `out`; false if none.
  bool TakeLatest(T& out) {
    return broker_ != nullptr && broker_->ReceiveLatest(queue_, &out, sizeof(T)) == BrokerError::kOk;
  }

  bool subscribed() const { return broker_ != nullptr; }
  uint16_t unread() const { return queue_.size(); }
  uint32_t overwritten() const { return queue_.overwritten(); }

 private:
  Broker* broker_ = nullptr;
  Queue<T, Depth> queue_;
};

}  // namespace syrof::pubsub
