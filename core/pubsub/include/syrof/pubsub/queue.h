// Fixed-size, overwrite-oldest queues of fixed-size tuples: the broker's
// mailboxes. The owner (a publisher or a subscriber) provides the memory, as
// with FreeRTOS's xQueueCreateStatic, so nothing is allocated at run time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace syrof::pubsub {

class Broker;

/// A FIFO of `depth` elements of `element_size` bytes over storage that the
/// derived class owns. When full, a push overwrites the oldest element and
/// counts it in overwritten(): a slow reader loses old data, never new.
/// The broker reads and writes it under the port's critical section; the
/// accessors here are for statistics and tests.
class QueueBase {
 public:
  QueueBase(const QueueBase&) = delete;
  QueueBase& operator=(const QueueBase&) = delete;

  uint16_t element_size() const { return element_size_; }
  uint16_t depth() const { return depth_; }
  /// Elements written and not yet read.
  uint16_t size() const { return count_; }
  /// Elements lost because the queue was full when a new one arrived.
  uint32_t overwritten() const { return overwritten_; }
  /// True once the queue is registered with a broker (a queue serves one
  /// publisher or one subscription, never two).
  bool attached() const { return attached_; }

 protected:
  QueueBase(std::byte* storage, uint16_t element_size, uint16_t depth)
      : storage_(storage), element_size_(element_size), depth_(depth) {}
  ~QueueBase() = default;

 private:
  friend class Broker;

  void Push(const std::byte* element);
  const std::byte* front() const { return storage_ + static_cast<size_t>(head_) * element_size_; }
  void PopFront();

  std::byte* storage_;
  uint16_t element_size_;
  uint16_t depth_;
  uint16_t head_ = 0;
  uint16_t count_ = 0;
  uint32_t overwritten_ = 0;
  bool attached_ = false;
};

/// A queue of `Depth` tuples of type T (trivially copyable: tuples are copied
/// byte for byte).
template <typename T, uint16_t Depth = 1>
class Queue final : public QueueBase {
  static_assert(std::is_trivially_copyable_v<T>, "broker tuples are copied byte for byte");
  static_assert(Depth >= 1, "a queue holds at least one tuple");
  static_assert(sizeof(T) <= UINT16_MAX, "tuples are at most 65535 bytes");

 public:
  Queue() : QueueBase(storage_, static_cast<uint16_t>(sizeof(T)), Depth) {}

 private:
  alignas(T) std::byte storage_[sizeof(T) * Depth];
};

}  // namespace syrof::pubsub
