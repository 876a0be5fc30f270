#include "syrof/wire/beacon_layout.h"

#include <array>

#include "field_values.h"

namespace syrof::wire {
namespace {

using detail::from_integer;
using detail::highest_in_bits;
using detail::lowest_in_bits;
using detail::to_integer;

// Walks the layout and records whether every field can carry what it claims:
// bounds inside what its bits hold, unbounded numbers as wide as their type
// (so no value is silently cut), and a whole number of bytes in all.
class WellFormedCheck {
 public:
  constexpr void constant(const FieldInfo&, unsigned bits, uint8_t value, WireError) {
    expect(bits >= 1 && bits <= 8 && value <= highest_in_bits<uint8_t>(bits));
    bits_ += bits;
  }
  template <typename T>
  constexpr void number(const FieldInfo&, unsigned bits, const T&) {
    expect(bits == 8 * sizeof(T));
    bits_ += bits;
  }
  template <typename T>
  constexpr void number(const FieldInfo&, unsigned bits, const T&, T min, T max, WireError error) {
    expect(bits >= 1 && bits <= 8 * sizeof(T) && error != WireError::kOk);
    expect(to_integer(min) <= to_integer(max));
    expect(to_integer(min) >= lowest_in_bits<T>(bits) &&
           to_integer(max) <= highest_in_bits<T>(bits));
    bits_ += bits;
  }
  constexpr void members(const FieldInfo&, const MemberSet&, uint16_t swarm_size, WireError error) {
    expect(swarm_size <= MemberSet::kCapacity && error != WireError::kOk);
    bits_ += 8 * MemberSetBytes(swarm_size);
  }
  template <size_t kSize>
  constexpr void bytes(const FieldInfo&, const std::array<uint8_t, kSize>&, uint8_t,
                       WireError error) {
    expect(error != WireError::kOk);
    bits_ += 8 * kSize;
  }

  constexpr bool ok() const { return ok_ && bits_ % 8 == 0; }

 private:
  constexpr void expect(bool condition) { ok_ = ok_ && condition; }

  size_t bits_ = 0;
  bool ok_ = true;
};

constexpr bool layout_is_well_formed(const Beacon& beacon, uint16_t swarm_size) {
  WellFormedCheck check;
  DescribeBeacon(check, beacon, swarm_size);
  return check.ok();
}

// Every size up to 1024 covers both robot_id widths and every amount of
// member-set padding; above that only the member set grows, so the largest
// size stands for the rest (and keeps compile-time evaluation short).
// A beacon's relay decides its coordinates' ranges: both kinds are checked.
constexpr bool every_layout_is_well_formed() {
  Beacon relaying{};
  relaying.relay.slot = 1;
  for (const Beacon& beacon : {Beacon{}, relaying}) {
    for (uint32_t swarm_size = 1; swarm_size <= kMaxSwarmSize && swarm_size <= 1024; ++swarm_size) {
      if (!layout_is_well_formed(beacon, static_cast<uint16_t>(swarm_size))) return false;
    }
    if (!layout_is_well_formed(beacon, kMaxSwarmSize)) return false;
  }
  return true;
}

static_assert(
    every_layout_is_well_formed(),
    "DescribeBeacon(): a field's range does not fit its bits, or the layout is not whole bytes");

// Appends text to a caller's buffer, remembering whether it ran out of room.
class TextWriter {
 public:
  explicit TextWriter(std::span<char> out) : out_(out) {}

  void append(const char* text) {
    while (*text != '\0') put(*text++);
  }

  void append(int32_t value) {
    if (value < 0) put('-');
    uint32_t magnitude =
        value < 0 ? 0u - static_cast<uint32_t>(value) : static_cast<uint32_t>(value);
    std::array<char, 10> digits{};
    size_t count = 0;
    do {
      digits[count++] = static_cast<char>('0' + magnitude % 10);
      magnitude /= 10;
    } while (magnitude != 0);
    while (count > 0) put(digits[--count]);
  }

  // Writes the terminating NUL; false if the text and the NUL did not fit.
  bool terminate() {
    put('\0');
    return !overflowed_;
  }

  // Characters before the NUL.
  size_t length() const { return size_ - 1; }

 private:
  void put(char c) {
    if (size_ < out_.size()) {
      out_[size_++] = c;
    } else {
      overflowed_ = true;
    }
  }

  std::span<char> out_;
  size_t size_ = 0;
  bool overflowed_ = false;
};

// Renders one Markdown table row per field: where it sits, how big it is, its
// name, and its meaning with the values the decoder accepts.
class TableRenderer {
 public:
  explicit TableRenderer(TextWriter& text) : text_(text) {
    text_.append("| Offset | Size | Field | Meaning |\n");
    text_.append("| --- | --- | --- | --- |\n");
  }

  void constant(const FieldInfo& info, unsigned bits, uint8_t value, WireError) {
    begin_row(info, bits);
    text_.append("; always ");
    text_.append(int32_t{value});
    end_row();
  }

  template <typename T>
  void number(const FieldInfo& info, unsigned bits, const T&) {
    begin_row(info, bits);
    append_range(lowest_in_bits<T>(bits), highest_in_bits<T>(bits));
    end_row();
  }

  template <typename T>
  void number(const FieldInfo& info, unsigned bits, const T&, T min, T max, WireError) {
    begin_row(info, bits);
    if constexpr (std::is_enum_v<T>) {
      for (int32_t value = to_integer(min); value <= to_integer(max); ++value) {
        text_.append(value == to_integer(min) ? "; " : ", ");
        text_.append(value);
        text_.append(" ");
        text_.append(ToString(from_integer<T>(value)));
      }
    } else {
      append_range(to_integer(min), to_integer(max));
    }
    end_row();
  }

  void members(const FieldInfo& info, const MemberSet&, uint16_t swarm_size, WireError) {
    begin_row(info, static_cast<unsigned>(8 * MemberSetBytes(swarm_size)));
    text_.append("; bit i % 8 of byte i / 8 is robot i, for i from 0 to ");
    text_.append(int32_t{swarm_size} - 1);
    if (swarm_size % 8 != 0) text_.append(", the other bits zero");
    end_row();
  }

  template <size_t kSize>
  void bytes(const FieldInfo& info, const std::array<uint8_t, kSize>&, uint8_t, WireError) {
    begin_row(info, 8 * kSize);
    text_.append("; the rest zero");
    end_row();
  }

  void total(uint16_t swarm_size) {
    text_.append("| | ");
    append_size(static_cast<unsigned>(bit_));
    text_.append(" | total | for a swarm of ");
    text_.append(int32_t{swarm_size});
    text_.append(swarm_size == 1 ? " robot |\n" : " robots |\n");
  }

 private:
  void begin_row(const FieldInfo& info, unsigned bits) {
    text_.append("| ");
    append_offset(bits);
    text_.append(" | ");
    append_size(bits);
    text_.append(" | ");
    text_.append(info.name);
    text_.append(" | ");
    text_.append(info.meaning);
    bit_ += bits;
  }

  void end_row() { text_.append(" |\n"); }

  // "6" for a whole-byte field, "4, bits 0-1" for one inside a byte, "bit 35"
  // for anything else.
  void append_offset(unsigned bits) {
    const auto byte = static_cast<int32_t>(bit_ / 8);
    const auto first_bit = static_cast<int32_t>(bit_ % 8);
    const auto last_bit = first_bit + static_cast<int32_t>(bits) - 1;
    if (first_bit == 0 && bits % 8 == 0) {
      text_.append(byte);
    } else if (last_bit < 8) {
      text_.append(byte);
      text_.append(bits == 1 ? ", bit " : ", bits ");
      text_.append(first_bit);
      if (bits != 1) {
        text_.append("-");
        text_.append(last_bit);
      }
    } else {
      text_.append("bit ");
      text_.append(static_cast<int32_t>(bit_));
    }
  }

  void append_size(unsigned bits) {
    const bool whole_bytes = bits % 8 == 0;
    const unsigned count = whole_bytes ? bits / 8 : bits;
    text_.append(static_cast<int32_t>(count));
    if (whole_bytes) {
      text_.append(count == 1 ? " byte" : " bytes");
    } else {
      text_.append(count == 1 ? " bit" : " bits");
    }
  }

  void append_range(int32_t lowest, int32_t highest) {
    text_.append("; ");
    text_.append(lowest);
    text_.append(" to ");
    text_.append(highest);
  }

  TextWriter& text_;
  size_t bit_ = 0;
};

}  // namespace

syrof::base::Result<size_t, WireError> RenderLayoutTable(uint16_t swarm_size,
                                                           std::span<char> out) {
  if (EncodedSize(swarm_size) == 0) return WireError::kSwarmSizeOutOfRange;
  TextWriter text(out);
  TableRenderer renderer(text);
  // A beacon that relays, so the table shows the coordinates' whole ranges.
  Beacon beacon{};
  beacon.relay.slot = 1;
  DescribeBeacon(renderer, static_cast<const Beacon&>(beacon), swarm_size);
  renderer.total(swarm_size);
  if (!text.terminate()) return WireError::kBufferTooSmall;
  return text.length();
}

}  // namespace syrof::wire
