// Writes a replay file to a stream, one radio round at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <ostream>
#include <span>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay {

/// Streams a replay: the header on construction, one WriteRound() per radio
/// round, Finish() at the end. The output depends only on the calls' values
/// (same calls, same bytes). Input the format cannot hold (see the contracts
/// below) or a failing stream puts the writer in a failed state: ok() turns
/// false, error() says why, and every later call writes nothing. A round is
/// checked whole before any of its bytes are written, so the file always
/// ends at a record boundary and a reader reports it as truncated.
class Writer {
 public:
  /// Writes the header to `out`, which the caller owns and must outlive the
  /// writer. Refuses (ok() false) a header that breaks Header's contracts.
  Writer(std::ostream& out, const Header& header);

  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Appends one round. `robots` holds frames with ids of the header, in
  /// strictly increasing id order (usually every robot); `events` the round's
  /// events. `index` must exceed the previous round's and `time_ns` not be
  /// below it. A frame's fields must fit the format (status <= 1, phase <= 2,
  /// mode <= 1, presence a Presence); events name header ids or kNoRobot.
  /// Unchanged fields of a robot are not repeated (format.h), so a still
  /// robot costs 4 bytes per round. `maps` holds the robots that started an
  /// epoch this round, in strictly increasing id order, each with the map it
  /// started with (non-null, members in increasing id order, header ids). A
  /// map equal to one another robot holds (its latest) is stored as a 4-byte
  /// reference to that robot, so a COOPERATIVE epoch's map costs its bytes
  /// once however many robots start it, whenever they start it. A map must
  /// not change once handed over (the writer keeps it); handing robots one
  /// shared object for equal maps spares the writer comparing them.
  void WriteRound(uint32_t index, int64_t time_ns, std::span<const RobotFrame> robots,
                  std::span<const Event> events, std::span<const RobotMap> maps = {});

  /// Writes the end marker with the totals, then flushes. Without it a
  /// reader reports the file as truncated. Later calls write nothing.
  void Finish();

  /// True while nothing was refused and the stream is good.
  bool ok() const;
  /// Why the writer failed (lab's error value; where "header" for a refused
  /// header); empty while ok().
  const Error& error() const { return error_; }

  /// Bytes written so far, header included.
  uint64_t bytes_written() const { return bytes_written_; }

 private:
  enum class State : uint8_t { kWriting, kFinished, kFailed };

  void Fail(std::string message, std::string where = "");
  std::string CheckRound(uint32_t index, int64_t time_ns, std::span<const RobotFrame> robots,
                         std::span<const Event> events, std::span<const RobotMap> maps) const;
  void PutMap(size_t slot, const std::shared_ptr<const EpochMap>& map);
  void Emit();  // writes buffer_ with its CRC appended

  std::ostream& out_;
  State state_ = State::kWriting;
  Error error_;
  std::vector<uint16_t> ids_;              // header ids, increasing
  std::vector<RobotFrame> previous_;       // per header robot: its last frame written
  std::vector<uint8_t> buffer_;            // the record being built
  std::vector<std::shared_ptr<const EpochMap>> latest_;  // per header robot: its last map written
  std::vector<uint64_t> latest_hash_;      // per header robot: MapHash of latest_
  std::set<std::pair<uint64_t, size_t>> by_hash_;  // (MapHash, slot) of every slot holding a map
  // The map PutMap hashed last, its MapHash, and a map found equal to it
  // (maps never change once handed over, and these keep them alive).
  std::shared_ptr<const EpochMap> hashed_map_;
  uint64_t hashed_map_hash_ = 0;
  std::shared_ptr<const EpochMap> hashed_map_equal_;
  bool any_round_ = false;
  uint32_t last_index_ = 0;
  int64_t last_time_ns_ = 0;
  uint32_t rounds_ = 0;
  uint64_t events_ = 0;
  uint64_t frames_ = 0;
  uint64_t bytes_written_ = 0;
};

}  // namespace syrof::lab::replay
