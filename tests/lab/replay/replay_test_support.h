// A small replay used by the replay tests: its header and rounds, written to
// bytes with the Writer, plus the offsets of its records for tests that
// damage it on purpose.
#pragma once

#include <cstdint>
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
  header.robots = {{0, 0, 0.1f}, {1, 0, 0.1f}, {2, 1, 0.12f}};
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

// Three rounds: robot 2 absent and then joining, robot 1 crashing, an epoch
// start, a collision and a partition, and a round with a robot left out.
inline std::vector<Round> SampleRounds() {
  std::vector<Round> rounds(3);
  rounds[0].index = 0;
  rounds[0].time_ns = 50'000'000;
  rounds[0].robots = {Frame(0, Presence::kRunning, 1, 1.0f, 1.0f), Frame(1, Presence::kRunning, 1, 2.0f, 1.0f),
                      RobotFrame{.id = 2}};
  rounds[0].events = {{EventKind::kEpochStart, 0, kNoRobot, 1, 0, 50'000'000},
                      {EventKind::kPartitionStart, kNoRobot, kNoRobot, 0, 0, 40'000'000}};

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
  return rounds;
}

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
    writer.WriteRound(round.index, round.time_ns, round.robots, round.events);
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
