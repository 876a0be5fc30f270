#include "syrof/lab/sensors/gaussian.h"

#include <array>
#include <cmath>

namespace syrof::lab::sensors {
namespace {

// The ziggurat of 128 layers under the unnormalized density f(x) =
// exp(-x^2 / 2) for x >= 0 (Marsaglia and Tsang, 2000): every layer has the
// area kLayerArea; layer 0 is the base rectangle plus the tail beyond
// kTailStart. edge[i] is the right edge of layer i (edge[0] the base's
// pseudo-width kLayerArea / f(kTailStart)), edge[128] = 0; height[i] =
// f(edge[i]).
constexpr int kLayers = 128;
constexpr double kTailStart = 3.442619855899;
constexpr double kLayerArea = 9.91256303526217e-3;

double Density(double x) { return std::exp(-0.5 * x * x); }

struct Tables {
  std::array<double, kLayers + 1> edge{};
  std::array<double, kLayers + 1> height{};

  Tables() {
    edge[0] = kLayerArea / Density(kTailStart);
    edge[1] = kTailStart;
    for (int i = 2; i < kLayers; ++i) edge[i] = std::sqrt(-2.0 * std::log(kLayerArea / edge[i - 1] + Density(edge[i - 1])));
    edge[kLayers] = 0.0;
    for (int i = 0; i <= kLayers; ++i) height[i] = Density(edge[i]);
  }
};

const Tables& ZigguratTables() {
  static const Tables tables;
  return tables;
}

}  // namespace

double GaussianSource::Next() {
  const Tables& tables = ZigguratTables();
  for (;;) {
    // One draw: bits 0-6 pick the layer, bit 7 the sign, bits 11-63 the
    // position across the layer.
    const uint64_t bits = engine_.Next();
    const int layer = static_cast<int>(bits & (kLayers - 1));
    const double sign = (bits & 0x80u) != 0 ? -1.0 : 1.0;
    const double x = static_cast<double>(bits >> 11) * 0x1.0p-53 * tables.edge[layer];
    // Inside the part of the layer that lies under the curve everywhere.
    if (x < tables.edge[layer + 1]) return sign * x;
    if (layer == 0) {
      // The tail beyond kTailStart (Marsaglia's method): 1 - Uniform() is in
      // (0, 1], so both logarithms are finite.
      double excess = 0;
      double y = 0;
      do {
        excess = -std::log(1.0 - Uniform()) / kTailStart;
        y = -std::log(1.0 - Uniform());
      } while (2.0 * y < excess * excess);
      return sign * (kTailStart + excess);
    }
    // The wedge between the layer's rectangle and the curve.
    const double height = tables.height[layer] + Uniform() * (tables.height[layer + 1] - tables.height[layer]);
    if (height < Density(x)) return sign * x;
  }
}

}  // namespace syrof::lab::sensors
