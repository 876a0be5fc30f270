#include "syrof/firmware/swarm/world_grid.h"

#include <cmath>

namespace syrof::firmware::swarm {

int64_t BeaconRound(const SwitchOn& on, double arrival_ns, int64_t period_ns) {
  const double since_ns = arrival_ns - on.world_ns + kEarlyToleranceNs;
  return on.round + static_cast<int64_t>(std::floor(since_ns / static_cast<double>(period_ns)));
}

std::optional<int64_t> TakeBoundary(BoundariesByRound& boundaries, int64_t round) {
  std::optional<int64_t> boundary;
  if (const auto it = boundaries.find(round); it != boundaries.end()) boundary = it->second;
  boundaries.erase(boundaries.begin(), boundaries.upper_bound(round));
  return boundary;
}

double BoundaryOf(const SwitchOn& on, int64_t round, int64_t period_ns) {
  return on.world_ns + static_cast<double>((round - on.round) * period_ns);
}

}  // namespace syrof::firmware::swarm
