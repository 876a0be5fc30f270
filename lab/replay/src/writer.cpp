#include "syrof/lab/replay/writer.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>

#include "little_endian.h"
#include "rules.h"
#include "syrof/lab/replay/format.h"

namespace syrof::lab::replay {
namespace {

using detail::PutF32;
using detail::PutI64;
using detail::PutU16;
using detail::PutU32;
using detail::PutU64;
using detail::PutF64;
using detail::PutU8;

bool SameBits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

std::string CheckHeader(const Header& header) {
  std::string problem = detail::CheckRadioRound(header.radio_round_ns);
  if (problem.empty()) problem = detail::CheckArenaSide(header.arena_width_m, "arena_width_m");
  if (problem.empty()) problem = detail::CheckArenaSide(header.arena_height_m, "arena_height_m");
  if (problem.empty()) problem = detail::CheckNameLength(header.scenario_name.size(), "scenario_name");
  if (problem.empty()) problem = detail::CheckNameBytes(header.scenario_name, "scenario_name");
  if (problem.empty()) problem = detail::CheckNameLength(header.app_name.size(), "app_name");
  if (problem.empty()) problem = detail::CheckNameBytes(header.app_name, "app_name");
  if (problem.empty()) problem = detail::CheckRobotCount(header.robots.size());
  for (size_t index = 0; problem.empty() && index < header.robots.size(); ++index) {
    const RobotInfo& robot = header.robots[index];
    problem = detail::CheckRobotId(robot.id, index == 0 ? nullptr : &header.robots[index - 1].id);
    if (problem.empty()) problem = detail::CheckBodyRadius(robot.body_radius_m, robot.id);
  }
  if (problem.empty()) problem = detail::CheckAnchorCount(header.anchors.size());
  for (size_t index = 0; problem.empty() && index < header.anchors.size(); ++index) {
    problem = detail::CheckAnchor(header.anchors[index], index);
  }
  for (const RobotInfo& robot : header.robots) {
    if (problem.empty()) problem = detail::CheckInputCount(robot.inputs.size(), robot.id);
    for (size_t index = 0; problem.empty() && index < robot.inputs.size(); ++index) {
      problem = detail::CheckInput(robot.inputs[index], {robot.inputs.data(), index}, robot.id);
    }
  }
  if (problem.empty() && header.message) problem = detail::CheckMessage(*header.message);
  return problem;
}

void PutName(std::vector<uint8_t>& out, const std::string& name) {
  PutU16(out, static_cast<uint16_t>(name.size()));
  out.insert(out.end(), name.begin(), name.end());
}

}  // namespace

Writer::Writer(std::ostream& out, const Header& header) : out_(out) {
  if (std::string problem = CheckHeader(header); !problem.empty()) {
    Fail(problem, "header");
    return;
  }
  ids_.reserve(header.robots.size());
  previous_.resize(header.robots.size());
  latest_.resize(header.robots.size());
  latest_hash_.resize(header.robots.size());
  for (size_t index = 0; index < header.robots.size(); ++index) {
    ids_.push_back(header.robots[index].id);
    previous_[index].id = header.robots[index].id;
  }

  buffer_.assign(format::kMagic.begin(), format::kMagic.end());
  PutU16(buffer_, kFormatVersion);
  PutU64(buffer_, header.seed);
  PutI64(buffer_, header.radio_round_ns);
  PutF32(buffer_, header.arena_width_m);
  PutF32(buffer_, header.arena_height_m);
  PutName(buffer_, header.scenario_name);
  PutName(buffer_, header.app_name);
  PutU32(buffer_, static_cast<uint32_t>(header.robots.size()));
  for (const RobotInfo& robot : header.robots) {
    PutU16(buffer_, robot.id);
    PutU8(buffer_, robot.kind);
    PutF32(buffer_, robot.body_radius_m);
  }
  PutU16(buffer_, static_cast<uint16_t>(header.anchors.size()));
  for (const AnchorInfo& anchor : header.anchors) {
    PutF32(buffer_, anchor.x_m);
    PutF32(buffer_, anchor.y_m);
  }
  for (const RobotInfo& robot : header.robots) {
    PutU8(buffer_, static_cast<uint8_t>(robot.inputs.size()));
    for (const InputValue& input : robot.inputs) {
      PutName(buffer_, input.name);
      PutF64(buffer_, input.value);
    }
  }
  if (!header.message) {
    PutU8(buffer_, format::kMessageUndeclared);
  } else if (header.message->none) {
    PutU8(buffer_, format::kMessageNone);
  } else {
    PutU8(buffer_, format::kMessageFields);
    PutU8(buffer_, static_cast<uint8_t>(header.message->fields.size()));
    for (const message::MessageField& field : header.message->fields) {
      PutName(buffer_, field.name);
      PutU8(buffer_, static_cast<uint8_t>(field.type));
    }
  }
  Emit();
}

bool Writer::ok() const { return state_ != State::kFailed && out_.good(); }

void Writer::Fail(std::string message, std::string where) {
  state_ = State::kFailed;
  error_ = Error{.where = std::move(where), .message = std::move(message)};
}

void Writer::Emit() {
  PutU32(buffer_, format::Crc32(buffer_));
  out_.write(reinterpret_cast<const char*>(buffer_.data()), static_cast<std::streamsize>(buffer_.size()));
  if (!out_.good()) {
    Fail(fmt::format("writing to the output stream failed after {} bytes", bytes_written_));
    return;
  }
  bytes_written_ += buffer_.size();
}

std::string Writer::CheckRound(uint32_t index, int64_t time_ns, std::span<const RobotFrame> robots,
                               std::span<const Event> events, std::span<const RobotMap> maps) const {
  std::string problem = detail::CheckRoundOrder(any_round_, last_index_, last_time_ns_, index, time_ns);
  if (problem.empty()) problem = detail::CheckFrameCount(robots.size(), ids_.size());
  if (problem.empty()) problem = detail::CheckEventCount(events.size());
  for (size_t position = 0; problem.empty() && position < robots.size(); ++position) {
    const RobotFrame& frame = robots[position];
    if (position > 0 && frame.id <= robots[position - 1].id) {
      problem = fmt::format("frame of robot {} follows robot {}; frames must be in increasing id order",
                            frame.id, robots[position - 1].id);
    } else if (detail::FindRobot(ids_, frame.id) == ids_.size()) {
      problem = fmt::format("frame of robot {}, which is not in the header", frame.id);
    } else {
      detail::PackState(frame, problem);
    }
  }
  for (size_t position = 0; problem.empty() && position < events.size(); ++position) {
    problem = detail::CheckEvent(events[position], ids_);
  }
  if (problem.empty()) problem = detail::CheckMapCount(maps.size(), ids_.size());
  for (size_t position = 0; problem.empty() && position < maps.size(); ++position) {
    const RobotMap& entry = maps[position];
    if (position > 0 && entry.robot <= maps[position - 1].robot) {
      problem = fmt::format("map of robot {} follows robot {}; maps must be in increasing robot order", entry.robot,
                            maps[position - 1].robot);
    } else if (detail::FindRobot(ids_, entry.robot) == ids_.size()) {
      problem = fmt::format("map of robot {}, which is not in the header", entry.robot);
    } else if (entry.map == nullptr) {
      problem = fmt::format("map of robot {} is null", entry.robot);
    } else if (position > 0 && entry.map == maps[position - 1].map) {
      // The same map as the robot before (a caller that shares equal maps): checked.
    } else if (std::string map_problem = detail::CheckMap(*entry.map, ids_); !map_problem.empty()) {
      problem = fmt::format("map of robot {}: {}", entry.robot, map_problem);
    }
  }
  if (!problem.empty()) problem = fmt::format("round {}: {}", index, problem);
  return problem;
}

namespace {

// A hash of a map's contents, a word at a time (a multiply and a shift per
// word; the byte-wise FNV-1a it replaced cost eight of each, which at 1000
// members and 1000 robots was 40% of a run). Equal maps hash equal;
// candidates with the same hash are compared in full before a reference is
// written, so the hash never decides what the file holds, only how fast an
// equal map is found.
uint64_t MapHash(const EpochMap& map) {
  uint64_t hash = 0xCBF29CE484222325ULL;
  auto mix = [&hash](uint64_t value) {
    hash = (hash ^ value) * 0x9E3779B97F4A7C15ULL;
    hash ^= hash >> 29;
  };
  mix(map.epoch);
  mix(map.mode);
  mix(map.members.size());
  for (const MapMember& member : map.members) {
    mix(member.id | uint64_t{member.phase} << 16 | uint64_t{member.payload.size()} << 24);
    mix(static_cast<uint16_t>(member.x_mm) | uint64_t{static_cast<uint16_t>(member.y_mm)} << 16 |
        uint64_t{static_cast<uint16_t>(member.heading_mrad)} << 32);
    mix(static_cast<uint16_t>(member.vx_mm_s) | uint64_t{static_cast<uint16_t>(member.vy_mm_s)} << 16);
    for (const uint8_t byte : member.payload) mix(byte);
  }
  return hash;
}

}  // namespace

void Writer::PutMap(size_t slot, const std::shared_ptr<const EpochMap>& map) {
  PutU16(buffer_, ids_[slot]);
  // A map handed again (the caller shares equal maps between robots) has
  // the hash it had; the held pointer keeps its address from being reused.
  if (map != hashed_map_) {
    hashed_map_ = map;
    hashed_map_hash_ = MapHash(*map);
    hashed_map_equal_.reset();
  }
  const uint64_t hash = hashed_map_hash_;
  // The robot's previous map is no longer what it holds.
  if (latest_[slot] != nullptr) by_hash_.erase({latest_hash_[slot], slot});
  // Another robot holding an equal map: the lowest slot, so the choice
  // depends only on the calls (same calls, same bytes). The index is
  // ordered by (hash, slot), so the first equal candidate is the answer:
  // one full comparison in the common case (every robot holding the same
  // map), none when it is the same map object or one found equal to it
  // before.
  size_t source = ids_.size();
  for (auto entry = by_hash_.lower_bound({hash, 0}); entry != by_hash_.end() && entry->first == hash; ++entry) {
    const std::shared_ptr<const EpochMap>& held = latest_[entry->second];
    if (held == map || held == hashed_map_equal_ || *held == *map) {
      source = entry->second;
      hashed_map_equal_ = held;
      break;
    }
  }
  if (source < ids_.size()) {
    PutU16(buffer_, ids_[source]);
    latest_[slot] = latest_[source];
  } else {
    PutU16(buffer_, format::kSameAsNone);
    PutU16(buffer_, map->epoch);
    PutU8(buffer_, map->mode);
    PutU16(buffer_, static_cast<uint16_t>(map->members.size()));
    for (const MapMember& member : map->members) {
      PutU16(buffer_, member.id);
      PutU8(buffer_, member.phase);
      for (const int16_t value : {member.x_mm, member.y_mm, member.heading_mrad, member.vx_mm_s, member.vy_mm_s}) {
        PutU16(buffer_, static_cast<uint16_t>(value));
      }
      PutU8(buffer_, static_cast<uint8_t>(member.payload.size()));
      buffer_.insert(buffer_.end(), member.payload.begin(), member.payload.end());
    }
    latest_[slot] = map;
  }
  latest_hash_[slot] = hash;
  by_hash_.insert({hash, slot});
}

void Writer::WriteRound(uint32_t index, int64_t time_ns, std::span<const RobotFrame> robots,
                        std::span<const Event> events, std::span<const RobotMap> maps) {
  if (state_ == State::kFinished) Fail("WriteRound after Finish");
  if (state_ != State::kWriting) return;
  if (std::string problem = CheckRound(index, time_ns, robots, events, maps); !problem.empty()) {
    Fail(std::move(problem));
    return;
  }

  buffer_.clear();
  PutU8(buffer_, format::kRoundTag);
  PutU32(buffer_, index);
  PutI64(buffer_, time_ns);
  PutU32(buffer_, static_cast<uint32_t>(robots.size()));
  PutU32(buffer_, static_cast<uint32_t>(events.size()));
  PutU32(buffer_, static_cast<uint32_t>(maps.size()));
  size_t slot = 0;  // frames and ids_ both increase, so one walk finds every slot
  for (const RobotFrame& frame : robots) {
    while (ids_[slot] != frame.id) ++slot;
    RobotFrame& previous = previous_[slot];
    std::string unused;
    const uint8_t state = detail::PackState(frame, unused);
    uint8_t changed = 0;
    if (frame.epoch != previous.epoch) changed |= format::kChangedEpoch;
    if (!SameBits(frame.true_x_m, previous.true_x_m)) changed |= format::kChangedTrueX;
    if (!SameBits(frame.true_y_m, previous.true_y_m)) changed |= format::kChangedTrueY;
    if (!SameBits(frame.true_heading_rad, previous.true_heading_rad)) changed |= format::kChangedTrueHeading;
    if (!SameBits(frame.est_x_m, previous.est_x_m)) changed |= format::kChangedEstX;
    if (!SameBits(frame.est_y_m, previous.est_y_m)) changed |= format::kChangedEstY;
    if (!SameBits(frame.est_heading_rad, previous.est_heading_rad)) changed |= format::kChangedEstHeading;
    PutU16(buffer_, frame.id);
    PutU8(buffer_, state);
    PutU8(buffer_, changed);
    if (changed & format::kChangedEpoch) PutU16(buffer_, frame.epoch);
    if (changed & format::kChangedTrueX) PutF32(buffer_, frame.true_x_m);
    if (changed & format::kChangedTrueY) PutF32(buffer_, frame.true_y_m);
    if (changed & format::kChangedTrueHeading) PutF32(buffer_, frame.true_heading_rad);
    if (changed & format::kChangedEstX) PutF32(buffer_, frame.est_x_m);
    if (changed & format::kChangedEstY) PutF32(buffer_, frame.est_y_m);
    if (changed & format::kChangedEstHeading) PutF32(buffer_, frame.est_heading_rad);
    previous = frame;
  }
  for (const Event& event : events) {
    PutU8(buffer_, static_cast<uint8_t>(event.kind));
    PutU16(buffer_, event.robot);
    PutU16(buffer_, event.other);
    PutU16(buffer_, event.epoch);
    PutU8(buffer_, event.mode);
    PutI64(buffer_, event.time_ns);
    PutU16(buffer_, event.partition);
  }
  // In order: a reference may name a robot whose map came earlier in this
  // round, as the reader resolves it.
  for (const RobotMap& entry : maps) PutMap(detail::FindRobot(ids_, entry.robot), entry.map);
  Emit();
  any_round_ = true;
  last_index_ = index;
  last_time_ns_ = time_ns;
  ++rounds_;
  events_ += events.size();
  frames_ += robots.size();
}

void Writer::Finish() {
  if (state_ != State::kWriting) return;
  buffer_.clear();
  PutU8(buffer_, format::kEndTag);
  PutU32(buffer_, rounds_);
  PutU64(buffer_, events_);
  PutU64(buffer_, frames_);
  Emit();
  if (state_ == State::kFailed) return;
  out_.flush();
  if (!out_.good()) {
    Fail("flushing the output stream failed");
    return;
  }
  state_ = State::kFinished;
}

}  // namespace syrof::lab::replay
