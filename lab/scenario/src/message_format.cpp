// Message formats: the pure part (sizes, check, decode) and the YAML reader
// of `message:` (docs/grading.md, "The assignment file").
#include "syrof/lab/scenario/message_format.h"

#include <set>

#include "syrof/lab/scenario/yaml/document.h"
#include "syrof/wire/beacon.h"

namespace syrof::lab::scenario {

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

std::string CheckPayload(const MessageFormat& format, size_t payload_length) {
  if (payload_length == 0) return {};
  if (format.none) return std::to_string(payload_length) + " bytes, but the format is none (send nothing)";
  if (payload_length == format.length) return {};
  return std::to_string(payload_length) + " bytes, but the format has " + std::to_string(format.length);
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

bool IsFieldName(const std::string& name) {
  if (name.empty() || name.size() > 32 || name[0] < 'a' || name[0] > 'z') return false;
  for (char c : name) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return true;
}

}  // namespace

std::vector<FieldValue> DecodePayload(const MessageFormat& format, std::span<const uint8_t> payload) {
  std::vector<FieldValue> values;
  if (payload.empty() || !CheckPayload(format, payload.size()).empty()) return values;
  for (const MessageField& field : format.fields) {
    values.push_back({field.name, DecodeField(field.type, payload.subspan(field.offset, FieldBytes(field.type)))});
  }
  return values;
}

bool ReadMessageFormat(const YamlNode& node, const std::string& path, MessageFormat& format,
                       Diagnostics& diagnostics) {
  format = MessageFormat{};
  if (node.is_scalar() && !node.quoted && node.scalar == "none") return true;
  if (!node.is_map()) {
    return FailAt(node, path,
                  "expected 'none' (the robots send nothing) or a map with 'length' and 'fields', e.g. "
                  "{ length: 2, fields: [ { name: charge, type: u16be } ] }",
                  diagnostics);
  }
  static constexpr std::string_view kKeys[] = {"length", "fields"};
  int64_t length = 0;
  if (!CheckKeys(node, path, kKeys, diagnostics) || !RequireKey(node, path, "length", diagnostics) ||
      !RequireKey(node, path, "fields", diagnostics) ||
      !ReadIntegerAt(node, path, "length", 1, static_cast<int64_t>(wire::kMaxPayloadBytes), length, diagnostics)) {
    return false;
  }
  const YamlNode& fields = *node.Find("fields");
  const std::string fields_path = JoinPath(path, "fields");
  if (!ExpectList(fields, fields_path, diagnostics)) return false;
  if (fields.values.empty()) {
    return FailAt(fields, fields_path, "needs at least one field (write 'message: none' for no message)",
                  diagnostics);
  }
  format.none = false;
  std::set<std::string> names;
  for (size_t i = 0; i < fields.values.size(); ++i) {
    const YamlNode& entry = fields.values[i];
    const std::string at = IndexPath(fields_path, i);
    static constexpr std::string_view kFieldKeys[] = {"name", "type"};
    MessageField field;
    size_t type = 0;
    if (!ExpectMap(entry, at, diagnostics) || !CheckKeys(entry, at, kFieldKeys, diagnostics) ||
        !RequireKey(entry, at, "name", diagnostics) || !RequireKey(entry, at, "type", diagnostics) ||
        !ReadString(*entry.Find("name"), JoinPath(at, "name"), field.name, diagnostics) ||
        !ReadChoice(*entry.Find("type"), JoinPath(at, "type"), kFieldTypeNames, type, diagnostics)) {
      return false;
    }
    if (!IsFieldName(field.name)) {
      return FailAt(*entry.Find("name"), JoinPath(at, "name"),
                    "a field's name must be 1 to 32 of a-z, 0-9 and '_', starting with a letter, got '" +
                        field.name + "'",
                    diagnostics);
    }
    if (!names.insert(field.name).second) {
      return FailAt(*entry.Find("name"), JoinPath(at, "name"), "another field is already named '" + field.name + "'",
                    diagnostics);
    }
    field.type = static_cast<FieldType>(type);
    field.offset = format.length;
    format.length += FieldBytes(field.type);
    format.fields.push_back(std::move(field));
  }
  if (format.length != static_cast<size_t>(length)) {
    return FailAt(*node.Find("length"), JoinPath(path, "length"),
                  "is " + std::to_string(length) + ", but the fields take " + std::to_string(format.length) +
                      " bytes",
                  diagnostics);
  }
  return true;
}

}  // namespace syrof::lab::scenario
