// The foundation demo: a few simulated robots, each with its own OS port,
// broker and tasks on one virtual clock, broadcasting beacons over a lossy
// radio. It shows the real-time core working before the simulated lab lands.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace syrof::lab::demo {

struct DemoOptions {
  int robots = 3;              ///< 2 .. kMaxDemoRobots
  double seconds = 1.0;        ///< virtual time to simulate, > 0
  double loss = 0.2;           ///< probability that one beacon misses one receiver, 0 .. 1
  uint32_t seed = 1;           ///< seeds the channel; the same seed gives the same run
  bool show_rounds = true;     ///< print one line per radio round
};

inline constexpr int kMaxDemoRobots = 8;
inline constexpr int64_t kRadioRoundNs = 50'000'000;   // 20 Hz, the design's default
inline constexpr int64_t kMotionPeriodNs = 10'000'000;  // 100 Hz
inline constexpr uint16_t kDemoSwarmSize = 32;          // beacon layout for swarms of up to 32

/// What each robot saw, for the summary and for tests.
struct RobotReport {
  int beacons_sent = 0;
  int beacons_received = 0;
  int beacons_lost = 0;       ///< beacons from others that the channel dropped
  int frames_rejected = 0;    ///< frames the decoder refused
  std::vector<std::string> rejection_reasons;
  double largest_position_error_m = 0;  ///< |decoded - sender's true position| over all received beacons
};

struct DemoReport {
  int radio_rounds = 0;
  int beacon_bytes = 0;
  uint64_t steps_run = 0;
  std::vector<RobotReport> robots;
};

/// Checks the options; returns an empty string when they are valid, else
/// what is wrong, naming the option.
std::string Validate(const DemoOptions& options);

/// Runs the demo with valid options, printing what happens to `out`.
/// Deterministic: the same options give the same text and report.
DemoReport RunDemo(const DemoOptions& options, std::ostream& out);

}  // namespace syrof::lab::demo
