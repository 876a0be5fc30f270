#include "syrof/estimation/state.h"

#include <cmath>

namespace syrof::estimation {

template <typename Scalar>
Scalar WrapAngle(Scalar radians) {
  constexpr Scalar kTwoPi = 2 * kPi<Scalar>;
  if (radians > kPi<Scalar>) {
    radians -= kTwoPi;
  } else if (radians < -kPi<Scalar>) {
    radians += kTwoPi;
  }
  if (radians > kPi<Scalar> || radians < -kPi<Scalar>) radians = std::remainder(radians, kTwoPi);
  return radians;
}

template float WrapAngle<float>(float);
template double WrapAngle<double>(double);

}  // namespace syrof::estimation
