#include "exact_rounding.h"

#include <bit>
#include <cstdint>

#include "syrof/base/check.h"

namespace syrof::queries::internal {
namespace {

// An unsigned 128-bit value as two halves: just what long division needs.
struct Unsigned128 {
  uint64_t high = 0;
  uint64_t low = 0;
};

Unsigned128 ToUnsigned(Int128 value) {
  SYROF_CHECK(!value.is_negative());
  return {value.high(), value.low()};
}

int BitWidth(Unsigned128 value) {
  return value.high != 0 ? 64 + static_cast<int>(std::bit_width(value.high))
                         : static_cast<int>(std::bit_width(value.low));
}

bool Bit(Unsigned128 value, int index) {
  return index >= 64 ? ((value.high >> (index - 64)) & 1) != 0 : ((value.low >> index) & 1) != 0;
}

Unsigned128 ShiftLeft(Unsigned128 value, int count) {
  SYROF_CHECK(count >= 0 && count < 128 && BitWidth(value) + count <= 127);
  if (count == 0) return value;
  if (count >= 64) return {value.low << (count - 64), 0};
  return {(value.high << count) | (value.low >> (64 - count)), value.low << count};
}

bool LessThan(Unsigned128 a, Unsigned128 b) { return a.high != b.high ? a.high < b.high : a.low < b.low; }

Unsigned128 Subtract(Unsigned128 a, Unsigned128 b) {
  return {a.high - b.high - (a.low < b.low ? 1 : 0), a.low - b.low};
}

struct Division {
  uint64_t quotient = 0;
  bool inexact = false;  // the remainder is not zero
};

// floor(numerator * 2^shift / denominator), shift >= 0, by binary long
// division that streams the numerator's bits followed by `shift` zeros, so
// the shifted numerator itself never has to fit. The quotient must fit in
// 63 bits (the callers choose shift so that it has 26 to 55).
Division DivideShifted(Unsigned128 numerator, int shift, Unsigned128 denominator) {
  SYROF_CHECK(shift >= 0 && (denominator.high | denominator.low) != 0);
  SYROF_CHECK(BitWidth(denominator) <= 126);
  Division division;
  Unsigned128 remainder;
  const int total_bits = BitWidth(numerator) + shift;
  for (int index = total_bits - 1; index >= 0; --index) {
    // remainder < denominator < 2^126, so doubling it cannot overflow.
    remainder = ShiftLeft(remainder, 1);
    if (index >= shift && Bit(numerator, index - shift)) remainder.low |= 1;
    SYROF_CHECK(division.quotient < (uint64_t{1} << 62));
    division.quotient <<= 1;
    if (!LessThan(remainder, denominator)) {
      remainder = Subtract(remainder, denominator);
      division.quotient |= 1;
    }
  }
  division.inexact = (remainder.high | remainder.low) != 0;
  return division;
}

// The float nearest to (quotient + f) * 2^exponent, where f is 0 when
// `inexact` is false and strictly between 0 and 1 otherwise; quotient has
// at least 25 significant bits, so the truncated part lies below the
// rounding position.
float RoundToFloat(bool negative, uint64_t quotient, bool inexact, int exponent) {
  const int width = static_cast<int>(std::bit_width(quotient));
  SYROF_CHECK(width >= 25);
  // Keep 25 bits: 24 for the significand and one rounding bit.
  const int drop = width - 25;
  if (drop > 0) {
    inexact = inexact || (quotient & ((uint64_t{1} << drop) - 1)) != 0;
    quotient >>= drop;
    exponent += drop;
  }
  auto significand = static_cast<uint32_t>(quotient >> 1);
  const bool round_bit = (quotient & 1) != 0;
  exponent += 1;
  if (round_bit && (inexact || (significand & 1) != 0)) ++significand;
  if (significand == (uint32_t{1} << 24)) {
    significand >>= 1;
    ++exponent;
  }
  // value = significand * 2^exponent with significand in [2^23, 2^24).
  const int biased_exponent = exponent + 23 + 127;
  SYROF_CHECK(biased_exponent >= 1 && biased_exponent <= 254);  // normal range
  const uint32_t bits =
      (negative ? 0x80000000u : 0u) | (static_cast<uint32_t>(biased_exponent) << 23) | (significand & 0x7FFFFFu);
  return std::bit_cast<float>(bits);
}

}  // namespace

uint64_t IntegerSqrt(uint64_t value) {
  // Digit by digit, two bits of the radicand per result bit.
  uint64_t result = 0;
  uint64_t bit = uint64_t{1} << 62;
  while (bit > value) bit >>= 2;
  while (bit != 0) {
    if (value >= result + bit) {
      value -= result + bit;
      result = (result >> 1) + bit;
    } else {
      result >>= 1;
    }
    bit >>= 2;
  }
  return result;
}

float NearestFloatOfQuotient(Int128 numerator, Int128 denominator) {
  SYROF_CHECK(denominator.sign() > 0);
  if (numerator.sign() == 0) return 0.0f;
  const bool negative = numerator.is_negative();
  const Unsigned128 magnitude = ToUnsigned(negative ? -numerator : numerator);
  Unsigned128 divisor = ToUnsigned(denominator);
  // 2^25 < magnitude * 2^shift / divisor < 2^27: 26 or 27 quotient bits.
  int shift = 26 + BitWidth(divisor) - BitWidth(magnitude);
  int exponent = -shift;
  if (shift < 0) {
    divisor = ShiftLeft(divisor, -shift);
    shift = 0;
  }
  const Division division = DivideShifted(magnitude, shift, divisor);
  return RoundToFloat(negative, division.quotient, division.inexact, exponent);
}

float NearestFloatOfSqrtQuotient(Int128 numerator, Int128 denominator) {
  SYROF_CHECK(denominator.sign() > 0 && !numerator.is_negative());
  if (numerator.sign() == 0) return 0.0f;
  const Unsigned128 magnitude = ToUnsigned(numerator);
  Unsigned128 divisor = ToUnsigned(denominator);
  // x = floor(magnitude * 4^half_shift / divisor) in [2^51, 2^54), so its
  // square root has 26 or 27 bits. floor(sqrt(x)) = floor(sqrt(exact)), and
  // the root is exact only if the division and the root both are.
  const int half_shift = (52 + BitWidth(divisor) - BitWidth(magnitude) + 1) >> 1;
  int shift = 2 * half_shift;
  if (shift < 0) {
    divisor = ShiftLeft(divisor, -shift);
    shift = 0;
  }
  const Division division = DivideShifted(magnitude, shift, divisor);
  const uint64_t root = IntegerSqrt(division.quotient);
  const bool inexact = division.inexact || root * root != division.quotient;
  return RoundToFloat(false, root, inexact, -half_shift);
}

}  // namespace syrof::queries::internal
