// Seeded stress for the runtimes that run in wall-clock time (the DDS swarm,
// docs/dds.md "Stress"; the emulated firmware swarm, docs/firmware.md
// "Stress"): what a loaded machine does to their processes, made repeatable.
//
//   - stalls: SIGSTOP, then SIGCONT 10 to 200 ms later, of a robot's process
//     (a DDS robot, a qemu guest) or of the world, at moments and of
//     lengths drawn from the seed (PlanStalls);
//   - late samples: a fraction of the samples a receiver takes (beacons,
//     sensor readings) held 10 to 200 ms before it handles them, as a
//     network that delivers them late would (SampleDelayNs);
//   - a CPU quota: the robots' processes share one cgroup whose quota is a
//     fraction of one core (cgroup v1 cpu.cfs_quota_us, or v2 cpu.max).
//
// The plan and the delays are pure functions of the seed and the run's
// size, so a failing stressed run reruns from its seed: the same processes
// are stopped at the same instants of the run for the same lengths, and the
// same samples are late by the same amounts. What the kernel and the
// transport do around them is not replayed; the stress is. Each runtime
// only applies the plan to its own processes and links.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"

namespace syrof::lab::sim {

struct StressOptions {
  uint64_t seed = 0;               ///< 0: no stress
  double stalls_per_second = 4;    ///< over the whole swarm and the world
  int64_t min_stall_ms = 10;
  int64_t max_stall_ms = 200;
  bool stall_world = true;         ///< the world is one more target, as likely as each robot
  /// The robots' processes together get this much of one core (1 .. 1000
  /// per mille of a 100 ms period); 0: no quota.
  uint32_t cpu_quota_permille = 0;
  /// The fraction (0 .. 1) of the samples a receiver takes that arrive
  /// late, each held min_delay_ms .. max_delay_ms (SampleDelayNs).
  double delayed_fraction = 0.05;
  int64_t min_delay_ms = 10;
  int64_t max_delay_ms = 200;

  bool on() const { return seed != 0; }
};

/// The world, as a stall's target.
inline constexpr uint16_t kStallWorld = 0xFFFF;

/// One SIGSTOP burst: `target` (a robot id, or kStallWorld) is stopped at
/// `at_ns` of run time (since the grid's origin) for `duration_ns`.
struct Stall {
  int64_t at_ns = 0;
  int64_t duration_ns = 0;
  uint16_t target = 0;

  bool operator==(const Stall&) const = default;
};

/// The stalls of a run of `duration_ns` with `robots` robots, in the order
/// of `at_ns`: a function of the options alone (SplitMix64 from the seed).
/// Empty when the stress is off. Stalls start in the first 95 % of the run.
std::vector<Stall> PlanStalls(const StressOptions& options, int64_t duration_ns, uint16_t robots);

/// The streams whose samples may arrive late. Each has its own draws, so a
/// beacon and a reading with the same key are late independently.
enum class DelayedStream : uint8_t { kBeacon = 1, kImu = 2, kFlow = 3, kUwb = 4 };

/// The sender of a sample the world sends (a sensor reading).
inline constexpr uint16_t kFromWorld = 0xFFFF;

/// How long `receiver` holds the sample of `stream` from `sender` stamped
/// `stamp` (a beacon's round, a reading's world time in ns) before it
/// handles it: 0 for most samples; for about `delayed_fraction` of them,
/// min_delay_ms .. max_delay_ms in whole ms. A hash of (seed, stream,
/// sender, receiver, stamp), so each link is late on its own, as with a
/// network, and a rerun delays the same samples by the same amounts. 0 when
/// the stress is off or its options are refused.
int64_t SampleDelayNs(const StressOptions& options, DelayedStream stream, uint16_t sender, uint16_t receiver,
                      int64_t stamp);

/// What is wrong with the options (where "stress"), or nothing: stall or
/// delay lengths outside 1 .. 10,000 ms or min above max, a negative rate
/// or above 100 a second, a quota above 1000 per mille, a delayed fraction
/// outside 0 .. 1.
std::optional<Error> CheckStressOptions(const StressOptions& options);

/// A cgroup the robots' processes join, with a CPU quota (cgroup v1's cpu
/// controller when it is mounted and writable, else v2's cpu.max).
/// Removed (its processes moved back to the root) when destroyed.
class CpuQuotaGroup {
 public:
  /// Creates the group; on failure ok() is false and error() says why
  /// (not root, no cpu controller).
  explicit CpuQuotaGroup(uint32_t permille);
  ~CpuQuotaGroup();
  CpuQuotaGroup(const CpuQuotaGroup&) = delete;
  CpuQuotaGroup& operator=(const CpuQuotaGroup&) = delete;

  bool ok() const { return !path_.empty(); }
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }
  /// Moves `pid` into the group; false if the kernel refused.
  bool Add(int pid);

 private:
  std::string path_;
  std::string root_;  // where processes go back to
  std::string error_;
};

}  // namespace syrof::lab::sim
