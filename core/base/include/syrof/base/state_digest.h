// StateDigest: a 128-bit fingerprint of a program's state, built by feeding
// it the bytes that make up that state, for a search that must tell whether
// it has been in a state before (lab/search: two runs in the same state at
// the same instant have the same future). Two independent 64-bit lanes, each
// a multiply-rotate over 8-byte words, finished through SplitMix64: two
// different states share a fingerprint with a chance of about 2^-128 per
// pair. Deterministic on every compiler and target; no allocation.
//
// What a state's owner feeds must make equal fingerprints imply equal
// futures: everything the future depends on goes in; what nothing reads
// back (counters kept for reports) may stay out. Feeding raw object bytes is
// safe in that direction: padding or a pointer that differs between equal
// states only makes equal states look different.
//
// Usage:
//   base::StateDigest digest;
//   digest.AddValue(state.epoch);
//   digest.AddBytes(std::as_bytes(std::span(array.data(), used)));
//   const base::StateDigest::Value value = digest.value();
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

#include "syrof/base/split_mix64.h"

namespace syrof::base {

class StateDigest {
 public:
  struct Value {
    uint64_t low = 0;
    uint64_t high = 0;
    bool operator==(const Value&) const = default;
  };

  void AddBytes(std::span<const std::byte> bytes) {
    const std::byte* data = bytes.data();
    size_t left = bytes.size();
    while (left >= 8) {
      uint64_t word;
      std::memcpy(&word, data, 8);
      Mix(word);
      data += 8;
      left -= 8;
    }
    if (left > 0) {
      uint64_t word = 0;
      std::memcpy(&word, data, left);
      Mix(word ^ (uint64_t{left} << 56));
    }
    length_ += bytes.size();
  }

  /// A trivially copyable value's bytes (its padding too: see the top).
  template <typename T>
  void AddValue(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    AddBytes(std::as_bytes(std::span<const T, 1>(&value, 1)));
  }

  /// The elements of `values`.
  template <typename T>
  void AddRange(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    AddValue(values.size());
    AddBytes(std::as_bytes(values));
  }

  Value value() const {
    return {SplitMix64Hash(low_ ^ length_), SplitMix64Hash(high_ ^ SplitMix64Hash(length_))};
  }

 private:
  void Mix(uint64_t word) {
    low_ = Rotate((low_ ^ word) * 0x9E3779B97F4A7C15ull, 29);
    high_ = Rotate((high_ + word) * 0xC2B2AE3D27D4EB4Full, 31) ^ word;
  }
  static uint64_t Rotate(uint64_t value, int bits) { return (value << bits) | (value >> (64 - bits)); }

  uint64_t low_ = 0x243F6A8885A308D3ull;
  uint64_t high_ = 0x13198A2E03707344ull;
  uint64_t length_ = 0;
};

}  // namespace syrof::base
