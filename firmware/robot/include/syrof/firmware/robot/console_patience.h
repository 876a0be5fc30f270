// When a robot's console writer gives up on a line (mps2_an386_main.cpp's
// ConsoleWrite): after kPatienceNs of waiting for room in the transmit ring
// while the robot runs. Time in which the guest did not run at all does not
// count: a qemu stopped from outside (the emulated swarm's stress stalls,
// docs/firmware.md "Stress"; a host that did not schedule it) comes back to
// a clock that moved on, and counting that gap cut lines in the middle (4
// of 50 stressed swarm runs) though the ring drained at once. One gap
// between two checks therefore counts at most kMaxGapNs; the writer checks
// at every interrupt (1 kHz at least). Pure, no allocation: M4 and host.
#pragma once

#include <algorithm>
#include <cstdint>

namespace syrof::firmware::robot {

class ConsolePatience {
 public:
  static constexpr int64_t kPatienceNs = 200'000'000;
  static constexpr int64_t kMaxGapNs = 10'000'000;

  /// Starts waiting at `now_ns` (the robot's clock).
  explicit constexpr ConsolePatience(int64_t now_ns) : last_check_ns_(now_ns) {}

  /// One check at `now_ns`: `progressed` when bytes went into the ring
  /// since the last. True when the writer should give up on the line.
  constexpr bool Exhausted(int64_t now_ns, bool progressed) {
    const int64_t gap_ns = std::clamp<int64_t>(now_ns - last_check_ns_, 0, kMaxGapNs);
    last_check_ns_ = now_ns;
    waited_ns_ = progressed ? 0 : waited_ns_ + gap_ns;
    return waited_ns_ > kPatienceNs;
  }

 private:
  int64_t last_check_ns_;
  int64_t waited_ns_ = 0;
};

}  // namespace syrof::firmware::robot
