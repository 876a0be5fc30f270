#include "syrof/firmware/swarm/guest_clock.h"

namespace syrof::firmware::swarm {

void GuestClockRate::OnGuestTime(int64_t host_ns, int64_t guest_ns) {
  if (on_host_clock_) return;
  if (!samples_.empty() && (guest_ns < samples_.back().guest_ns || host_ns < samples_.back().host_ns)) {
    samples_.clear();
  }
  samples_.push_back(Sample{host_ns, guest_ns});
  // Keep one sample at least a window older than the newest: the slope is
  // taken across the whole window.
  while (samples_.size() > 2 && guest_ns - samples_[1].guest_ns >= window_ns_) samples_.pop_front();
  const Sample& oldest = samples_.front();
  const int64_t guest_span = guest_ns - oldest.guest_ns;
  if (10 * guest_span < window_ns_) return;
  host_per_guest_ = static_cast<double>(host_ns - oldest.host_ns) / static_cast<double>(guest_span);
}

}  // namespace syrof::firmware::swarm
