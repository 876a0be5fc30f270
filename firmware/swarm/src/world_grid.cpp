#include "syrof/firmware/swarm/world_grid.h"

#include <cmath>

namespace syrof::firmware::swarm {

int64_t BeaconRound(const SwitchOn& on, double arrival_ns, int64_t period_ns) {
  const double since_ns = arrival_ns - on.world_ns + kEarlyToleranceNs;
  return on.round + static_cast<int64_t>(std::floor(since_ns / static_cast<double>(period_ns)));
}

double BoundaryOf(const SwitchOn& on, int64_t round, int64_t period_ns) {
  return on.world_ns + static_cast<double>((round - on.round) * period_ns);
}

}  // namespace syrof::firmware::swarm
