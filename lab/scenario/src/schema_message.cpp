// `message:` (docs/grading.md, "The message format"): read into a
// lab::message::MessageFormat with the scenario files' rules.
#include <set>

#include "syrof/lab/scenario/yaml/document.h"
#include "syrof/wire/beacon.h"

namespace syrof::lab::scenario {

using message::FieldBytes;
using message::FieldType;
using message::IsFieldName;
using message::kFieldTypeNames;
using message::MessageField;
using message::MessageFormat;

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
