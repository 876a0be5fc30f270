#include "syrof/firmware/swarm/guest_clock.h"

namespace syrof::firmware::swarm {

void GuestClockRate::OnBeacon(int64_t host_ns) {
  const int64_t previous = last_ns_;
  last_ns_ = host_ns;
  if (previous < 0) return;
  const int64_t gap = host_ns - previous;
  if (2 * gap < round_ns_ || gap > 4 * round_ns_) return;
  // An exponential average over about ten rounds: the host's scheduling
  // jitters single gaps by milliseconds.
  const double sample = static_cast<double>(gap) / static_cast<double>(round_ns_);
  host_per_guest_ += 0.1 * (sample - host_per_guest_);
}

}  // namespace syrof::firmware::swarm
