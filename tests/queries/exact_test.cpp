// The exact arithmetic under every query: Int128, the integer square root and
// the correctly rounded conversions to float (queries/src, internal).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>

#include "exact_rounding.h"
#include "int128.h"
#include "query_test_support.h"

namespace syrof::queries {
namespace {

using internal::Int128;
using internal::IntegerSqrt;
using internal::NearestFloatOfQuotient;
using internal::NearestFloatOfSqrtQuotient;
using testing::ReferenceSqrt;
using testing::Rng;

TEST(Int128Test, ProductsOfInt64ExtremesMatchKnownValues) {
  // (2^63 - 1)^2 = 2^126 - 2^64 + 1
  EXPECT_EQ(Int128::Product(INT64_MAX, INT64_MAX), Int128::FromHalves(0x3FFFFFFFFFFFFFFFull, 1));
  // (-2^63)^2 = 2^126
  EXPECT_EQ(Int128::Product(INT64_MIN, INT64_MIN), Int128::FromHalves(0x4000000000000000ull, 0));
  // -2^63 * (2^63 - 1) = -2^126 + 2^63
  EXPECT_EQ(Int128::Product(INT64_MIN, INT64_MAX), -Int128::FromHalves(0x3FFFFFFFFFFFFFFFull, 0x8000000000000000ull));
  EXPECT_EQ(Int128::Product(-3, 5), Int128(-15));
  EXPECT_EQ(Int128::Product(0, INT64_MIN), Int128(0));
  EXPECT_EQ(Int128::Product(int64_t{1} << 40, int64_t{1} << 40), Int128::FromHalves(1ull << 16, 0));
}

TEST(Int128Test, AdditionCarriesAndSubtractionBorrowsAcrossHalves) {
  const Int128 all_ones_low = Int128::FromHalves(0, ~0ull);
  EXPECT_EQ(all_ones_low + Int128(1), Int128::FromHalves(1, 0));
  EXPECT_EQ(Int128::FromHalves(1, 0) - Int128(1), all_ones_low);
  EXPECT_EQ(Int128(0) - Int128(1), Int128(-1));
  EXPECT_EQ(-Int128(INT64_MIN), Int128::FromHalves(0, 0x8000000000000000ull));
  EXPECT_EQ(-(-Int128::FromHalves(5, 7)), Int128::FromHalves(5, 7));
}

TEST(Int128Test, ComparesAndSignsLikeIntegers) {
  EXPECT_LT(Int128(-1), Int128(0));
  EXPECT_LT(Int128(INT64_MAX), Int128::FromHalves(1, 0));
  EXPECT_LT(-Int128::FromHalves(1, 0), Int128(INT64_MIN));
  EXPECT_EQ(Int128(-7).sign(), -1);
  EXPECT_EQ(Int128(0).sign(), 0);
  EXPECT_EQ(Int128::FromHalves(1, 0).sign(), 1);
  EXPECT_TRUE(Int128(INT64_MIN).fits_int64());
  EXPECT_FALSE((Int128(INT64_MAX) + Int128(1)).fits_int64());
  EXPECT_FALSE((Int128(INT64_MIN) - Int128(1)).fits_int64());
}

#if defined(__SIZEOF_INT128__)
// On the host, against the compiler's own 128-bit integers (a GNU extension).
__extension__ typedef __int128 NativeInt128;
__extension__ typedef unsigned __int128 NativeUint128;

TEST(Int128Test, AgreesWithCompilerInt128OnRandomValues) {
  Rng rng(1);
  const auto to_native = [](Int128 value) {
    return static_cast<NativeInt128>((static_cast<NativeUint128>(value.high()) << 64) | value.low());
  };
  for (int trial = 0; trial < 200000; ++trial) {
    // Vary the magnitudes so both the int32 fast path and the wide path run.
    const int shift_a = static_cast<int>(rng.Below(64));
    const int shift_b = static_cast<int>(rng.Below(64));
    const auto a = static_cast<int64_t>(rng.Next()) >> shift_a;
    const auto b = static_cast<int64_t>(rng.Next()) >> shift_b;
    const Int128 product = Int128::Product(a, b);
    ASSERT_EQ(to_native(product), static_cast<NativeInt128>(a) * b) << a << " * " << b;
    const Int128 sum = product + Int128::Product(b, b);
    ASSERT_EQ(to_native(sum), static_cast<NativeInt128>(a) * b + static_cast<NativeInt128>(b) * b);
    ASSERT_EQ(to_native(product - Int128(a)), static_cast<NativeInt128>(a) * b - a);
    ASSERT_EQ(product < Int128(b), static_cast<NativeInt128>(a) * b < b);
  }
}
#endif

TEST(IntegerSqrtTest, MatchesBisectionAndEdges) {
  for (const uint64_t value : std::initializer_list<uint64_t>{0, 1, 2, 3, 4, 15, 16, 17, (1ull << 62) - 1, 1ull << 62,
                                                              (1ull << 63) - 1, std::numeric_limits<uint64_t>::max()}) {
    EXPECT_EQ(IntegerSqrt(value), ReferenceSqrt(value)) << value;
  }
  Rng rng(2);
  for (int trial = 0; trial < 20000; ++trial) {
    const uint64_t value = rng.Next() >> rng.Below(64);
    ASSERT_EQ(IntegerSqrt(value), ReferenceSqrt(value)) << value;
    const uint64_t root = rng.Next() >> 32;  // perfect squares and their neighbours
    ASSERT_EQ(IntegerSqrt(root * root), root);
    if (root > 0) {
      ASSERT_EQ(IntegerSqrt(root * root - 1), root - 1);
    }
  }
}

// Exact check that `f` is the float nearest to numerator / denominator
// (both in [2^16, 2^40)), ties to even: the value lies between the
// midpoints to f's neighbours. f = m 2^e with m in [2^23, 2^24).
::testing::AssertionResult IsNearestFloatOfQuotient(int64_t numerator, int64_t denominator, float f) {
  int exponent = 0;
  const float fraction = std::frexp(f, &exponent);
  const auto m = static_cast<int64_t>(std::ldexp(fraction, 24));
  const int e = exponent - 24;
  // Compare numerator / denominator with a * 2^k: sign(numerator 2^-k - denominator a).
  const auto compare = [&](int64_t a, int k) {
    const Int128 left = k <= 0 ? Int128::Product(numerator, int64_t{1} << -k) : Int128(numerator);
    const Int128 right = k <= 0 ? Int128::Product(denominator, a) : Int128::Product(denominator * a, int64_t{1} << k);
    return (left - right).sign();
  };
  const int above_upper = compare(2 * m + 1, e - 1);  // vs upper midpoint
  const int below_lower = m == (int64_t{1} << 23) ? compare(4 * m - 1, e - 2) : compare(2 * m - 1, e - 1);
  const bool even = (m % 2) == 0;
  if (above_upper > 0 || (above_upper == 0 && !even) || below_lower < 0 || (below_lower == 0 && !even)) {
    return ::testing::AssertionFailure() << numerator << "/" << denominator << " -> " << f << " (m=" << m << ", e=" << e
                                         << ")";
  }
  return ::testing::AssertionSuccess();
}

TEST(NearestFloatTest, QuotientIsCorrectlyRounded) {
  EXPECT_EQ(NearestFloatOfQuotient(Int128(1), Int128(2)), 0.5f);
  EXPECT_EQ(NearestFloatOfQuotient(Int128(-3), Int128(4)), -0.75f);
  EXPECT_EQ(NearestFloatOfQuotient(Int128(0), Int128(7)), 0.0f);
  EXPECT_EQ(NearestFloatOfQuotient(Int128(32767), Int128(1000)), 32.767f);
  EXPECT_EQ(NearestFloatOfQuotient(Int128(-32768), Int128(1000)), -32.768f);
  // 2^24 + 1 is a tie between 2^24 and 2^24 + 2: even significand wins.
  EXPECT_EQ(NearestFloatOfQuotient(Int128((1 << 24) + 1), Int128(1)), 16777216.0f);
  EXPECT_EQ(NearestFloatOfQuotient(Int128((1 << 24) + 3), Int128(1)), 16777220.0f);
  Rng rng(3);
  for (int trial = 0; trial < 20000; ++trial) {
    // Both in [2^16, 2^40), so the quotient lies in (2^-24, 2^24).
    const auto numerator = static_cast<int64_t>(rng.Next() >> (24 + rng.Below(24))) | (int64_t{1} << 16);
    const auto denominator = static_cast<int64_t>(rng.Next() >> (24 + rng.Below(24))) | (int64_t{1} << 16);
    const float f = NearestFloatOfQuotient(Int128(numerator), Int128(denominator));
    ASSERT_TRUE(IsNearestFloatOfQuotient(numerator, denominator, f));
    ASSERT_EQ(NearestFloatOfQuotient(Int128(-numerator), Int128(denominator)), -f);
  }
}

TEST(NearestFloatTest, MillimetresToMetresMatchesFloatDivision) {
  // float(mm) is exact and one IEEE division is correctly rounded.
  for (int32_t mm = -32768; mm <= 32767; ++mm) {
    ASSERT_EQ(NearestFloatOfQuotient(Int128(mm), Int128(1000)), static_cast<float>(mm) / 1000.0f) << mm;
  }
}

// Exact check that `f` is the float nearest to sqrt(numerator / denominator):
// numerator / denominator lies between the squares of the midpoints to f's
// neighbours, (2m +- 1)^2 2^(2e-2) (or (4m - 1)^2 2^(2e-4) below a power of 2).
::testing::AssertionResult IsNearestFloatOfSqrtQuotient(int64_t numerator, int64_t denominator, float f) {
  int exponent = 0;
  const auto m = static_cast<int64_t>(std::ldexp(std::frexp(f, &exponent), 24));
  const int e = exponent - 24;
  // sign(numerator / denominator - odd^2 2^k)
  const auto compare = [&](int64_t odd, int k) {
    Int128 left(numerator);
    Int128 right = Int128::Product(denominator, odd * odd);
    for (int bit = 0; bit < -k; ++bit) left = left + left;
    for (int bit = 0; bit < k; ++bit) right = right + right;
    return (left - right).sign();
  };
  const int above_upper = compare(2 * m + 1, 2 * e - 2);
  const int below_lower = m == (int64_t{1} << 23) ? compare(4 * m - 1, 2 * e - 4) : compare(2 * m - 1, 2 * e - 2);
  // An irrational root is never a tie; a rational one is a tie only if exact.
  const bool even = (m % 2) == 0;
  if (above_upper > 0 || (above_upper == 0 && !even) || below_lower < 0 || (below_lower == 0 && !even)) {
    return ::testing::AssertionFailure() << "sqrt(" << numerator << "/" << denominator << ") -> " << f;
  }
  return ::testing::AssertionSuccess();
}

TEST(NearestFloatTest, SquareRootOfQuotientIsCorrectlyRounded) {
  EXPECT_EQ(NearestFloatOfSqrtQuotient(Int128(0), Int128(3)), 0.0f);
  EXPECT_EQ(NearestFloatOfSqrtQuotient(Int128(9), Int128(4)), 1.5f);
  EXPECT_EQ(NearestFloatOfSqrtQuotient(Int128(25'000'000), Int128(1'000'000)), 5.0f);
  // sqrt(2 * 65535^2) mm, the longest distance in range, in metres.
  EXPECT_EQ(NearestFloatOfSqrtQuotient(Int128(2 * int64_t{65535} * 65535), Int128(1'000'000)),
            static_cast<float>(std::sqrt(2.0) * 65.535));
  Rng rng(4);
  for (int trial = 0; trial < 20000; ++trial) {
    // numerator in [2^22, 2^52), denominator in [1, 2^30): the root lies in
    // [2^-4, 2^26), which keeps the exact check below within 128 bits.
    const auto numerator = static_cast<int64_t>(rng.Next() >> (12 + rng.Below(30))) | (int64_t{1} << 22);
    const auto denominator = static_cast<int64_t>(rng.Next() >> (34 + rng.Below(29))) | 1;
    const float f = NearestFloatOfSqrtQuotient(Int128(numerator), Int128(denominator));
    ASSERT_TRUE(IsNearestFloatOfSqrtQuotient(numerator, denominator, f));
    // Independent estimate: within one ulp of the double computation.
    const double reference = std::sqrt(static_cast<double>(numerator) / static_cast<double>(denominator));
    ASSERT_NEAR(f, reference, std::abs(reference) * 1.2e-7) << numerator << "/" << denominator;
  }
}

}  // namespace
}  // namespace syrof::queries
