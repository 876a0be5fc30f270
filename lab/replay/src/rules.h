// The rules a replay's values obey, defined once for the writer (which
// refuses input breaking them) and the reader (which refuses a file breaking
// them). Each Check returns "" when the value is fine, else what is wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay::detail {

std::string CheckNameLength(size_t length, const char* what);
std::string CheckNameBytes(std::string_view name, const char* what);
std::string CheckRadioRound(int64_t radio_round_ns);
std::string CheckArenaSide(float side_m, const char* what);
std::string CheckRobotCount(uint64_t count);
/// `previous` is the id before `id` in the header, or nullptr for the first.
std::string CheckRobotId(uint16_t id, const uint16_t* previous);
std::string CheckBodyRadius(float radius_m, uint16_t id);
std::string CheckAnchorCount(uint64_t count);
std::string CheckAnchor(const AnchorInfo& anchor, size_t index);
std::string CheckInputCount(uint64_t count, uint16_t id);
// An input's name (a name's rules, not empty, not an earlier input's) and value.
std::string CheckInput(const InputValue& input, std::span<const InputValue> earlier, uint16_t id);
std::string CheckFieldCount(uint64_t count);
std::string CheckFieldType(uint8_t type);
// A message field's name, unique among `earlier`, and the format's length
// with it at most kMaxPayloadBytes.
std::string CheckField(const message::MessageField& field, std::span<const message::MessageField> earlier);
// A whole format as the writer receives it (offsets and length included).
std::string CheckMessage(const message::MessageFormat& format);

std::string CheckRoundOrder(bool any_round, uint32_t last_index, int64_t last_time_ns,
                            uint32_t index, int64_t time_ns);
std::string CheckFrameCount(uint64_t count, size_t robot_count);
std::string CheckEventCount(uint64_t count);

/// Index of `id` in the increasing `ids`, or ids.size() when absent.
size_t FindRobot(std::span<const uint16_t> ids, uint16_t id);

/// The frame's state byte (format.h); "" in `problem` unless a field does not fit.
uint8_t PackState(const RobotFrame& frame, std::string& problem);
/// Fills presence, status, phase and mode from a state byte; "" when valid.
std::string UnpackState(uint8_t state, RobotFrame& frame);

/// An event's fields outside the rules; "" when fine.
std::string CheckEvent(const Event& event, std::span<const uint16_t> ids);  // kFormatVersion's kinds
/// A version-3 event's partition field against its kind (a partition event
/// names a partition and no robot; any other kind names no partition).
std::string CheckEventPartition(const Event& event);

std::string CheckMapCount(uint64_t count, size_t robot_count);
/// A map's mode (0 .. 1) and member count (at most the header's robots).
std::string CheckMapMode(uint8_t mode);
std::string CheckMemberCount(uint64_t count, size_t robot_count);
/// A member: a header id above `previous` (nullptr for the first), phase
/// 0 .. 2, payload at most kMaxPayloadBytes.
std::string CheckMember(uint16_t id, const uint16_t* previous, uint8_t phase, size_t payload_length,
                        std::span<const uint16_t> ids);
/// A whole map, for the writer.
std::string CheckMap(const EpochMap& map, std::span<const uint16_t> ids);
std::string CheckEventKind(uint8_t kind, uint16_t version = kFormatVersion);
std::string CheckEventRobot(uint16_t robot, std::span<const uint16_t> ids, const char* what);

}  // namespace syrof::lab::replay::detail
