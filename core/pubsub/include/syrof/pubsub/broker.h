// The real-time publish-subscribe broker (paper, section 5).
//
// The paper's interface, kept: registerPublisher(id, size, queue) returns the
// publisher's index; subscribe(id, task, queue) attaches a subscriber's queue
// and task; publish(index) copies what the publisher queued to every
// subscriber's queue and notifies each subscriber's task through the OS port.
// Capacity is fixed at compile time (StaticBroker<...>); nothing is allocated
// after start-up; a publish costs one copy per subscriber per tuple, and then
// one notification per subscriber. Application code uses the typed wrappers
// in topic.h and never handles sizes.
//
// Registration happens at start-up: publishers first, then their subscribers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/base/result.h"
#include "syrof/base/state_digest.h"
#include "syrof/os/port.h"
#include "syrof/pubsub/queue.h"

namespace syrof::pubsub {

/// A topic's unique identifier (the paper's uint8_t id).
using TopicId = uint8_t;
/// The handle RegisterPublisher returns; publish with it.
using PublisherIndex = uint8_t;

enum class [[nodiscard]] BrokerError : uint8_t {
  kOk = 0,
  kDuplicatePublisher,  ///< RegisterPublisher: the id already has a publisher
  kUnknownTopic,        ///< Subscribe: no publisher registered this id
  kSizeMismatch,        ///< the queue's tuple size differs from the topic's (or the read buffer's)
  kCapacityExhausted,   ///< the publisher or subscription table is full
  kUnregisteredIndex,   ///< Publish: no RegisterPublisher call returned this index
  kInvalidQueue,        ///< the queue is already attached to a publisher or subscription
  kEmpty,               ///< Receive: no unread tuple (a status, not a misuse)
};

/// A short, stable name for logs and tests.
const char* ToString(BrokerError error);

/// One row of the publisher table.
struct PublisherSlot {
  QueueBase* queue;
  uint16_t first_subscription;  // index into the subscription table, or kNone
  uint16_t subscription_count;
  uint32_t published;  // tuples delivered so far
  TopicId id;
};

/// One row of the subscription table; rows of a topic form a list in
/// subscription order, which is also the order of delivery and notification.
struct SubscriptionSlot {
  QueueBase* queue;
  uint16_t next;  // next subscription of the same topic, or kNone
  os::TaskId task;
};

/// The broker over tables it does not own; use StaticBroker to get one with
/// its tables. Thread-safe through the port's critical section.
class Broker {
 public:
  static constexpr uint16_t kNone = UINT16_MAX;

  Broker(const Broker&) = delete;
  Broker& operator=(const Broker&) = delete;

  /// registerPublisher: makes `queue` the publisher queue of topic `id`,
  /// whose tuples are `size` bytes. Returns the index for Publish().
  base::Result<PublisherIndex, BrokerError> RegisterPublisher(TopicId id, size_t size, QueueBase& queue);

  /// subscribe: after each Publish of topic `id`, the tuples arrive in
  /// `queue` and `task` is notified. The topic's publisher must be
  /// registered first and the queue's tuple size must match.
  BrokerError Subscribe(TopicId id, os::TaskId task, QueueBase& queue);

  /// publish: moves every tuple waiting in the publisher's queue to each
  /// subscriber's queue, then notifies each subscriber's task once. Safe
  /// from any task. Publishing an empty queue does nothing.
  BrokerError Publish(PublisherIndex index);

  /// Appends one tuple to a publisher's queue (the owner's write before
  /// Publish). `size` must be the topic's tuple size.
  BrokerError Stage(PublisherIndex index, const void* tuple, size_t size);

  /// Pops the oldest unread tuple of a subscriber's queue into `out`
  /// (`size` bytes, the queue's tuple size). kEmpty if none is unread.
  BrokerError Receive(QueueBase& queue, void* out, size_t size);

  /// Pops every unread tuple and keeps only the newest in `out`. kEmpty if
  /// none is unread.
  BrokerError ReceiveLatest(QueueBase& queue, void* out, size_t size);

  size_t publisher_count() const { return publisher_count_; }
  size_t subscription_count() const { return subscription_count_; }
  /// Tuples delivered through publisher `index` so far (0 for unknown).
  uint32_t published(PublisherIndex index) const;

  /// Every queue's unread tuples, oldest first, into `digest`
  /// (base/state_digest.h): what the tasks have still to read.
  void AddToDigest(base::StateDigest& digest) const;

 protected:
  Broker(os::Port& port, std::span<PublisherSlot> publishers, std::span<SubscriptionSlot> subscriptions)
      : port_(port), publishers_(publishers), subscriptions_(subscriptions) {}
  ~Broker() = default;

 private:
  os::Port& port_;
  std::span<PublisherSlot> publishers_;
  std::span<SubscriptionSlot> subscriptions_;
  size_t publisher_count_ = 0;
  size_t subscription_count_ = 0;
};

namespace detail {
template <size_t MaxPublishers, size_t MaxSubscriptions>
struct BrokerTables {
  PublisherSlot publishers[MaxPublishers];
  SubscriptionSlot subscriptions[MaxSubscriptions];
};
}  // namespace detail

/// A broker with room for `MaxPublishers` topics and `MaxSubscriptions`
/// subscriptions in all, fixed at compile time.
template <size_t MaxPublishers, size_t MaxSubscriptions>
class StaticBroker final : private detail::BrokerTables<MaxPublishers, MaxSubscriptions>, public Broker {
  static_assert(MaxPublishers >= 1 && MaxPublishers <= 256, "publisher indices are uint8_t");
  static_assert(MaxSubscriptions >= 1 && MaxSubscriptions < Broker::kNone, "subscription indices are uint16_t");
  using Tables = detail::BrokerTables<MaxPublishers, MaxSubscriptions>;

 public:
  explicit StaticBroker(os::Port& port) : Tables{}, Broker(port, Tables::publishers, Tables::subscriptions) {}
};

}  // namespace syrof::pubsub
