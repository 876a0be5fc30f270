#include "syrof/wire/beacon_codec.h"

#include <algorithm>
#include <array>

#include "field_values.h"
#include "syrof/base/check.h"

namespace syrof::wire {
namespace {

using detail::from_integer;
using detail::from_raw_bits;
using detail::to_integer;
using detail::to_raw_bits;

// Writes a valid beacon as a little-endian bit stream into a zeroed buffer of
// exactly the encoded size; stops at the first value the decoder would reject.
class Encoder {
 public:
  explicit Encoder(std::span<uint8_t> out) : out_(out) {}

  WireError error() const { return error_; }

  void constant(const FieldInfo&, unsigned bits, uint8_t value, WireError) { write(bits, value); }

  template <typename T>
  void number(const FieldInfo&, unsigned bits, const T& field) {
    write(bits, to_raw_bits(to_integer(field), bits));
  }

  template <typename T>
  void number(const FieldInfo&, unsigned bits, const T& field, T min, T max, WireError error) {
    const int32_t value = to_integer(field);
    if (value < to_integer(min) || value > to_integer(max)) {
      fail(error);
      return;
    }
    write(bits, to_raw_bits(value, bits));
  }

  void members(const FieldInfo&, const MemberSet& set, uint16_t swarm_size, WireError error) {
    if (set.next_member(swarm_size) != MemberSet::kCapacity) {
      fail(error);
      return;
    }
    for (size_t index = 0; index < MemberSetBytes(swarm_size); ++index) {
      write(8, set.byte_at(index));
    }
  }

  template <size_t kSize>
  void bytes(const FieldInfo&, const std::array<uint8_t, kSize>& array, uint8_t used,
             WireError error) {
    for (size_t index = used; index < kSize; ++index) {
      if (array[index] != 0) {
        fail(error);
        return;
      }
    }
    for (const uint8_t byte : array) write(8, byte);
  }

 private:
  void fail(WireError error) {
    if (error_ == WireError::kOk) error_ = error;
  }

  void write(unsigned bits, uint32_t value) {
    if (error_ != WireError::kOk) return;
    // The buffer was sized from the same layout, so running past it is a bug.
    SYROF_CHECK(bit_ + bits <= 8 * out_.size());
    while (bits > 0) {
      const unsigned shift = bit_ % 8;
      const unsigned taken = std::min(bits, 8 - shift);
      out_[bit_ / 8] |= static_cast<uint8_t>((value & ((uint32_t{1} << taken) - 1)) << shift);
      value >>= taken;
      bits -= taken;
      bit_ += taken;
    }
  }

  std::span<uint8_t> out_;
  size_t bit_ = 0;
  WireError error_ = WireError::kOk;
};

// Reads a little-endian bit stream field by field into a default Beacon and
// stops at the first problem: the input running out, or a field's own error.
class Decoder {
 public:
  explicit Decoder(std::span<const uint8_t> in) : in_(in) {}

  WireError error() const { return error_; }
  size_t bytes_read() const { return (bit_ + 7) / 8; }

  void constant(const FieldInfo&, unsigned bits, uint8_t value, WireError error) {
    uint32_t raw = 0;
    if (read(bits, raw) && raw != value) fail(error);
  }

  template <typename T>
  void number(const FieldInfo&, unsigned bits, T& field) {
    uint32_t raw = 0;
    if (read(bits, raw)) field = from_integer<T>(from_raw_bits<T>(raw, bits));
  }

  template <typename T>
  void number(const FieldInfo&, unsigned bits, T& field, T min, T max, WireError error) {
    uint32_t raw = 0;
    if (!read(bits, raw)) return;
    const int32_t value = from_raw_bits<T>(raw, bits);
    if (value < to_integer(min) || value > to_integer(max)) {
      fail(error);
      return;
    }
    field = from_integer<T>(value);
  }

  void members(const FieldInfo&, MemberSet& set, uint16_t swarm_size, WireError error) {
    for (size_t index = 0; index < MemberSetBytes(swarm_size); ++index) {
      uint32_t raw = 0;
      if (!read(8, raw)) return;
      const size_t ids_in_byte = std::min<size_t>(8, swarm_size - 8 * index);
      if ((raw >> ids_in_byte) != 0) {
        fail(error);
        return;
      }
      set.set_byte(index, static_cast<uint8_t>(raw));
    }
  }

  template <size_t kSize>
  void bytes(const FieldInfo&, std::array<uint8_t, kSize>& array, uint8_t used, WireError error) {
    for (size_t index = 0; index < kSize; ++index) {
      uint32_t raw = 0;
      if (!read(8, raw)) return;
      if (index >= used && raw != 0) {
        fail(error);
        return;
      }
      array[index] = static_cast<uint8_t>(raw);
    }
  }

 private:
  void fail(WireError error) {
    if (error_ == WireError::kOk) error_ = error;
  }

  // Reads `bits` bits into `value`; false (and nothing read) after an error or
  // when the input ends first, which is then the error.
  bool read(unsigned bits, uint32_t& value) {
    if (error_ != WireError::kOk) return false;
    if (bit_ + bits > 8 * in_.size()) {
      fail(WireError::kTruncated);
      return false;
    }
    value = 0;
    unsigned filled = 0;
    while (filled < bits) {
      const unsigned shift = bit_ % 8;
      const unsigned taken = std::min(bits - filled, 8 - shift);
      const uint32_t chunk = (uint32_t{in_[bit_ / 8]} >> shift) & ((uint32_t{1} << taken) - 1);
      value |= chunk << filled;
      filled += taken;
      bit_ += taken;
    }
    return true;
  }

  std::span<const uint8_t> in_;
  size_t bit_ = 0;
  WireError error_ = WireError::kOk;
};

}  // namespace

syrof::base::Result<size_t, WireError> Encode(const Beacon& beacon, uint16_t swarm_size,
                                              std::span<uint8_t> out) {
  const size_t size = EncodedSize(swarm_size);
  if (size == 0) return WireError::kSwarmSizeOutOfRange;
  if (out.size() < size) return WireError::kBufferTooSmall;
  const std::span<uint8_t> encoding = out.first(size);
  std::fill(encoding.begin(), encoding.end(), uint8_t{0});
  Encoder encoder(encoding);
  DescribeBeacon(encoder, beacon, swarm_size);
  if (encoder.error() != WireError::kOk) {
    std::fill(encoding.begin(), encoding.end(), uint8_t{0});
    return encoder.error();
  }
  return size;
}

syrof::base::Result<Beacon, WireError> Decode(std::span<const uint8_t> in, uint16_t swarm_size) {
  if (swarm_size == 0 || swarm_size > kMaxSwarmSize) return WireError::kSwarmSizeOutOfRange;
  Beacon beacon;
  Decoder decoder(in);
  DescribeBeacon(decoder, beacon, swarm_size);
  if (decoder.error() != WireError::kOk) return decoder.error();
  if (decoder.bytes_read() != in.size()) return WireError::kTrailingBytes;
  return beacon;
}

}  // namespace syrof::wire
