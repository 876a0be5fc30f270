// Round-start skew between emulated robots, from the instants (host clock)
// their beacons reached the swarm host: a robot sends its beacon at its
// round boundary, and every robot's bytes take the same path (guest UART,
// qemu, a Unix socket), so the differences between robots' arrival times
// measure how far apart their round boundaries are, plus the host's
// scheduling noise.
//
// For each beacon of robot i > 0, the skew is the distance to the nearest
// beacon of robot 0, folded into [0, period / 2]. Beacons before `from_ns`
// (the start-up, before round alignment settled) are left out.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace syrof::firmware::swarm {

struct SkewStats {
  int64_t samples = 0;
  int64_t median_ns = 0;
  int64_t p95_ns = 0;
  int64_t max_ns = 0;
};

/// `send_ns[i]`: robot i's beacon arrival instants, increasing.
SkewStats RoundStartSkew(std::span<const std::vector<int64_t>> send_ns, int64_t period_ns, int64_t from_ns);

}  // namespace syrof::firmware::swarm
