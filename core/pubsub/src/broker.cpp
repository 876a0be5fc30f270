#include "syrof/pubsub/broker.h"

#include <cstring>

#include "syrof/base/check.h"

namespace syrof::pubsub {

const char* ToString(BrokerError error) {
  switch (error) {
    case BrokerError::kOk: return "ok";
    case BrokerError::kDuplicatePublisher: return "duplicate publisher id";
    case BrokerError::kUnknownTopic: return "unknown topic id";
    case BrokerError::kSizeMismatch: return "tuple size mismatch";
    case BrokerError::kCapacityExhausted: return "capacity exhausted";
    case BrokerError::kUnregisteredIndex: return "publisher index never registered";
    case BrokerError::kInvalidQueue: return "queue already attached";
    case BrokerError::kEmpty: return "no unread tuple";
  }
  return "unknown broker error";
}

base::Result<PublisherIndex, BrokerError> Broker::RegisterPublisher(TopicId id, size_t size, QueueBase& queue) {
  os::CriticalSection section(port_);
  for (size_t i = 0; i < publisher_count_; ++i) {
    if (publishers_[i].id == id) return BrokerError::kDuplicatePublisher;
  }
  if (size != queue.element_size()) return BrokerError::kSizeMismatch;
  if (queue.attached()) return BrokerError::kInvalidQueue;
  if (publisher_count_ == publishers_.size()) return BrokerError::kCapacityExhausted;
  queue.attached_ = true;
  publishers_[publisher_count_] = PublisherSlot{&queue, kNone, 0, 0, id};
  return static_cast<PublisherIndex>(publisher_count_++);
}

BrokerError Broker::Subscribe(TopicId id, os::TaskId task, QueueBase& queue) {
  os::CriticalSection section(port_);
  PublisherSlot* publisher = nullptr;
  for (size_t i = 0; i < publisher_count_; ++i) {
    if (publishers_[i].id == id) publisher = &publishers_[i];
  }
  if (publisher == nullptr) return BrokerError::kUnknownTopic;
  if (queue.element_size() != publisher->queue->element_size()) return BrokerError::kSizeMismatch;
  if (queue.attached()) return BrokerError::kInvalidQueue;
  if (subscription_count_ == subscriptions_.size()) return BrokerError::kCapacityExhausted;

  const auto index = static_cast<uint16_t>(subscription_count_++);
  subscriptions_[index] = SubscriptionSlot{&queue, kNone, task};
  queue.attached_ = true;
  // Append, so delivery follows subscription order.
  uint16_t* link = &publisher->first_subscription;
  while (*link != kNone) link = &subscriptions_[*link].next;
  *link = index;
  ++publisher->subscription_count;
  return BrokerError::kOk;
}

BrokerError Broker::Stage(PublisherIndex index, const void* tuple, size_t size) {
  if (index >= publisher_count_) return BrokerError::kUnregisteredIndex;
  QueueBase& queue = *publishers_[index].queue;
  if (size != queue.element_size()) return BrokerError::kSizeMismatch;
  os::CriticalSection section(port_);
  queue.Push(static_cast<const std::byte*>(tuple));
  return BrokerError::kOk;
}

BrokerError Broker::Publish(PublisherIndex index) {
  if (index >= publisher_count_) return BrokerError::kUnregisteredIndex;
  PublisherSlot& publisher = publishers_[index];
  bool delivered = false;
  {
    os::CriticalSection section(port_);
    QueueBase& source = *publisher.queue;
    while (source.size() > 0) {
      for (uint16_t s = publisher.first_subscription; s != kNone; s = subscriptions_[s].next) {
        subscriptions_[s].queue->Push(source.front());
      }
      source.PopFront();
      ++publisher.published;
      delivered = true;
    }
  }
  // Outside the critical section: a notified task on a threaded port may
  // start at once and take the lock to read its queue.
  if (delivered) {
    for (uint16_t s = publisher.first_subscription; s != kNone; s = subscriptions_[s].next) {
      port_.Notify(subscriptions_[s].task);
    }
  }
  return BrokerError::kOk;
}

BrokerError Broker::Receive(QueueBase& queue, void* out, size_t size) {
  if (size != queue.element_size()) return BrokerError::kSizeMismatch;
  os::CriticalSection section(port_);
  if (queue.size() == 0) return BrokerError::kEmpty;
  std::memcpy(out, queue.front(), size);
  queue.PopFront();
  return BrokerError::kOk;
}

BrokerError Broker::ReceiveLatest(QueueBase& queue, void* out, size_t size) {
  if (size != queue.element_size()) return BrokerError::kSizeMismatch;
  os::CriticalSection section(port_);
  if (queue.size() == 0) return BrokerError::kEmpty;
  while (queue.size() > 1) queue.PopFront();
  std::memcpy(out, queue.front(), size);
  queue.PopFront();
  return BrokerError::kOk;
}

uint32_t Broker::published(PublisherIndex index) const {
  return index < publisher_count_ ? publishers_[index].published : 0;
}

}  // namespace syrof::pubsub

namespace syrof::pubsub {

void Broker::AddToDigest(base::StateDigest& digest) const {
  auto add_queue = [&digest](const QueueBase* queue) {
    digest.AddValue(queue->count_);
    for (uint16_t i = 0; i < queue->count_; ++i) {
      const size_t slot = (static_cast<size_t>(queue->head_) + i) % queue->depth_;
      digest.AddBytes(std::span<const std::byte>(queue->storage_ + slot * queue->element_size_, queue->element_size_));
    }
  };
  for (size_t i = 0; i < publisher_count_; ++i) add_queue(publishers_[i].queue);
  for (size_t i = 0; i < subscription_count_; ++i) add_queue(subscriptions_[i].queue);
}

}  // namespace syrof::pubsub
