// A small replay used by the replay tests: its header and rounds, written to
// bytes with the Writer, plus the offsets of its records for tests that
// damage it on purpose.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "syrof/lab/replay/format.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/replay/writer.h"

namespace syrof::lab::replay::testing {

inline Header SampleHeader() {
  Header header;
  header.seed = 42;
  header.radio_round_ns = 50'000'000;
  header.arena_width_m = 4.0f;
  header.arena_height_m = 3.0f;
  header.scenario_name = "three_robots";
  header.app_name = "builtin:idle";
  header.robots = {{0, 0, 0.1f, {}}, {1, 0, 0.1f, {}}, {2, 1, 0.12f, {}}};
  header.anchors = {{0.0f, 0.0f}, {4.0f, 3.0f}};
  return header;
}

inline RobotFrame Frame(uint16_t id, Presence presence, uint16_t epoch, float x_m, float y_m) {
  RobotFrame frame;
  frame.id = id;
  frame.presence = presence;
  frame.epoch = epoch;
  frame.true_x_m = x_m;
  frame.true_y_m = y_m;
  frame.true_heading_rad = 0.25f;
  frame.est_x_m = x_m + 0.01f;
  frame.est_y_m = y_m - 0.02f;
  frame.est_heading_rad = 0.26f;
  return frame;
}

// A map holding `members` (ids) with snapshots derived from the ids.
inline std::shared_ptr<const EpochMap> Map(uint16_t epoch, uint8_t mode, std::vector<uint16_t> members) {
  auto map = std::make_shared<EpochMap>();
  map->epoch = epoch;
  map->mode = mode;
  for (const uint16_t id : members) {
    MapMember member;
    member.id = id;
    member.phase = 0;
    member.x_mm = static_cast<int16_t>(1000 + 100 * id);
    member.y_mm = static_cast<int16_t>(-5 * id);
    member.heading_mrad = static_cast<int16_t>(250 + id);
    member.vx_mm_s = static_cast<int16_t>(id);
    member.payload.assign(id, static_cast<uint8_t>(0xA0 + id));  // robot i sends i bytes
    map->members.push_back(member);
  }
  return map;
}

// Three rounds: robot 2 absent and then joining, robot 1 crashing, an epoch
// start, a collision and a partition, and a round with a robot left out.
// Robots 0 and 1 start epoch 1 with the same COOPERATIVE map (stored once,
// then referenced); robot 2 starts epoch 2 AUTONOMOUS with its own.
inline std::vector<Round> SampleRounds() {
  std::vector<Round> rounds(3);
  rounds[0].index = 0;
  rounds[0].time_ns = 50'000'000;
  rounds[0].robots = {Frame(0, Presence::kRunning, 1, 1.0f, 1.0f), Frame(1, Presence::kRunning, 1, 2.0f, 1.0f),
                      RobotFrame{.id = 2}};
  rounds[0].events = {{EventKind::kEpochStart, 0, kNoRobot, 1, 0, 50'000'000},
                      {EventKind::kPartitionStart, kNoRobot, kNoRobot, 0, 0, 40'000'000, 0}};
  const std::shared_ptr<const EpochMap> shared = Map(1, 0, {0, 1});
  rounds[0].maps = {{0, shared}, {1, shared}};

  rounds[1].index = 1;
  rounds[1].time_ns = 100'000'000;
  rounds[1].robots = {Frame(0, Presence::kRunning, 1, 1.1f, 1.0f), Frame(1, Presence::kCrashed, 1, 2.0f, 1.0f),
                      Frame(2, Presence::kRunning, 0, 3.0f, 2.0f)};
  rounds[1].robots[0].phase = 1;
  rounds[1].robots[2].status = 1;
  rounds[1].robots[2].mode = 1;
  rounds[1].events = {{EventKind::kCollision, 0, 1, 1, 0, 90'000'000},
                      {EventKind::kCrash, 1, kNoRobot, 1, 0, 95'000'000},
                      {EventKind::kJoin, 2, kNoRobot, 0, 1, 100'000'000}};

  rounds[2].index = 3;  // indices may skip
  rounds[2].time_ns = 200'000'000;
  rounds[2].robots = {Frame(0, Presence::kRunning, 2, 1.2f, 1.0f), Frame(2, Presence::kRunning, 2, 3.0f, 2.1f)};
  rounds[2].robots[0].phase = 2;
  rounds[2].robots[1].mode = 1;
  rounds[2].events = {{EventKind::kMemberRemoved, 0, 1, 2, 0, 200'000'000}};
  rounds[2].maps = {{2, Map(2, 1, {0, 2})}};
  return rounds;
}

// A version-2 file written out by hand from the version-2 layout (one robot,
// 7, a rover; one round with one frame and one EPOCH_START event); the CRCs
// come from zlib.crc32. The event starts at kGoldenV2EventAt.
inline const std::vector<uint8_t>& GoldenFileVersion2() {
  static const std::vector<uint8_t> bytes = {
      'S', 'Y', 'R', 'O', 'F', 'R', 'P', 'L', 0x02, 0x00, 0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01, 0x80,
      0xF0, 0xFA, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x40, 0x00, 0x00, 0x20, 0x40, 0x02, 0x00, 'a',
      'b', 0x01, 0x00, 'c', 0x01, 0x00, 0x00, 0x00, 0x07, 0x00, 0x01, 0x00, 0x00, 0x00, 0x3E, 0x05, 0xE8, 0xE3,
      0xFC,  // header
      'R', 0x03, 0x00, 0x00, 0x00, 0x80, 0xD1, 0xF0, 0x08, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01,
      0x00, 0x00, 0x00, 0x07, 0x00, 0x35, 0x1B, 0x02, 0x01, 0x00, 0x00, 0x80, 0x3F, 0x00, 0x00, 0x00, 0xBF, 0x00,
      0x00, 0x80, 0x3F,  // round header and frame
      0x00, 0x07, 0x00, 0xFF, 0xFF, 0x02, 0x01, 0x01, 0x80, 0xD1, 0xF0, 0x08, 0x00, 0x00, 0x00, 0x00,  // event
      0xA0, 0x86, 0x17, 0xA0,  // round crc
      'E', 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x16, 0xA5, 0x63, 0x3F};
  return bytes;
}
inline constexpr size_t kGoldenV2HeaderEnd = 56;
inline constexpr size_t kGoldenV2EventAt = 95;
inline constexpr size_t kGoldenV2RoundEnd = 115;

// Bytes of a written replay and where each record ends.
struct Written {
  std::string bytes;
  size_t header_end = 0;
  std::vector<size_t> round_ends;  // offset just past each round record
};

inline Written Write(const Header& header, std::span<const Round> rounds, bool finish = true) {
  std::ostringstream out;
  Written written;
  Writer writer(out, header);
  written.header_end = writer.bytes_written();
  for (const Round& round : rounds) {
    writer.WriteRound(round.index, round.time_ns, round.robots, round.events, round.maps);
    written.round_ends.push_back(writer.bytes_written());
  }
  if (finish) writer.Finish();
  written.bytes = out.str();
  return written;
}

inline Written WriteSample() {
  const std::vector<Round> rounds = SampleRounds();
  return Write(SampleHeader(), rounds);
}

// What a reader makes of some bytes.
struct ReadBack {
  bool header_ok = false;
  Header header;
  std::vector<Round> rounds;
  bool complete = false;
  bool truncated = false;
  std::string error;
};

inline ReadBack Read(const std::string& bytes) {
  std::istringstream in(bytes);
  Reader reader(in);
  ReadBack result;
  result.header_ok = reader.ReadHeader(result.header);
  if (result.header_ok) {
    Round round;
    while (reader.Next(round)) result.rounds.push_back(round);
  }
  result.complete = reader.complete();
  result.truncated = reader.truncated();
  result.error = reader.failed() ? reader.error().ToString() : std::string();
  return result;
}

// Rewrites the CRC of the record [start, crc_offset) after a deliberate edit,
// so the reader gets past the checksum to the error under test.
inline void FixCrc(std::string& bytes, size_t start, size_t crc_offset) {
  const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
  const uint32_t crc = format::Crc32({data + start, crc_offset - start});
  for (unsigned index = 0; index < 4; ++index) bytes[crc_offset + index] = static_cast<char>(crc >> (8 * index));
}

inline void PutU16At(std::string& bytes, size_t offset, uint16_t value) {
  bytes[offset] = static_cast<char>(value);
  bytes[offset + 1] = static_cast<char>(value >> 8);
}

inline void PutU32At(std::string& bytes, size_t offset, uint32_t value) {
  for (unsigned index = 0; index < 4; ++index) bytes[offset + index] = static_cast<char>(value >> (8 * index));
}

}  // namespace syrof::lab::replay::testing
