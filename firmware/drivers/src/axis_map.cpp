#include "syrof/firmware/drivers/axis_map.h"

namespace syrof::firmware::drivers {

bool IsSignedPermutation(std::span<const AxisSource> map) {
  unsigned used = 0;
  for (const AxisSource& source : map) {
    if (source.sign != 1 && source.sign != -1) return false;
    if (source.axis >= map.size()) return false;
    const unsigned bit = 1u << source.axis;
    if (used & bit) return false;
    used |= bit;
  }
  return true;
}

}  // namespace syrof::firmware::drivers
