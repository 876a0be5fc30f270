// Reads a replay file from a stream, one radio round at a time.
#pragma once

#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay {

/// Streams a replay back: ReadHeader() once, then Next() until it returns
/// false. Holds one round and one frame and one map per robot, never the
/// whole file.
///
/// The file is untrusted. Whatever its bytes, the reader neither crashes nor
/// allocates more than the data it has actually read justifies (counts are
/// checked against the limits in replay.h before use); it stops at the first
/// problem with error() naming the byte offset and what is wrong (lab's
/// error value, where "offset 8", message "format version 3 is newer than
/// this reader's (2)"). It reads every version from kOldestFormatVersion to
/// kFormatVersion.
class Reader {
 public:
  /// Reads from `in`, which the caller owns and must outlive the reader. The
  /// stream needs no seeking (a pipe is fine); offsets count from where it is.
  explicit Reader(std::istream& in);

  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  /// Reads and checks the header. False on error (see error()); call once.
  bool ReadHeader(Header& header);

  /// Reads the next round into `round`. False at the end marker (complete()
  /// turns true) or on error (failed()); then `round` is unspecified
  /// and every later call returns false.
  bool Next(Round& round);

  /// True once the end marker was read, its totals agreed with the rounds
  /// read, and nothing followed it.
  bool complete() const { return state_ == State::kComplete; }
  /// True once a problem stopped the reader; error() says which.
  bool failed() const { return state_ == State::kFailed; }
  /// What is wrong and at which byte offset ("offset N"); empty unless failed().
  const Error& error() const { return error_; }
  /// True when the error is that the file ends early (a run cut short) rather
  /// than bytes that are wrong.
  bool truncated() const { return truncated_; }
  /// Bytes consumed so far.
  uint64_t offset() const { return offset_; }
  /// The file's format version, once ReadHeader() succeeded (0 before).
  uint16_t version() const { return version_; }

 private:
  enum class State : uint8_t { kStart, kRounds, kComplete, kFailed };

  // Reads exactly `count` bytes into scratch_ (folded into crc_) or fails
  // naming `what`; returns a pointer to them.
  const uint8_t* Take(size_t count, const char* what);
  bool Fail(uint64_t at, const std::string& message);
  bool CheckCrc(uint64_t record_start, const char* record);
  bool ReadName(std::string& name, const char* what);
  bool ReadInputs(Header& header);   // version 4 on: each robot's private inputs
  bool ReadMessage(Header& header);  // version 4 on: the message format
  // `next_robot`: the header slot after the previous frame's robot, 0 for a round's first.
  bool ReadFrame(RobotFrame& frame, size_t& next_robot);
  bool ReadEvent(Event& event);
  // `next_robot` as for frames: maps come in increasing robot order.
  bool ReadMap(RobotMap& entry, size_t& next_robot);
  bool ReadEnd(uint64_t record_start);

  std::istream& in_;
  State state_ = State::kStart;
  Error error_;
  bool truncated_ = false;
  uint64_t offset_ = 0;
  uint32_t crc_ = 0;
  uint8_t scratch_[64] = {};
  uint16_t version_ = 0;
  std::vector<uint16_t> ids_;         // header ids, increasing
  std::vector<RobotFrame> previous_;  // per header robot: its last frame read
  std::vector<std::shared_ptr<const EpochMap>> latest_;  // per header robot: its last map read (references)
  bool any_round_ = false;
  uint32_t last_index_ = 0;
  int64_t last_time_ns_ = 0;
  uint32_t rounds_ = 0;
  uint64_t events_ = 0;
  uint64_t frames_ = 0;
};

}  // namespace syrof::lab::replay
