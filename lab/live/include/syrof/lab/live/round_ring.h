// The live page's memory of a run: the last stretch of world time, as the
// rounds' texts (SSE events, ready to write), in a ring. Each reader keeps
// its own cursor, a sequence number; a reader whose cursor fell behind the
// ring's start skips to it and is told how many rounds it missed.
//
// Not thread-safe: LiveServer holds it under its lock. Every operation is
// O(1) or O(what it hands out); the texts are shared, never copied.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace syrof::lab::live {

class RoundRing {
 public:
  /// Keeps the rounds within `span_ns` of world time of the newest one, and
  /// at most `max_rounds` of them and `max_bytes` of text (the oldest go
  /// first, the newest always stays).
  RoundRing(int64_t span_ns, size_t max_rounds, size_t max_bytes);

  /// Adds a round at world time `time_ns` (not decreasing) with its text.
  void Push(int64_t time_ns, std::shared_ptr<const std::string> text);

  /// The sequence number of the oldest round held, and one past the newest
  /// (equal when empty). Sequence numbers start at 0 and never repeat.
  uint64_t begin() const { return begin_; }
  uint64_t end() const { return begin_ + entries_.size(); }
  size_t size() const { return entries_.size(); }
  size_t bytes() const { return bytes_; }

  /// What a reader at `cursor` gets next: at most `max_rounds` texts from
  /// max(cursor, begin()), the cursor after them, and how many rounds it
  /// skipped because they left the ring before it read them.
  struct Taken {
    std::vector<std::shared_ptr<const std::string>> texts;
    uint64_t next = 0;
    uint64_t skipped = 0;
  };
  Taken Take(uint64_t cursor, size_t max_rounds) const;

 private:
  struct Entry {
    int64_t time_ns;
    std::shared_ptr<const std::string> text;
  };
  int64_t span_ns_;
  size_t max_rounds_;
  size_t max_bytes_;
  std::deque<Entry> entries_;
  uint64_t begin_ = 0;
  size_t bytes_ = 0;
};

}  // namespace syrof::lab::live
