#include "syrof/pubsub/queue.h"

#include <cstring>

namespace syrof::pubsub {

void QueueBase::Push(const std::byte* element) {
  if (count_ == depth_) {
    PopFront();
    ++overwritten_;
  }
  const uint16_t tail = static_cast<uint16_t>((head_ + count_) % depth_);
  std::memcpy(storage_ + static_cast<size_t>(tail) * element_size_, element, element_size_);
  ++count_;
}

void QueueBase::PopFront() {
  head_ = static_cast<uint16_t>((head_ + 1) % depth_);
  --count_;
}

}  // namespace syrof::pubsub
