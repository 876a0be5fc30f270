// A message format: what the bytes of a robot's payload (sendMessageData,
// at most SYROF_APP_MAX_PAYLOAD_BYTES) mean, as an assignment declares it
// (`message:` in assignment.yaml or a scenario file; docs/grading.md, "The
// message format"). One definition drives the grader's check of every
// payload a robot sets (`syrof grade --mix`) and the viewer's decoding of
// each member's payload, so the two cannot drift.
//
// A format is `none` (the robots send nothing: every payload set must be
// empty) or a list of fields laid end to end, offsets implicit in order,
// the total length fixed. Setting an empty payload (clearing it: "nothing
// told yet") is allowed by every format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/lab/base/error.h"

namespace syrof::lab::message {

/// A field's type: its width, signedness and byte order.
enum class FieldType : uint8_t { kU8, kI8, kU16Be, kU16Le, kI16Be, kI16Le, kU32Be, kU32Le, kI32Be, kI32Le };

/// "u8", "i16be", ...: the names the YAML uses, in FieldType order.
inline constexpr std::string_view kFieldTypeNames[] = {"u8",    "i8",    "u16be", "u16le", "i16be",
                                                       "i16le", "u32be", "u32le", "i32be", "i32le"};

/// Types there are: a FieldType value stored as a byte (in a replay) is
/// below this.
inline constexpr size_t kFieldTypeCount = std::size(kFieldTypeNames);

/// Bytes a value of `type` takes.
size_t FieldBytes(FieldType type);

/// 1 to 32 of a-z, 0-9 and '_', starting with a letter.
bool IsFieldName(std::string_view name);

struct MessageField {
  std::string name;  ///< 1 to 32 of a-z 0-9 _, starting with a letter; unique in the format
  FieldType type = FieldType::kU8;
  size_t offset = 0;  ///< bytes before it: the sum of the earlier fields' sizes

  bool operator==(const MessageField& other) const = default;
};

struct MessageFormat {
  /// `message: none`: no field, and every payload set must be empty.
  bool none = true;
  std::vector<MessageField> fields;  ///< empty for `none`
  size_t length = 0;                 ///< the payload's bytes: the fields' sizes added up

  /// "none", or "2 bytes: charge u16be".
  std::string ToString() const;

  bool operator==(const MessageFormat& other) const = default;
};

/// Why a payload of `payload_length` bytes breaks `format` (where "payload",
/// message "10 bytes, but the format has 2"), or nothing when it fits:
/// empty, or exactly format.length bytes of a non-`none` format. The length
/// may be more than a beacon holds (a refused sendMessageData is checked
/// too).
std::optional<Error> CheckPayload(const MessageFormat& format, size_t payload_length);

/// One decoded field of a payload.
struct FieldValue {
  std::string_view name;  ///< the format's field name (the format outlives it)
  int64_t value = 0;
};

/// The fields of `payload` under `format`; empty when the payload does not
/// fit it (CheckPayload is not "") or is empty.
std::vector<FieldValue> DecodePayload(const MessageFormat& format, std::span<const uint8_t> payload);

}  // namespace syrof::lab::message
