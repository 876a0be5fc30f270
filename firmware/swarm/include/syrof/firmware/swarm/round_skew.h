// Round-start skew between emulated robots, from the instants (host clock)
// their beacons reached the swarm host: a robot sends its beacon at its
// round boundary, and every robot's bytes take the same path (guest UART,
// qemu, a Unix socket), so the differences between robots' arrival times
// measure how far apart their round boundaries are, plus the host's
// scheduling noise.
//
// For each beacon of robot i > 0, the skew is the distance to the nearest
// beacon of robot 0, folded into [0, period / 2]: one sample a beacon.
// Beacons before `from_ns` (the start-up, before round alignment settled)
// are left out. The figures (p50, p99, max in microseconds) are the ones
// DDS gives its own samples (lab::metrics::SkewOf).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "syrof/lab/metrics/metrics.h"

namespace syrof::firmware::swarm {

/// `send_ns[i]`: robot i's beacon arrival instants, increasing.
lab::metrics::SkewStats RoundStartSkew(std::span<const std::vector<int64_t>> send_ns, int64_t period_ns,
                                       int64_t from_ns);

}  // namespace syrof::firmware::swarm
