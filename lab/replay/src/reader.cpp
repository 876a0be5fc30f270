#include "syrof/lab/replay/reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "little_endian.h"
#include "rules.h"
#include "syrof/lab/replay/format.h"

namespace syrof::lab::replay {
namespace {

using detail::GetF32;
using detail::GetF64;
using detail::GetI64;
using detail::GetU16;
using detail::GetU32;
using detail::GetU64;

std::string HexBytes(const uint8_t* bytes, size_t count) {
  std::string text;
  for (size_t index = 0; index < count; ++index) {
    text += fmt::format("{}{:02X}", index == 0 ? "" : " ", bytes[index]);
  }
  return text;
}

}  // namespace

Reader::Reader(std::istream& in) : in_(in) {}

bool Reader::Fail(uint64_t at, const std::string& message) {
  state_ = State::kFailed;
  error_ = Error{.where = fmt::format("offset {}", at), .message = message};
  return false;
}

const uint8_t* Reader::Take(size_t count, const char* what) {
  // Callers ask for one field or one fixed part at a time.
  static_assert(sizeof(scratch_) >= format::kHeaderFixedBytes);
  in_.read(reinterpret_cast<char*>(scratch_), static_cast<std::streamsize>(count));
  const auto got = static_cast<size_t>(in_.gcount());
  if (got < count) {
    if (in_.bad()) {
      Fail(offset_ + got, fmt::format("reading {} failed (I/O error)", what));
    } else {
      truncated_ = true;
      Fail(offset_, fmt::format("file ends inside {} ({} of {} bytes present; truncated)", what, got,
                                count));
    }
    return nullptr;
  }
  crc_ = format::Crc32({scratch_, count}, crc_);
  offset_ += count;
  return scratch_;
}

bool Reader::CheckCrc(uint64_t record_start, const char* record) {
  const uint32_t computed = crc_;
  const uint64_t at = offset_;
  const uint8_t* bytes = Take(format::kCrcBytes, "checksum");
  if (bytes == nullptr) return false;
  const uint32_t stored = GetU32(bytes);
  if (stored != computed) {
    return Fail(at, fmt::format("checksum of the {} starting at offset {} is 0x{:08X}, stored 0x{:08X}: "
                                "the file is damaged",
                                record, record_start, computed, stored));
  }
  return true;
}

bool Reader::ReadInputs(Header& header) {
  for (RobotInfo& robot : header.robots) {
    uint64_t at = offset_;
    const uint8_t* bytes = Take(1, "input count");
    if (bytes == nullptr) return false;
    if (std::string problem = detail::CheckInputCount(bytes[0], robot.id); !problem.empty()) return Fail(at, problem);
    const uint8_t count = bytes[0];
    for (uint8_t index = 0; index < count; ++index) {
      at = offset_;
      InputValue input;
      if (!ReadName(input.name, "input name")) return false;
      if ((bytes = Take(8, "input value")) == nullptr) return false;
      input.value = GetF64(bytes);
      if (std::string problem = detail::CheckInput(input, robot.inputs, robot.id); !problem.empty()) {
        return Fail(at, problem);
      }
      robot.inputs.push_back(std::move(input));
    }
  }
  return true;
}

bool Reader::ReadMessage(Header& header) {
  uint64_t at = offset_;
  const uint8_t* bytes = Take(1, "message kind");
  if (bytes == nullptr) return false;
  const uint8_t kind = bytes[0];
  if (kind == format::kMessageUndeclared) return true;
  if (kind == format::kMessageNone) {
    header.message = message::MessageFormat{};
    return true;
  }
  if (kind != format::kMessageFields) return Fail(at, fmt::format("unknown message kind {}", kind));
  at = offset_;
  if ((bytes = Take(1, "message field count")) == nullptr) return false;
  const uint8_t count = bytes[0];
  if (std::string problem = detail::CheckFieldCount(count); !problem.empty()) return Fail(at, problem);
  message::MessageFormat format;
  format.none = false;
  for (uint8_t index = 0; index < count; ++index) {
    at = offset_;
    message::MessageField field;
    if (!ReadName(field.name, "message field name")) return false;
    if ((bytes = Take(1, "message field type")) == nullptr) return false;
    if (std::string problem = detail::CheckFieldType(bytes[0]); !problem.empty()) return Fail(at, problem);
    field.type = static_cast<message::FieldType>(bytes[0]);
    field.offset = format.length;
    if (std::string problem = detail::CheckField(field, format.fields); !problem.empty()) return Fail(at, problem);
    format.length += message::FieldBytes(field.type);
    format.fields.push_back(std::move(field));
  }
  header.message = std::move(format);
  return true;
}

bool Reader::ReadName(std::string& name, const char* what) {
  const uint64_t at = offset_;
  const uint8_t* bytes = Take(2, what);
  if (bytes == nullptr) return false;
  const uint16_t length = GetU16(bytes);
  if (std::string problem = detail::CheckNameLength(length, what); !problem.empty()) {
    return Fail(at, problem);
  }
  name.resize(length);
  size_t done = 0;
  while (done < length) {
    const size_t chunk = std::min(sizeof(scratch_), length - done);
    bytes = Take(chunk, what);
    if (bytes == nullptr) return false;
    std::memcpy(name.data() + done, bytes, chunk);
    done += chunk;
  }
  if (std::string problem = detail::CheckNameBytes(name, what); !problem.empty()) {
    return Fail(at + 2, problem);
  }
  return true;
}

bool Reader::ReadHeader(Header& header) {
  if (state_ == State::kFailed) return false;
  if (state_ != State::kStart) return Fail(offset_, "ReadHeader called twice");
  crc_ = 0;

  // The magic is compared before its length is demanded, so a short file of
  // another kind is named as such rather than as a truncated replay.
  in_.read(reinterpret_cast<char*>(scratch_), format::kMagic.size());
  const auto got = static_cast<size_t>(in_.gcount());
  if (!std::equal(scratch_, scratch_ + got, format::kMagic.begin())) {
    return Fail(0, fmt::format("not a SyROF replay file: it starts with {}, not the magic 'SYROFRPL'",
                               HexBytes(scratch_, got)));
  }
  if (got < format::kMagic.size()) {
    truncated_ = true;
    return Fail(0, fmt::format("file ends inside the magic ({} of 8 bytes present; truncated)", got));
  }
  crc_ = format::Crc32({scratch_, got});
  offset_ = got;

  const uint8_t* bytes = Take(2, "version");
  if (bytes == nullptr) return false;
  const uint16_t version = GetU16(bytes);
  if (version > kFormatVersion) {
    return Fail(8, fmt::format("format version {} is newer than this reader's ({}); read the file "
                               "with the SyROF that wrote it or a later one",
                               version, kFormatVersion));
  }
  if (version < kOldestFormatVersion) {
    return Fail(8, fmt::format("format version {} does not exist (this reader knows versions {} to {})",
                               version, kOldestFormatVersion, kFormatVersion));
  }
  version_ = version;

  if ((bytes = Take(8, "seed")) == nullptr) return false;
  header.seed = GetU64(bytes);
  uint64_t at = offset_;
  if ((bytes = Take(8, "radio_round_ns")) == nullptr) return false;
  header.radio_round_ns = GetI64(bytes);
  if (std::string problem = detail::CheckRadioRound(header.radio_round_ns); !problem.empty()) {
    return Fail(at, problem);
  }
  at = offset_;
  if ((bytes = Take(4, "arena_width_m")) == nullptr) return false;
  header.arena_width_m = GetF32(bytes);
  if (std::string problem = detail::CheckArenaSide(header.arena_width_m, "arena_width_m");
      !problem.empty()) {
    return Fail(at, problem);
  }
  at = offset_;
  if ((bytes = Take(4, "arena_height_m")) == nullptr) return false;
  header.arena_height_m = GetF32(bytes);
  if (std::string problem = detail::CheckArenaSide(header.arena_height_m, "arena_height_m");
      !problem.empty()) {
    return Fail(at, problem);
  }
  if (!ReadName(header.scenario_name, "scenario_name")) return false;
  if (!ReadName(header.app_name, "app_name")) return false;

  at = offset_;
  if ((bytes = Take(4, "robot count")) == nullptr) return false;
  const uint32_t robot_count = GetU32(bytes);
  if (std::string problem = detail::CheckRobotCount(robot_count); !problem.empty()) {
    return Fail(at, problem);
  }
  // Grown as robots are read, not reserved from the count: a short file with
  // a large count costs only what it holds.
  header.robots.clear();
  ids_.clear();
  for (uint32_t index = 0; index < robot_count; ++index) {
    at = offset_;
    if ((bytes = Take(format::kRobotInfoBytes, "robot entry")) == nullptr) return false;
    RobotInfo robot;
    robot.id = GetU16(bytes);
    robot.kind = bytes[2];
    robot.body_radius_m = GetF32(bytes + 3);
    std::string problem = detail::CheckRobotId(robot.id, ids_.empty() ? nullptr : &ids_.back());
    if (problem.empty()) problem = detail::CheckBodyRadius(robot.body_radius_m, robot.id);
    if (!problem.empty()) return Fail(at, problem);
    header.robots.push_back(robot);
    ids_.push_back(robot.id);
  }
  header.anchors.clear();
  if (version_ >= 3) {
    at = offset_;
    if ((bytes = Take(2, "anchor count")) == nullptr) return false;
    const uint16_t anchor_count = GetU16(bytes);
    if (std::string problem = detail::CheckAnchorCount(anchor_count); !problem.empty()) return Fail(at, problem);
    for (uint16_t index = 0; index < anchor_count; ++index) {
      at = offset_;
      if ((bytes = Take(format::kAnchorBytes, "anchor")) == nullptr) return false;
      const AnchorInfo anchor{GetF32(bytes), GetF32(bytes + 4)};
      if (std::string problem = detail::CheckAnchor(anchor, index); !problem.empty()) return Fail(at, problem);
      header.anchors.push_back(anchor);
    }
  }
  header.message.reset();
  if (version_ >= 4 && (!ReadInputs(header) || !ReadMessage(header))) return false;
  if (!CheckCrc(0, "header")) return false;

  previous_.assign(ids_.size(), RobotFrame{});
  latest_.assign(ids_.size(), nullptr);
  for (size_t index = 0; index < ids_.size(); ++index) previous_[index].id = ids_[index];
  state_ = State::kRounds;
  return true;
}

bool Reader::ReadFrame(RobotFrame& frame, size_t& next_robot) {
  uint64_t at = offset_;
  const uint8_t* bytes = Take(format::kFrameFixedBytes, "frame");
  if (bytes == nullptr) return false;
  const uint16_t id = GetU16(bytes);
  const uint8_t state = bytes[2];
  const uint8_t changed = bytes[3];
  const size_t slot = detail::FindRobot(ids_, id);
  if (slot == ids_.size()) return Fail(at, fmt::format("frame of robot {}, which is not in the header", id));
  if (slot < next_robot) {
    return Fail(at, fmt::format("frame of robot {} after robot {}; frames must be in increasing id order",
                                id, ids_[next_robot - 1]));
  }
  next_robot = slot + 1;

  frame = previous_[slot];
  if (std::string problem = detail::UnpackState(state, frame); !problem.empty()) {
    return Fail(at + 2, problem);
  }
  if ((changed & format::kChangedReservedMask) != 0) {
    return Fail(at + 3, fmt::format("robot {} changed-fields byte 0x{:02X} has reserved bits set", id,
                                    changed));
  }
  if (changed & format::kChangedEpoch) {
    if ((bytes = Take(2, "frame epoch")) == nullptr) return false;
    frame.epoch = GetU16(bytes);
  }
  // The float fields in their bit order (format.h).
  float* const fields[] = {&frame.true_x_m, &frame.true_y_m, &frame.true_heading_rad,
                           &frame.est_x_m,  &frame.est_y_m,  &frame.est_heading_rad};
  for (unsigned field = 0; field < 6; ++field) {
    if ((changed & (format::kChangedTrueX << field)) == 0) continue;
    if ((bytes = Take(4, "frame pose")) == nullptr) return false;
    *fields[field] = GetF32(bytes);
  }
  previous_[slot] = frame;
  return true;
}

bool Reader::ReadEvent(Event& event) {
  const uint64_t at = offset_;
  const size_t size = version_ >= 3 ? format::kEventBytes : format::kEventBytesV2;
  const uint8_t* bytes = Take(size, "event");
  if (bytes == nullptr) return false;
  if (std::string problem = detail::CheckEventKind(bytes[0], version_); !problem.empty()) return Fail(at, problem);
  event.kind = static_cast<EventKind>(bytes[0]);
  event.robot = GetU16(bytes + 1);
  event.other = GetU16(bytes + 3);
  event.epoch = GetU16(bytes + 5);
  event.mode = bytes[7];
  event.time_ns = GetI64(bytes + 8);
  event.partition = version_ >= 3 ? GetU16(bytes + 16) : kNoPartition;
  if (std::string problem = detail::CheckEventRobot(event.robot, ids_, "robot"); !problem.empty()) {
    return Fail(at + 1, problem);
  }
  if (std::string problem = detail::CheckEventRobot(event.other, ids_, "other"); !problem.empty()) {
    return Fail(at + 3, problem);
  }
  if (version_ >= 3) {
    if (std::string problem = detail::CheckEventPartition(event); !problem.empty()) return Fail(at, problem);
  } else if (IsPartitionEvent(event.kind)) {
    // Versions 1 and 2 kept the partition's index in the robot field.
    event.partition = event.robot;
    event.robot = kNoRobot;
  }
  return true;
}

bool Reader::ReadMap(RobotMap& entry, size_t& next_robot) {
  uint64_t at = offset_;
  const uint8_t* bytes = Take(format::kMapEntryBytes, "map");
  if (bytes == nullptr) return false;
  const uint16_t robot = GetU16(bytes);
  const uint16_t same_as = GetU16(bytes + 2);
  const size_t slot = detail::FindRobot(ids_, robot);
  if (slot == ids_.size()) return Fail(at, fmt::format("map of robot {}, which is not in the header", robot));
  if (slot < next_robot) {
    return Fail(at, fmt::format("map of robot {} after robot {}; maps must be in increasing robot order", robot,
                                ids_[next_robot - 1]));
  }
  next_robot = slot + 1;
  entry.robot = robot;
  if (same_as != format::kSameAsNone) {
    const size_t source = detail::FindRobot(ids_, same_as);
    if (source == ids_.size()) {
      return Fail(at + 2, fmt::format("map of robot {} is the same as robot {}'s, which is not in the header", robot,
                                      same_as));
    }
    if (latest_[source] == nullptr) {
      return Fail(at + 2, fmt::format("map of robot {} is the same as robot {}'s, but robot {} has no map yet", robot,
                                      same_as, same_as));
    }
    entry.map = latest_[source];
    latest_[slot] = entry.map;
    return true;
  }

  auto map = std::make_shared<EpochMap>();
  at = offset_;
  if ((bytes = Take(format::kMapBodyFixedBytes, "map body")) == nullptr) return false;
  map->epoch = GetU16(bytes);
  map->mode = bytes[2];
  const uint16_t member_count = GetU16(bytes + 3);
  if (std::string problem = detail::CheckMapMode(map->mode); !problem.empty()) {
    return Fail(at + 2, fmt::format("map of robot {}: {}", robot, problem));
  }
  if (std::string problem = detail::CheckMemberCount(member_count, ids_.size()); !problem.empty()) {
    return Fail(at + 3, fmt::format("map of robot {}: {}", robot, problem));
  }
  // Grown as members are read: a short file with a large count costs nothing.
  for (uint16_t index = 0; index < member_count; ++index) {
    at = offset_;
    if ((bytes = Take(format::kMapMemberFixedBytes, "map member")) == nullptr) return false;
    MapMember member;
    member.id = GetU16(bytes);
    member.phase = bytes[2];
    member.x_mm = static_cast<int16_t>(GetU16(bytes + 3));
    member.y_mm = static_cast<int16_t>(GetU16(bytes + 5));
    member.heading_mrad = static_cast<int16_t>(GetU16(bytes + 7));
    member.vx_mm_s = static_cast<int16_t>(GetU16(bytes + 9));
    member.vy_mm_s = static_cast<int16_t>(GetU16(bytes + 11));
    const uint8_t payload_length = bytes[13];
    if (std::string problem =
            detail::CheckMember(member.id, map->members.empty() ? nullptr : &map->members.back().id, member.phase,
                                payload_length, ids_);
        !problem.empty()) {
      return Fail(at, fmt::format("map of robot {}: {}", robot, problem));
    }
    if ((bytes = Take(payload_length, "map member payload")) == nullptr) return false;
    member.payload.assign(bytes, bytes + payload_length);
    map->members.push_back(std::move(member));
  }
  entry.map = map;
  latest_[slot] = std::move(map);
  return true;
}

bool Reader::ReadEnd(uint64_t record_start) {
  const uint8_t* bytes = Take(format::kEndBytes - 1, "end marker");
  if (bytes == nullptr) return false;
  const uint32_t rounds = GetU32(bytes);
  const uint64_t events = GetU64(bytes + 4);
  const uint64_t frames = GetU64(bytes + 12);
  if (!CheckCrc(record_start, "end marker")) return false;
  if (rounds != rounds_ || events != events_ || frames != frames_) {
    return Fail(record_start + 1,
                fmt::format("end marker counts {} rounds, {} events and {} frames, but the file holds "
                            "{}, {} and {}",
                            rounds, events, frames, rounds_, events_, frames_));
  }
  if (in_.peek() != std::istream::traits_type::eof()) {
    return Fail(offset_, "unexpected bytes after the end marker");
  }
  state_ = State::kComplete;
  return false;
}

bool Reader::Next(Round& round) {
  if (state_ == State::kStart) return Fail(offset_, "Next called before ReadHeader");
  if (state_ != State::kRounds) return false;

  const uint64_t record_start = offset_;
  if (in_.peek() == std::istream::traits_type::eof()) {
    truncated_ = !in_.bad();
    return Fail(record_start, fmt::format("file ends after {} rounds without the end marker; {}", rounds_,
                                          truncated_ ? "truncated" : "I/O error"));
  }
  crc_ = 0;
  const uint8_t* bytes = Take(1, "record tag");
  if (bytes == nullptr) return false;
  if (bytes[0] == format::kEndTag) return ReadEnd(record_start);
  if (bytes[0] != format::kRoundTag) {
    return Fail(record_start, fmt::format("unknown record tag 0x{:02X} (a round starts with 'R', the end "
                                          "marker with 'E')",
                                          bytes[0]));
  }

  const size_t fixed = version_ >= 3 ? format::kRoundFixedBytes : format::kRoundFixedBytesV2;
  if ((bytes = Take(fixed - 1, "round header")) == nullptr) return false;
  const uint32_t index = GetU32(bytes);
  const int64_t time_ns = GetI64(bytes + 4);
  const uint32_t frame_count = GetU32(bytes + 12);
  const uint32_t event_count = GetU32(bytes + 16);
  const uint32_t map_count = version_ >= 3 ? GetU32(bytes + 20) : 0;
  if (std::string problem =
          detail::CheckRoundOrder(any_round_, last_index_, last_time_ns_, index, time_ns);
      !problem.empty()) {
    return Fail(record_start + 1, problem);
  }
  if (std::string problem = detail::CheckFrameCount(frame_count, ids_.size()); !problem.empty()) {
    return Fail(record_start + 13, fmt::format("round {}: {}", index, problem));
  }
  if (std::string problem = detail::CheckEventCount(event_count); !problem.empty()) {
    return Fail(record_start + 17, fmt::format("round {}: {}", index, problem));
  }
  if (std::string problem = detail::CheckMapCount(map_count, ids_.size()); !problem.empty()) {
    return Fail(record_start + 21, fmt::format("round {}: {}", index, problem));
  }

  round.index = index;
  round.time_ns = time_ns;
  round.robots.clear();
  round.events.clear();
  round.maps.clear();
  size_t next_robot = 0;
  for (uint32_t position = 0; position < frame_count; ++position) {
    RobotFrame frame;
    if (!ReadFrame(frame, next_robot)) return false;
    round.robots.push_back(frame);
  }
  for (uint32_t position = 0; position < event_count; ++position) {
    Event event;
    if (!ReadEvent(event)) return false;
    round.events.push_back(event);
  }
  size_t next_map_robot = 0;
  for (uint32_t position = 0; position < map_count; ++position) {
    RobotMap entry;
    if (!ReadMap(entry, next_map_robot)) return false;
    round.maps.push_back(std::move(entry));
  }
  if (!CheckCrc(record_start, "round")) return false;

  any_round_ = true;
  last_index_ = index;
  last_time_ns_ = time_ns;
  ++rounds_;
  events_ += event_count;
  frames_ += frame_count;
  return true;
}

}  // namespace syrof::lab::replay
