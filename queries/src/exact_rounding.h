// From exact integers to the float answers, with integer arithmetic only.
//
// The queries' answers are exact rationals (a circumcentre) or square roots
// of rationals (a radius, a distance). Each is returned as the float nearest
// to the exact value, ties to even, computed by long division and an integer
// square root: no floating-point operation and no libm call takes part, so
// every platform returns the same bits by construction.
#pragma once

#include <cstdint>

#include "int128.h"

namespace syrof::queries::internal {

/// floor(sqrt(value)).
uint64_t IntegerSqrt(uint64_t value);

/// The float nearest to numerator / denominator (denominator > 0), ties to
/// even. The magnitude of the result must lie in float's normal range, and
/// |numerator|, denominator below 2^126.
float NearestFloatOfQuotient(Int128 numerator, Int128 denominator);

/// The float nearest to sqrt(numerator / denominator) (numerator >= 0,
/// denominator > 0), ties to even; the same range conditions as above.
float NearestFloatOfSqrtQuotient(Int128 numerator, Int128 denominator);

}  // namespace syrof::queries::internal
