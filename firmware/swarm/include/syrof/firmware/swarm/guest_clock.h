// How fast an emulated robot's clock runs against the host's, from the
// instants its beacons reach the host: a robot sends one beacon per radio
// round of its own clock, so the host time between two of them over the
// round's length is the guest's slowdown (about 2.4 under -icount with the
// sensor link, docs/firmware.md). The host scales the channel's latency by
// it, so a beacon still arrives half a round of the receivers' clocks after
// it was sent, where round alignment expects it.
#pragma once

#include <cstdint>

namespace syrof::firmware::swarm {

class GuestClockRate {
 public:
  explicit GuestClockRate(int64_t round_ns) : round_ns_(round_ns) {}

  /// A beacon reached the host at `host_ns` (increasing). Gaps outside half
  /// to four rounds (a lost or merged frame, a start-up) are ignored.
  void OnBeacon(int64_t host_ns);

  /// Host nanoseconds per guest nanosecond, smoothed (1 until measured).
  double host_per_guest() const { return host_per_guest_; }

  /// `guest_ns` of the guest's time in host time.
  int64_t ToHost(int64_t guest_ns) const { return static_cast<int64_t>(static_cast<double>(guest_ns) * host_per_guest_); }

 private:
  int64_t round_ns_;
  int64_t last_ns_ = -1;
  double host_per_guest_ = 1.0;
};

}  // namespace syrof::firmware::swarm
