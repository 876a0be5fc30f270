// Message formats: sizes, the payload check and the decoder.
#include "syrof/lab/message/message_format.h"

namespace syrof::lab::message {

size_t FieldBytes(FieldType type) {
  switch (type) {
    case FieldType::kU8:
    case FieldType::kI8:
      return 1;
    case FieldType::kU16Be:
    case FieldType::kU16Le:
    case FieldType::kI16Be:
    case FieldType::kI16Le:
      return 2;
    default:
      return 4;
  }
}

std::string MessageFormat::ToString() const {
  if (none) return "none";
  std::string text = std::to_string(length) + (length == 1 ? " byte:" : " bytes:");
  for (size_t i = 0; i < fields.size(); ++i) {
    text += (i == 0 ? " " : ", ") + fields[i].name + " " +
            std::string(kFieldTypeNames[static_cast<size_t>(fields[i].type)]);
  }
  return text;
}

std::optional<Error> CheckPayload(const MessageFormat& format, size_t payload_length) {
  if (payload_length == 0 || (!format.none && payload_length == format.length)) return std::nullopt;
  if (format.none) {
    return Error{.where = "payload",
                 .message = std::to_string(payload_length) + " bytes, but the format is none (send nothing)"};
  }
  return Error{.where = "payload",
               .message = std::to_string(payload_length) + " bytes, but the format has " + std::to_string(format.length)};
}

namespace {

bool IsBigEndian(FieldType type) {
  return type == FieldType::kU16Be || type == FieldType::kI16Be || type == FieldType::kU32Be ||
         type == FieldType::kI32Be;
}
bool IsSigned(FieldType type) {
  return type == FieldType::kI8 || type == FieldType::kI16Be || type == FieldType::kI16Le ||
         type == FieldType::kI32Be || type == FieldType::kI32Le;
}

int64_t DecodeField(FieldType type, std::span<const uint8_t> bytes) {
  const size_t size = FieldBytes(type);
  uint64_t raw = 0;
  for (size_t i = 0; i < size; ++i) {
    const uint8_t byte = IsBigEndian(type) ? bytes[i] : bytes[size - 1 - i];
    raw = (raw << 8) | byte;
  }
  if (IsSigned(type) && (raw >> (8 * size - 1)) != 0) return static_cast<int64_t>(raw) - (int64_t{1} << (8 * size));
  return static_cast<int64_t>(raw);
}

}  // namespace

bool IsFieldName(std::string_view name) {
  if (name.empty() || name.size() > 32 || name[0] < 'a' || name[0] > 'z') return false;
  for (char c : name) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return true;
}

std::vector<FieldValue> DecodePayload(const MessageFormat& format, std::span<const uint8_t> payload) {
  std::vector<FieldValue> values;
  if (payload.empty() || CheckPayload(format, payload.size())) return values;
  for (const MessageField& field : format.fields) {
    values.push_back({field.name, DecodeField(field.type, payload.subspan(field.offset, FieldBytes(field.type)))});
  }
  return values;
}

}  // namespace syrof::lab::message
