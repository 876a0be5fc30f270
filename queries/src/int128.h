// A signed 128-bit integer for the queries' exact predicates.
//
// Positions are integer millimetres in int16 range, so every geometric
// decision is a sign of an integer polynomial in the coordinates. Orientation
// fits int64; the in-circle determinant and the squared distances to a
// circle's rational centre need up to about 106 bits (see docs/queries.md,
// "Exactness"). 32-bit ARM has no __int128, so this is a small two's
// complement type built on uint64_t halves: the same code, and therefore the
// same answers, on the host and on the Cortex-M4.
//
// Only what the predicates need: +, -, negation, comparison, and products
// whose operands both fit in int64 (every product the queries form does; a
// wider operand is a bug and stops the program through SYROF_CHECK). Sums
// wrap modulo 2^128 like unsigned arithmetic, but the queries' bounds keep
// every value below 2^110 in magnitude.
#pragma once

#include <compare>
#include <cstdint>
#include <type_traits>

#include "syrof/base/check.h"

namespace syrof::queries::internal {

class Int128 {
 public:
  constexpr Int128() = default;
  // Implicit from any signed built-in integer so the type works as a CGAL
  // number type (CGAL writes FT(0) and mixes literals into expressions).
  template <typename Integer>
  requires std::is_integral_v<Integer> && std::is_signed_v<Integer>
  constexpr Int128(Integer value)  // NOLINT(google-explicit-constructor)
      : low_(static_cast<uint64_t>(static_cast<int64_t>(value))), high_(value < 0 ? ~uint64_t{0} : 0) {}

  /// From the two's complement halves.
  static constexpr Int128 FromHalves(uint64_t high, uint64_t low) {
    Int128 result;
    result.high_ = high;
    result.low_ = low;
    return result;
  }

  /// The exact product of two int64 values (never overflows).
  static constexpr Int128 Product(int64_t a, int64_t b) {
    // Fast path: both fit in int32, so the product fits in int64.
    if (a >= INT32_MIN && a <= INT32_MAX && b >= INT32_MIN && b <= INT32_MAX) {
      return Int128(a * b);
    }
    const bool negative = (a < 0) != (b < 0);
    const Int128 magnitude = UnsignedProduct(Magnitude(a), Magnitude(b));
    return negative ? -magnitude : magnitude;
  }

  /// The product of two unsigned 64-bit values as an unsigned 128-bit pattern.
  static constexpr Int128 UnsignedProduct(uint64_t a, uint64_t b) {
    const uint64_t a0 = a & 0xFFFFFFFFu;
    const uint64_t a1 = a >> 32;
    const uint64_t b0 = b & 0xFFFFFFFFu;
    const uint64_t b1 = b >> 32;
    const uint64_t p00 = a0 * b0;
    const uint64_t p01 = a0 * b1;
    const uint64_t p10 = a1 * b0;
    const uint64_t p11 = a1 * b1;
    const uint64_t middle = (p00 >> 32) + (p01 & 0xFFFFFFFFu) + (p10 & 0xFFFFFFFFu);
    return FromHalves(p11 + (p01 >> 32) + (p10 >> 32) + (middle >> 32), (p00 & 0xFFFFFFFFu) | (middle << 32));
  }

  constexpr uint64_t high() const { return high_; }
  constexpr uint64_t low() const { return low_; }

  constexpr bool is_negative() const { return (high_ >> 63) != 0; }
  constexpr int sign() const {
    if (is_negative()) return -1;
    return (high_ | low_) != 0 ? 1 : 0;
  }
  /// Whether the value lies in int64's range.
  constexpr bool fits_int64() const { return high_ == (is_negative_low() ? ~uint64_t{0} : 0); }
  /// The value as int64; only valid when fits_int64().
  constexpr int64_t to_int64() const { return static_cast<int64_t>(low_); }

  constexpr Int128 operator-() const {
    const uint64_t low = ~low_ + 1;
    return FromHalves(~high_ + (low == 0 ? 1 : 0), low);
  }
  friend constexpr Int128 operator+(Int128 a, Int128 b) {
    const uint64_t low = a.low_ + b.low_;
    return FromHalves(a.high_ + b.high_ + (low < a.low_ ? 1 : 0), low);
  }
  friend constexpr Int128 operator-(Int128 a, Int128 b) {
    const uint64_t low = a.low_ - b.low_;
    return FromHalves(a.high_ - b.high_ - (a.low_ < b.low_ ? 1 : 0), low);
  }
  friend constexpr Int128 operator*(Int128 a, Int128 b) {
    // The queries' bounds keep every factor within int64 (docs/queries.md).
    SYROF_CHECK(a.fits_int64() && b.fits_int64());
    return Product(a.to_int64(), b.to_int64());
  }
  constexpr Int128& operator+=(Int128 other) { return *this = *this + other; }
  constexpr Int128& operator-=(Int128 other) { return *this = *this - other; }
  constexpr Int128& operator*=(Int128 other) { return *this = *this * other; }

  friend constexpr bool operator==(Int128 a, Int128 b) = default;
  friend constexpr std::strong_ordering operator<=>(Int128 a, Int128 b) {
    const auto high_a = static_cast<int64_t>(a.high_);
    const auto high_b = static_cast<int64_t>(b.high_);
    if (high_a != high_b) return high_a <=> high_b;
    return a.low_ <=> b.low_;
  }

  /// Nearest double, for CGAL's To_double (diagnostics only; never a decision).
  double to_double() const {
    constexpr double kTwoTo64 = 18446744073709551616.0;
    if (is_negative()) return -(-*this).to_double();
    return static_cast<double>(high_) * kTwoTo64 + static_cast<double>(low_);
  }

 private:
  static constexpr uint64_t Magnitude(int64_t value) {
    return value < 0 ? ~static_cast<uint64_t>(value) + 1 : static_cast<uint64_t>(value);
  }
  constexpr bool is_negative_low() const { return (low_ >> 63) != 0; }

  uint64_t low_ = 0;
  uint64_t high_ = 0;
};

}  // namespace syrof::queries::internal
