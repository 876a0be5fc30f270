// How fast an emulated robot's clock runs against the host's, from pairs of
// instants: the guest time a robot printed on a console line (its `R` line's
// t_ms, once a radio round) and the host time the line reached the host.
// The slope over the last couple of seconds is the guest's slowdown (about
// 2 under -icount with the sensor link, docs/firmware.md). The host runs the
// world at the robots' mean rate and scales the channel's latency by it, so
// a beacon still arrives half a round of the receivers' clocks after it was
// sent, where round alignment expects it.
//
// A first version timed the gaps between a robot's beacons instead. Those
// gaps also hold the robot's own round shifts: when round alignment moved
// every robot later, the host read it as slower clocks, lengthened the
// latency, and the robots moved later still; the rounds oscillated by
// +-20 ms with a period of about six rounds (docs/firmware.md).
#pragma once

#include <cstdint>
#include <deque>

namespace syrof::firmware::swarm {

class GuestClockRate {
 public:
  /// The slope is taken over about `window_ns` of guest time.
  explicit GuestClockRate(int64_t window_ns = 2'000'000'000) : window_ns_(window_ns) {}

  /// A guest on the host's clock (qemu without -icount): its clock is the
  /// host's, so its rate is exactly 1 and OnGuestTime measures nothing. A
  /// measured rate would only be noise: in the first seconds qemu
  /// translates code and a guest's lines come unevenly, and an estimate
  /// 0.6% off moved the world 25 ms off the robots' grid in ten seconds.
  static GuestClockRate OnHostClock() {
    GuestClockRate rate;
    rate.on_host_clock_ = true;
    return rate;
  }

  /// A line the guest printed at `guest_ns` of its clock reached the host at
  /// `host_ns`. A guest time that goes backwards (a restarted instance)
  /// starts the measurement again.
  void OnGuestTime(int64_t host_ns, int64_t guest_ns);

  /// Host nanoseconds per guest nanosecond (1 until a tenth of the window
  /// has been seen).
  double host_per_guest() const { return host_per_guest_; }

  /// `guest_ns` of the guest's time in host time.
  int64_t ToHost(int64_t guest_ns) const { return static_cast<int64_t>(static_cast<double>(guest_ns) * host_per_guest_); }

 private:
  struct Sample {
    int64_t host_ns;
    int64_t guest_ns;
  };
  int64_t window_ns_;
  bool on_host_clock_ = false;
  std::deque<Sample> samples_;
  double host_per_guest_ = 1.0;
};

}  // namespace syrof::firmware::swarm
