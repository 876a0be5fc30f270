// Little-endian encoding of the format's scalar types, independent of the
// host's byte order. Floats travel as their IEEE-754 bit pattern, so every
// value (NaN payloads and -0 included) comes back bit for bit.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace syrof::lab::replay::detail {

inline void PutU8(std::vector<uint8_t>& out, uint8_t value) { out.push_back(value); }

// `bytes` bytes of `value`, least significant first. One size check per
// value, not one per byte: the replay writer puts a round's frames through
// these (about 1,500 values a round at 100 robots).
template <unsigned bytes>
inline void PutLittleEndian(std::vector<uint8_t>& out, uint64_t value) {
  const size_t at = out.size();
  out.resize(at + bytes);
  uint8_t* place = out.data() + at;
  for (unsigned index = 0; index < bytes; ++index) place[index] = static_cast<uint8_t>(value >> (8 * index));
}

inline void PutU16(std::vector<uint8_t>& out, uint16_t value) { PutLittleEndian<2>(out, value); }

inline void PutU32(std::vector<uint8_t>& out, uint32_t value) { PutLittleEndian<4>(out, value); }

inline void PutU64(std::vector<uint8_t>& out, uint64_t value) { PutLittleEndian<8>(out, value); }

inline void PutI64(std::vector<uint8_t>& out, int64_t value) { PutU64(out, static_cast<uint64_t>(value)); }

inline void PutF32(std::vector<uint8_t>& out, float value) { PutU32(out, std::bit_cast<uint32_t>(value)); }

inline void PutF64(std::vector<uint8_t>& out, double value) { PutU64(out, std::bit_cast<uint64_t>(value)); }

inline uint16_t GetU16(const uint8_t* bytes) {
  return static_cast<uint16_t>(bytes[0] | (bytes[1] << 8));
}

inline uint32_t GetU32(const uint8_t* bytes) {
  uint32_t value = 0;
  for (unsigned index = 0; index < 4; ++index) value |= uint32_t{bytes[index]} << (8 * index);
  return value;
}

inline uint64_t GetU64(const uint8_t* bytes) {
  uint64_t value = 0;
  for (unsigned index = 0; index < 8; ++index) value |= uint64_t{bytes[index]} << (8 * index);
  return value;
}

inline int64_t GetI64(const uint8_t* bytes) { return static_cast<int64_t>(GetU64(bytes)); }

inline float GetF32(const uint8_t* bytes) { return std::bit_cast<float>(GetU32(bytes)); }

inline double GetF64(const uint8_t* bytes) { return std::bit_cast<double>(GetU64(bytes)); }

}  // namespace syrof::lab::replay::detail
