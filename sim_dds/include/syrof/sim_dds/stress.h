// Seeded stress for a DDS swarm (docs/dds.md, "Stress"): what a loaded
// machine does to processes that run in wall-clock time, made repeatable.
//
//   - stalls: SIGSTOP, then SIGCONT 10 to 200 ms later, of a robot process
//     or of the world, at moments and of lengths drawn from the seed;
//   - a CPU quota: the robot processes share one cgroup whose quota is a
//     fraction of one core (cgroup v1 cpu.cfs_quota_us, or v2 cpu.max).
//
// The plan is a pure function of the seed and the run's size, so a failing
// stressed run reruns from its seed: the same processes are stopped at the
// same instants of the run for the same lengths. What the kernel and DDS do
// around them is not replayed; the stress is.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace syrof::sim_dds {

struct StressOptions {
  uint64_t seed = 0;               ///< 0: no stress
  double stalls_per_second = 4;    ///< over the whole swarm and the world
  int64_t min_stall_ms = 10;
  int64_t max_stall_ms = 200;
  bool stall_world = true;         ///< the world is one more target, as likely as each robot
  /// The robot processes together get this much of one core (1 .. 1000
  /// per mille of a 100 ms period); 0: no quota.
  uint32_t cpu_quota_permille = 0;

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

/// What is wrong with the options, or empty: stall lengths outside
/// 1 .. 10,000 ms or min above max, a negative rate or above 100 a second,
/// a quota above 1000 per mille.
std::string CheckStressOptions(const StressOptions& options);

/// A cgroup the robot processes join, with a CPU quota (cgroup v1's cpu
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

}  // namespace syrof::sim_dds
