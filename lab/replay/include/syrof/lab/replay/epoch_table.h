// Who started which epoch, in which mode, with which members (and the
// members' payloads, the state the apps share): the part of a run the three
// runtimes (the lab, the DDS swarm, the firmware swarm) promise to agree on
// for the same scenario and seed. `syrof compare` checks that
// promise (comparison.h, docs/replay.md "Comparing two runs").
//
// Usage, with rounds as a Reader returns them:
//
//   EpochTableBuilder builder(header, reader.version());
//   while (reader.Next(round)) builder.Add(round);
//   EpochTable table = std::move(builder).Finish();
//
// The builder is pure: no I/O, and the table depends only on the rounds
// handed in. It holds one row per epoch (one entry per robot), not the
// rounds: equal maps (a COOPERATIVE epoch's, which the reader hands every
// robot as one object) share one member list.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay {

/// A map's member ids, strictly increasing.
using MemberIds = std::vector<uint16_t>;

/// A map's members' payloads (the bytes each member's app sent with
/// sendMessageData, at most 9), in the order of its MemberIds: what the
/// apps share of their state in that map.
using MemberPayloads = std::vector<std::vector<uint8_t>>;

/// One robot in one epoch: whether and how it started it.
struct EpochStart {
  /// EPOCH_START events of the robot for this epoch: 0 when it did not start
  /// it, 1 normally; more if it started the same epoch again (rejoining a
  /// group that was behind it).
  uint16_t start_count = 0;
  uint32_t round = 0;  ///< index of the round of its first start (when start_count > 0)
  uint8_t mode = 0;    ///< wire::Mode value of its first start, stored as is
  /// The members of the map it started the epoch with, at its first start;
  /// null when the file holds no map for it (format versions 1 and 2).
  std::shared_ptr<const MemberIds> members;
  /// The payloads of those members, beside `members` (null when it is).
  std::shared_ptr<const MemberPayloads> payloads;

  bool started() const { return start_count > 0; }
};

/// One epoch of a run.
struct EpochRow {
  /// The epoch's number, unwrapped: the 16-bit wire epoch plus 65536 for each
  /// time the numbers wrapped since the file's first epoch start. Each start
  /// is placed nearest the epoch started before it in the file (serial
  /// arithmetic, as the synchronizer compares epochs), so a number that
  /// comes again after a wrap is a later epoch, not the same one.
  int64_t number = 0;
  std::vector<EpochStart> robots;  ///< one per Header::robots entry, in its order

  /// The number as the protocol and the replay's events carry it.
  uint16_t wire_epoch() const { return static_cast<uint16_t>(number); }
};

/// The epochs of one run.
struct EpochTable {
  std::vector<uint16_t> robot_ids;  ///< Header::robots' ids, increasing
  bool has_maps = false;            ///< the file's format records maps (version 3 on)
  uint32_t round_count = 0;         ///< rounds added
  uint32_t first_round = 0;         ///< index of the first round added (when round_count > 0)
  uint32_t last_round = 0;          ///< index of the last round added (when round_count > 0)
  /// Every epoch some robot started, by increasing number (gaps when no
  /// robot started an epoch).
  std::vector<EpochRow> epochs;
};

/// Most entries (epochs times robots) a table holds by default: half a GiB
/// of EpochStart. A real run stays far below (1,024 robots through 16,384
/// epochs); a hostile file could ask for gigabytes, each 20-byte
/// EPOCH_START of a new epoch opening a row of up to 65,535 robots.
inline constexpr size_t kMaxEpochTableCells = size_t{1} << 24;

/// Builds an EpochTable from a replay's rounds, in file order. A robot's
/// start is its EPOCH_START event (epoch and mode); its members come from
/// the map record of the same round (the map's epoch is placed like the
/// event's). A map without an event in its round still counts as a start,
/// with the map's mode.
class EpochTableBuilder {
 public:
  /// `header` and `version` as Reader::ReadHeader() and Reader::version()
  /// gave them; the table holds at most `max_cells` entries.
  EpochTableBuilder(const Header& header, uint16_t version, size_t max_cells = kMaxEpochTableCells);

  /// Adds the next round of the file. Ids in it are the header's (the
  /// reader checks that); an id that is not is ignored. False, with the
  /// round added only in part and full() true, when a new epoch's row would
  /// take the table past its `max_cells`: add nothing more.
  bool Add(const Round& round);

  /// An Add() found the table full.
  bool full() const { return full_; }

  /// The table of the rounds added so far.
  EpochTable Finish() &&;

 private:
  int64_t Unwrap(uint16_t wire_epoch);
  EpochStart* Entry(int64_t number, uint16_t robot);  // null for an id not in the header, or when full
  // The member ids and payloads of `map`, shared by robots handed the same map.
  struct MapContents {
    std::shared_ptr<const MemberIds> members;
    std::shared_ptr<const MemberPayloads> payloads;
  };
  MapContents ContentsOf(const std::shared_ptr<const EpochMap>& map);

  EpochTable table_;
  size_t max_rows_ = 0;  // max_cells / robots
  bool full_ = false;
  bool any_epoch_ = false;
  int64_t last_epoch_ = 0;  // unwrapped number of the last start placed
  // Member lists and payloads of the maps seen lately, by the reader's map
  // object, so robots handed the same map share one copy. Cleared when it
  // grows past the robot count (a cache: a miss only costs a copy).
  std::unordered_map<const EpochMap*, std::pair<std::shared_ptr<const EpochMap>, MapContents>> contents_cache_;
};

/// The table of `rounds` (a whole read file, or its beginning), up to the
/// round where it found itself full (kMaxEpochTableCells).
EpochTable BuildEpochTable(const Header& header, uint16_t version, std::span<const Round> rounds);

}  // namespace syrof::lab::replay
