#include "syrof/firmware/swarm/console_lines.h"

#include <algorithm>
#include <charconv>

namespace syrof::firmware::swarm {
namespace {

// A cursor over one line that reads `key=value` fields in a fixed order.
class Fields {
 public:
  /// `start`: where the fields begin, after the line's tag (R, E, held).
  explicit Fields(std::string_view line, size_t start = 1) : line_(line), at_(start) {}

  // Reads " key=" then a decimal integer in [low, high].
  bool Integer(std::string_view key, int64_t low, int64_t high, int64_t& value) {
    if (!Key(key)) return false;
    return Number(key, low, high, value);
  }
  bool Key(std::string_view key) {
    if (line_.substr(at_, 1) != " " || line_.substr(at_ + 1, key.size()) != key ||
        line_.substr(at_ + 1 + key.size(), 1) != "=") {
      return Fail("expected ' " + std::string(key) + "='");
    }
    at_ += key.size() + 2;
    return true;
  }
  bool Number(std::string_view field, int64_t low, int64_t high, int64_t& value) {
    const char* begin = line_.data() + at_;
    const char* end = line_.data() + line_.size();
    const auto [next, error] = std::from_chars(begin, end, value);
    if (error != std::errc() || next == begin) return Fail(std::string(field) + ": expected a whole number");
    if (value < low || value > high) {
      return Fail(std::string(field) + ": " + std::to_string(value) + " is outside [" + std::to_string(low) + ", " +
                  std::to_string(high) + "]");
    }
    at_ += static_cast<size_t>(next - begin);
    return true;
  }
  bool Char(char expected, std::string_view field) {
    if (at_ >= line_.size() || line_[at_] != expected) {
      return Fail(std::string(field) + ": expected '" + std::string(1, expected) + "'");
    }
    ++at_;
    return true;
  }
  bool AtEnd() const { return at_ >= line_.size(); }
  /// The line from here to its end, consumed.
  std::string_view Rest() {
    const std::string_view rest = line_.substr(std::min(at_, line_.size()));
    at_ = line_.size();
    return rest;
  }
  size_t at() const { return at_; }
  char Peek() const { return at_ < line_.size() ? line_[at_] : '\0'; }
  void Skip() { ++at_; }
  bool Fail(std::string what) {
    if (error_.what.empty()) error_ = LineError{std::move(what), at_};
    return false;
  }
  const LineError& error() const { return error_; }

 private:
  std::string_view line_;
  size_t at_;
  LineError error_;
};

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

ConsoleLine ParseRound(std::string_view line, uint16_t swarm_size) {
  Fields fields(line);
  RoundLine round;
  int64_t t = 0, robot = 0, epoch = 0, mode = 0, phase = 0, member = 0, valid = 0, x = 0, y = 0, lost = 0;
  if (!fields.Integer("t_ms", 0, INT64_MAX / 1'000'000, t) || !fields.Integer("robot", 0, swarm_size - 1, robot) ||
      !fields.Integer("epoch", 0, 65535, epoch) || !fields.Integer("mode", 0, 1, mode) ||
      !fields.Integer("phase", 0, 2, phase) || !fields.Integer("member", 0, 1, member) ||
      !fields.Integer("valid", 0, 1, valid) || !fields.Integer("x_mm", -1'000'000, 1'000'000, x) ||
      !fields.Integer("y_mm", -1'000'000, 1'000'000, y) || !fields.Integer("lost", 0, UINT32_MAX, lost)) {
    return fields.error();
  }
  if (!fields.AtEnd()) {
    fields.Fail("unexpected text after lost=");
    return fields.error();
  }
  round.t_ms = t;
  round.robot = static_cast<uint16_t>(robot);
  round.epoch = static_cast<uint16_t>(epoch);
  round.mode = static_cast<wire::Mode>(mode);
  round.phase = static_cast<wire::Phase>(phase);
  round.member = member == 1;
  round.estimate_valid = valid == 1;
  round.x_m = static_cast<double>(x) / 1000.0;
  round.y_m = static_cast<double>(y) / 1000.0;
  round.epoch_lines_lost = static_cast<uint32_t>(lost);
  return round;
}

ConsoleLine ParseEpoch(std::string_view line, uint16_t swarm_size) {
  Fields fields(line);
  EpochLine epoch_line;
  int64_t t = 0, robot = 0, epoch = 0, mode = 0, active = 0;
  if (!fields.Integer("t_ms", 0, INT64_MAX / 1'000'000, t) || !fields.Integer("robot", 0, swarm_size - 1, robot) ||
      !fields.Integer("epoch", 0, 65535, epoch) || !fields.Integer("mode", 0, 1, mode) ||
      !fields.Integer("active", 0, 1, active) || !fields.Key("members")) {
    return fields.error();
  }
  sync::LDMap& map = epoch_line.map;
  map.epoch = static_cast<uint16_t>(epoch);
  map.mode = static_cast<wire::Mode>(mode);
  while (!fields.AtEnd()) {
    int64_t id = 0, x = 0, y = 0, heading = 0, vx = 0, vy = 0;
    if (!fields.Number("member id", 0, swarm_size - 1, id) || !fields.Char(':', "member") ||
        !fields.Number("x_mm", INT16_MIN, INT16_MAX, x) || !fields.Char(':', "member") ||
        !fields.Number("y_mm", INT16_MIN, INT16_MAX, y) || !fields.Char(':', "member") ||
        !fields.Number("heading_mrad", INT16_MIN, INT16_MAX, heading) || !fields.Char(':', "member") ||
        !fields.Number("vx_mm_s", INT16_MIN, INT16_MAX, vx) || !fields.Char(':', "member") ||
        !fields.Number("vy_mm_s", INT16_MIN, INT16_MAX, vy) || !fields.Char(':', "member")) {
      return fields.error();
    }
    const auto member = static_cast<uint16_t>(id);
    if (map.members.test(member)) {
      fields.Fail("member " + std::to_string(id) + " listed twice");
      return fields.error();
    }
    map.members.set(member);
    wire::Snapshot& snapshot = map.snapshots[member];
    snapshot.x_mm = static_cast<int16_t>(x);
    snapshot.y_mm = static_cast<int16_t>(y);
    snapshot.heading_mrad = static_cast<int16_t>(heading);
    snapshot.vx_mm_s = static_cast<int16_t>(vx);
    snapshot.vy_mm_s = static_cast<int16_t>(vy);
    uint8_t payload[wire::kMaxPayloadBytes];
    size_t length = 0;
    while (!fields.AtEnd() && fields.Peek() != ';') {
      const int high = HexDigit(fields.Peek());
      fields.Skip();
      const int low = HexDigit(fields.Peek());
      if (high < 0 || low < 0) {
        fields.Fail("payload: expected pairs of hex digits");
        return fields.error();
      }
      fields.Skip();
      if (length == sizeof payload) {
        fields.Fail("payload: more than " + std::to_string(sizeof payload) + " bytes");
        return fields.error();
      }
      payload[length++] = static_cast<uint8_t>(high * 16 + low);
    }
    (void)snapshot.SetPayload(std::span<const uint8_t>(payload, length));
    if (!fields.AtEnd()) fields.Skip();  // the ';'
  }
  epoch_line.t_ms = t;
  epoch_line.robot = static_cast<uint16_t>(robot);
  epoch_line.active = active == 1;
  return epoch_line;
}

ConsoleLine ParseHeld(std::string_view line, uint16_t swarm_size) {
  Fields fields(line, std::string_view("held").size());
  HeldLine held;
  int64_t t = 0, robot = 0;
  if (!fields.Integer("id", 0, swarm_size - 1, robot) || !fields.Integer("t_ms", 0, INT64_MAX / 1'000'000, t) ||
      !fields.Key("app")) {
    return fields.error();
  }
  const size_t app_at = fields.at();
  const std::string_view app = fields.Rest();
  if (app.empty()) return LineError{"app: the image names no app", app_at};
  if (app.size() > kMaxAppNameBytes) {
    return LineError{"app: " + std::to_string(app.size()) + " bytes, more than the " +
                         std::to_string(kMaxAppNameBytes) + " a replay holds",
                     app_at};
  }
  for (size_t i = 0; i < app.size(); ++i) {
    if (app[i] < 0x20 || app[i] > 0x7e) return LineError{"app: a byte that is not printable ASCII", app_at + i};
  }
  held.t_ms = t;
  held.robot = static_cast<uint16_t>(robot);
  held.app = std::string(app);
  return held;
}

}  // namespace

ConsoleLine ParseConsoleLine(std::string_view line, uint16_t swarm_size) {
  if (line.size() >= 2 && line[0] == 'R' && line[1] == ' ') return ParseRound(line, swarm_size);
  if (line.size() >= 2 && line[0] == 'E' && line[1] == ' ') return ParseEpoch(line, swarm_size);
  if (line.starts_with("held ")) return ParseHeld(line, swarm_size);
  return OtherLine{};
}

}  // namespace syrof::firmware::swarm
