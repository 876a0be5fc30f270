// Seeded stress on a DDS run (lab/sim/stress.h, docs/dds.md "Stress"): the
// robots' SIGSTOP bursts played on the run's grid, the world's own played
// by a child process (a stopped process cannot wake itself), and the robots'
// CPU quota. The late beacons and readings are the robots' to play
// (RobotProcessOptions::stress). Internal to sim_dds.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/sim/stress.h"
#include "syrof/process/spawn.h"

namespace syrof::sim_dds {

/// Why the stress could not start: the run's exit code (2: bad options) and what.
struct StressFailure {
  int exit_code = 1;
  lab::Error error;
};

class WorldStress {
 public:
  /// Whether robot `id` may be signalled now.
  using Robot = std::function<bool(uint16_t id)>;
  /// `stop` true: SIGSTOP robot `id`; false: SIGCONT.
  using Signal = std::function<void(uint16_t id, bool stop)>;

  /// The stress of a run of `robots` robots; nothing happens when it is off.
  WorldStress(const lab::sim::StressOptions& options, uint16_t robots);
  /// Ends the world's staller (End's last part) if End was not called.
  ~WorldStress();
  WorldStress(const WorldStress&) = delete;
  WorldStress& operator=(const WorldStress&) = delete;

  /// The robots' CPU quota group, when the options ask for one; before any
  /// robot starts. quota() is null without one.
  std::optional<StressFailure> OpenQuota();
  lab::sim::CpuQuotaGroup* quota() { return quota_.get(); }

  /// The plan from the seed over a run of `duration_ns` starting at
  /// `start_monotonic_ns`, said in one line to `log`, and the process that
  /// stalls the world at its stalls' instants.
  std::optional<StressFailure> Start(int64_t duration_ns, int64_t start_monotonic_ns, std::ostream& log);

  /// The robot stalls due by run time `now_ns`: SIGSTOP to those `running`
  /// says may be stopped, SIGCONT at a stall's end to those still running.
  void Play(int64_t now_ns, const Robot& running, const Signal& signal);

  /// No stall outlives the run: each robot the stress stopped continues when
  /// `may_continue` says so, the world's staller is told to stop and reaped
  /// (it finishes the stall it is in, if any). No stall starts after.
  void End(const Robot& may_continue, const Signal& signal);

  /// SIGSTOP bursts applied so far, robots' and world's.
  int64_t stalls() const { return stalls_; }
  /// The stress's seed once Start accepted the options (0: none).
  uint64_t seed() const { return seed_; }

 private:
  void EndStaller();

  const lab::sim::StressOptions options_;
  std::vector<lab::sim::Stall> stalls_plan_;
  size_t next_stall_ = 0;
  std::vector<int64_t> stalled_until_;  // per robot, run time; -1: not stopped by the stress
  process::Child world_staller_;
  std::atomic<int>* staller_stop_ = nullptr;  // shared with the staller (an anonymous shared page)
  std::unique_ptr<lab::sim::CpuQuotaGroup> quota_;
  int64_t stalls_ = 0;
  uint64_t seed_ = 0;
};

}  // namespace syrof::sim_dds
