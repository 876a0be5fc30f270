#include "rules.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "syrof/lab/replay/format.h"

namespace syrof::lab::replay::detail {

std::string CheckNameLength(size_t length, const char* what) {
  if (length <= kMaxNameBytes) return {};
  return fmt::format("{} is {} bytes, more than the {} allowed", what, length, kMaxNameBytes);
}

namespace {

// Length of the UTF-8 character starting at `index`, or 0 when the bytes
// there are not one (overlong forms, surrogates and values above U+10FFFF
// included).
size_t Utf8Length(std::string_view text, size_t index) {
  const auto lead = static_cast<uint8_t>(text[index]);
  if (lead < 0x80) return 1;
  const size_t length = (lead & 0xE0) == 0xC0 ? 2 : (lead & 0xF0) == 0xE0 ? 3 : (lead & 0xF8) == 0xF0 ? 4 : 0;
  if (length == 0 || index + length > text.size()) return 0;
  uint32_t value = lead & (0x7F >> length);
  for (size_t next = 1; next < length; ++next) {
    const auto byte = static_cast<uint8_t>(text[index + next]);
    if ((byte & 0xC0) != 0x80) return 0;
    value = (value << 6) | (byte & 0x3F);
  }
  static constexpr uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (value < kSmallest[length] || value > 0x10FFFF || (value >= 0xD800 && value <= 0xDFFF)) return 0;
  return length;
}

}  // namespace

std::string CheckNameBytes(std::string_view name, const char* what) {
  for (size_t index = 0; index < name.size();) {
    const auto byte = static_cast<uint8_t>(name[index]);
    // Control characters could rewrite a terminal showing the dump.
    if (byte < 0x20 || byte == 0x7F) {
      return fmt::format("{} has control character 0x{:02X} at byte {}", what, byte, index);
    }
    // The names are shown as text: in JSON (syrof view, --format jsonl), which must be UTF-8.
    const size_t length = Utf8Length(name, index);
    if (length == 0) return fmt::format("{} is not UTF-8 at byte {}", what, index);
    index += length;
  }
  return {};
}

std::string CheckRadioRound(int64_t radio_round_ns) {
  if (radio_round_ns > 0) return {};
  return fmt::format("radio_round_ns is {}; it must be positive", radio_round_ns);
}

std::string CheckArenaSide(float side_m, const char* what) {
  if (std::isfinite(side_m) && side_m > 0) return {};
  return fmt::format("{} is {}; it must be finite and positive", what, side_m);
}

std::string CheckRobotCount(uint64_t count) {
  if (count <= kMaxRobots) return {};
  return fmt::format("robot count {} is more than the {} a replay can hold", count, kMaxRobots);
}

std::string CheckRobotId(uint16_t id, const uint16_t* previous) {
  if (id == kNoRobot) return fmt::format("robot id {} is reserved for 'no robot'", id);
  if (previous != nullptr && id <= *previous) {
    return fmt::format("robot id {} follows {}; header robot ids must increase", id, *previous);
  }
  return {};
}

std::string CheckBodyRadius(float radius_m, uint16_t id) {
  if (std::isfinite(radius_m) && radius_m >= 0) return {};
  return fmt::format("robot {} has body radius {}; it must be finite and not negative", id, radius_m);
}

std::string CheckAnchorCount(uint64_t count) {
  if (count <= kMaxAnchors) return {};
  return fmt::format("anchor count {} is more than the {} allowed", count, kMaxAnchors);
}

std::string CheckAnchor(const AnchorInfo& anchor, size_t index) {
  if (std::isfinite(anchor.x_m) && std::isfinite(anchor.y_m)) return {};
  return fmt::format("anchor {} at ({}, {}) is not finite", index, anchor.x_m, anchor.y_m);
}

std::string CheckInputCount(uint64_t count, uint16_t id) {
  if (count <= kMaxInputsPerRobot) return {};
  return fmt::format("robot {} has {} private inputs; at most {}", id, count, kMaxInputsPerRobot);
}

std::string CheckInput(const InputValue& input, std::span<const InputValue> earlier, uint16_t id) {
  if (input.name.empty()) return fmt::format("robot {}'s input {} has an empty name", id, earlier.size());
  if (std::string problem = CheckNameLength(input.name.size(), "input name"); !problem.empty()) return problem;
  if (std::string problem = CheckNameBytes(input.name, "input name"); !problem.empty()) return problem;
  for (const InputValue& other : earlier) {
    if (other.name == input.name) return fmt::format("robot {} has the input '{}' twice", id, input.name);
  }
  if (!std::isfinite(input.value)) return fmt::format("robot {}'s input '{}' is not finite", id, input.name);
  return {};
}

std::string CheckFieldCount(uint64_t count) {
  if (count >= 1 && count <= kMaxPayloadBytes) return {};
  return fmt::format("message field count {} is not in [1, {}]", count, kMaxPayloadBytes);
}

std::string CheckFieldType(uint8_t type) {
  if (type < message::kFieldTypeCount) return {};
  return fmt::format("unknown message field type {}", type);
}

std::string CheckField(const message::MessageField& field, std::span<const message::MessageField> earlier) {
  if (!message::IsFieldName(field.name)) return fmt::format("message field name '{}' is not a field name", field.name);
  size_t length = 0;
  for (const message::MessageField& other : earlier) {
    if (other.name == field.name) return fmt::format("message field '{}' is named twice", field.name);
    length += message::FieldBytes(other.type);
  }
  if (field.offset != length) return fmt::format("message field '{}' is not at offset {}", field.name, length);
  if (length + message::FieldBytes(field.type) > kMaxPayloadBytes) {
    return fmt::format("message fields up to '{}' take more than {} bytes", field.name, kMaxPayloadBytes);
  }
  return {};
}

std::string CheckMessage(const message::MessageFormat& format) {
  if (format.none) {
    return format.fields.empty() && format.length == 0 ? "" : "a message format 'none' with fields";
  }
  if (std::string problem = CheckFieldCount(format.fields.size()); !problem.empty()) return problem;
  for (size_t index = 0; index < format.fields.size(); ++index) {
    if (std::string problem = CheckFieldType(static_cast<uint8_t>(format.fields[index].type)); !problem.empty()) {
      return problem;
    }
    const std::span<const message::MessageField> earlier(format.fields.data(), index);
    if (std::string problem = CheckField(format.fields[index], earlier); !problem.empty()) return problem;
  }
  const message::MessageField& last = format.fields.back();
  if (format.length != last.offset + message::FieldBytes(last.type)) return "a message format's length is not its fields'";
  return {};
}

std::string CheckRoundOrder(bool any_round, uint32_t last_index, int64_t last_time_ns,
                            uint32_t index, int64_t time_ns) {
  if (!any_round) return {};
  if (index <= last_index) {
    return fmt::format("round index {} does not follow round {}; round indices must increase", index,
                       last_index);
  }
  if (time_ns < last_time_ns) {
    return fmt::format("round {} at {} ns is before the previous round's {} ns", index, time_ns,
                       last_time_ns);
  }
  return {};
}

std::string CheckFrameCount(uint64_t count, size_t robot_count) {
  if (count <= robot_count) return {};
  return fmt::format("frame count {} is more than the header's {} robots", count, robot_count);
}

std::string CheckEventCount(uint64_t count) {
  if (count <= kMaxEventsPerRound) return {};
  return fmt::format("event count {} is more than the {} allowed per round", count,
                     kMaxEventsPerRound);
}

size_t FindRobot(std::span<const uint16_t> ids, uint16_t id) {
  const auto found = std::lower_bound(ids.begin(), ids.end(), id);
  if (found == ids.end() || *found != id) return ids.size();
  return static_cast<size_t>(found - ids.begin());
}

uint8_t PackState(const RobotFrame& frame, std::string& problem) {
  const auto presence = static_cast<uint8_t>(frame.presence);
  if (presence > static_cast<uint8_t>(Presence::kCrashed)) {
    problem = fmt::format("robot {} has presence {}, not a Presence", frame.id, presence);
  } else if (frame.status > format::kMaxStatus) {
    problem = fmt::format("robot {} has status {}; 0 member or 1 joining", frame.id, frame.status);
  } else if (frame.phase > format::kMaxPhase) {
    problem = fmt::format("robot {} has phase {}; 0 .. {}", frame.id, frame.phase, format::kMaxPhase);
  } else if (frame.mode > format::kMaxMode) {
    problem = fmt::format("robot {} has mode {}; 0 .. {}", frame.id, frame.mode, format::kMaxMode);
  } else {
    problem.clear();
  }
  return static_cast<uint8_t>(presence << format::kPresenceShift |
                              frame.status << format::kStatusShift |
                              frame.phase << format::kPhaseShift | frame.mode << format::kModeShift);
}

std::string UnpackState(uint8_t state, RobotFrame& frame) {
  if ((state & format::kStateReservedMask) != 0) {
    return fmt::format("robot {} state byte 0x{:02X} has reserved bits set", frame.id, state);
  }
  const auto phase = static_cast<uint8_t>((state >> format::kPhaseShift) & 3);
  if (phase > format::kMaxPhase) {
    return fmt::format("robot {} has phase {}; 0 .. {}", frame.id, phase, format::kMaxPhase);
  }
  frame.presence = static_cast<Presence>((state >> format::kPresenceShift) & 3);
  frame.status = static_cast<uint8_t>((state >> format::kStatusShift) & 1);
  frame.phase = phase;
  frame.mode = static_cast<uint8_t>((state >> format::kModeShift) & 1);
  return {};
}

std::string CheckEventKind(uint8_t kind, uint16_t version) {
  if (kind <= static_cast<uint8_t>(LastEventKind(version))) return {};
  return fmt::format("unknown event kind {} (format version {})", kind, version);
}

std::string CheckEventRobot(uint16_t robot, std::span<const uint16_t> ids, const char* what) {
  if (robot == kNoRobot || FindRobot(ids, robot) < ids.size()) return {};
  return fmt::format("event {} {} is not a robot of the header", what, robot);
}

std::string CheckEvent(const Event& event, std::span<const uint16_t> ids) {
  std::string problem = CheckEventKind(static_cast<uint8_t>(event.kind));
  if (problem.empty()) problem = CheckEventRobot(event.robot, ids, "robot");
  if (problem.empty()) problem = CheckEventRobot(event.other, ids, "other");
  if (problem.empty()) problem = CheckEventPartition(event);
  return problem;
}

std::string CheckEventPartition(const Event& event) {
  if (IsPartitionEvent(event.kind)) {
    if (event.partition == kNoPartition) {
      return fmt::format("{} event names no partition (partition {} means none)", ToString(event.kind),
                         kNoPartition);
    }
    if (event.robot != kNoRobot || event.other != kNoRobot) {
      return fmt::format("{} event names robot {} and other {}; a partition event names no robot",
                         ToString(event.kind), event.robot, event.other);
    }
  } else if (event.partition != kNoPartition) {
    return fmt::format("{} event names partition {}; only partition events do", ToString(event.kind),
                       event.partition);
  }
  return {};
}

std::string CheckMapCount(uint64_t count, size_t robot_count) {
  if (count <= robot_count) return {};
  return fmt::format("map count {} is more than the header's {} robots", count, robot_count);
}

std::string CheckMapMode(uint8_t mode) {
  if (mode <= format::kMaxMode) return {};
  return fmt::format("map mode {}; 0 COOPERATIVE or 1 AUTONOMOUS", mode);
}

std::string CheckMemberCount(uint64_t count, size_t robot_count) {
  if (count <= robot_count) return {};
  return fmt::format("member count {} is more than the header's {} robots", count, robot_count);
}

std::string CheckMember(uint16_t id, const uint16_t* previous, uint8_t phase, size_t payload_length,
                        std::span<const uint16_t> ids) {
  if (FindRobot(ids, id) == ids.size()) return fmt::format("map member {} is not a robot of the header", id);
  if (previous != nullptr && id <= *previous) {
    return fmt::format("map member {} follows member {}; members must be in increasing id order", id, *previous);
  }
  if (phase > format::kMaxPhase) return fmt::format("map member {} has phase {}; 0 .. {}", id, phase, format::kMaxPhase);
  if (payload_length > kMaxPayloadBytes) {
    return fmt::format("map member {} has a payload of {} bytes, more than the {} allowed", id, payload_length,
                       kMaxPayloadBytes);
  }
  return {};
}

std::string CheckMap(const EpochMap& map, std::span<const uint16_t> ids) {
  std::string problem = CheckMapMode(map.mode);
  if (problem.empty()) problem = CheckMemberCount(map.members.size(), ids.size());
  // Members and header ids both increase, so one walk finds every member;
  // CheckMember (a search per member, and a string) words what is wrong.
  size_t cursor = 0;
  for (size_t index = 0; problem.empty() && index < map.members.size(); ++index) {
    const MapMember& member = map.members[index];
    const uint16_t* previous = index == 0 ? nullptr : &map.members[index - 1].id;
    const bool increasing = previous == nullptr || member.id > *previous;
    if (increasing) {
      while (cursor < ids.size() && ids[cursor] < member.id) ++cursor;
    }
    const bool fits = increasing && cursor < ids.size() && ids[cursor] == member.id &&
                      member.phase <= format::kMaxPhase && member.payload.size() <= kMaxPayloadBytes;
    if (!fits) problem = CheckMember(member.id, previous, member.phase, member.payload.size(), ids);
  }
  return problem;
}

}  // namespace syrof::lab::replay::detail
