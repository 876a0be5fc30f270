#include "syrof/lab/live/round_ring.h"

#include <algorithm>
#include <utility>

#include "syrof/base/check.h"

namespace syrof::lab::live {

RoundRing::RoundRing(int64_t span_ns, size_t max_rounds, size_t max_bytes)
    : span_ns_(span_ns), max_rounds_(std::max<size_t>(1, max_rounds)), max_bytes_(max_bytes) {}

void RoundRing::Push(int64_t time_ns, std::shared_ptr<const std::string> text) {
  SYROF_CHECK(text != nullptr);
  bytes_ += text->size();
  entries_.push_back(Entry{time_ns, std::move(text)});
  while (entries_.size() > 1 && (entries_.size() > max_rounds_ || bytes_ > max_bytes_ ||
                                 time_ns - entries_.front().time_ns > span_ns_)) {
    bytes_ -= entries_.front().text->size();
    entries_.pop_front();
    ++begin_;
  }
}

RoundRing::Taken RoundRing::Take(uint64_t cursor, size_t max_rounds) const {
  Taken taken;
  if (cursor < begin_) {
    taken.skipped = begin_ - cursor;
    cursor = begin_;
  }
  const uint64_t stop = std::min<uint64_t>(end(), cursor + max_rounds);
  for (uint64_t sequence = cursor; sequence < stop; ++sequence) {
    taken.texts.push_back(entries_[static_cast<size_t>(sequence - begin_)].text);
  }
  taken.next = std::max(cursor, stop);
  return taken;
}

}  // namespace syrof::lab::live
