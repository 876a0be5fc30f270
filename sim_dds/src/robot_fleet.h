// The DDS world's robot processes (docs/dds.md, "Processes"), as the world
// loop's RobotRuntime: a join spawns a robot (those present at start are
// spawned before discovery), a crash is SIGKILL, a pause SIGSTOP and its
// end SIGCONT; every robot is ended and reaped, with its exit and its CPU
// time, before the fleet goes. Internal to sim_dds.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/lab/sim/remote_world.h"
#include "syrof/lab/sim/stress.h"
#include "syrof/process/spawn.h"
#include "syrof/sim_dds/dds_world.h"
#include "syrof/sim_dds/robot_process.h"

namespace syrof::sim_dds {

class RobotFleet final : public lab::sim::RobotRuntime {
 public:
  /// Robots of run `run_id` on DDS domain `domain_id`, from `robot_binary`
  /// with `options`; each pid started goes to `pids`; a robot that cannot
  /// be started when the player switches it on is logged to `log` (the
  /// player counts it crashed). `options`, `loop`, `log` and `pids`
  /// outlive the fleet.
  RobotFleet(const SwarmOptions& options, std::string robot_binary, uint64_t run_id, uint32_t domain_id,
             const lab::sim::RemoteWorld& loop, std::ostream& log, std::vector<int>& pids);
  ~RobotFleet() override { EndAll(); }
  RobotFleet(const RobotFleet&) = delete;
  RobotFleet& operator=(const RobotFleet&) = delete;

  /// Starts robot `id`'s process: the world's environment, standard output
  /// and error; a process group of its own; SIGKILL when the world ends,
  /// even killed outright; its network namespace when
  /// SwarmOptions::robot_networks names one; in `quota` when set. False:
  /// spawn_error() says why.
  bool Spawn(uint16_t id);
  const std::string& spawn_error() const { return spawn_error_; }

  /// The robots' CPU quota (--stress), joined by every robot spawned after.
  void JoinQuota(lab::sim::CpuQuotaGroup* quota) { quota_ = quota; }

  process::Child& process(uint16_t id) { return robots_[id].process; }
  /// Reaps robot `id` if it ended (or waits for it, `block`): its exit and CPU time.
  void Reap(uint16_t id, bool block);
  /// Whether some robot process started and ended (after Reap).
  bool AnyEnded() const;
  /// Whether every robot process started has been reaped.
  bool AllReaped() const;
  /// SIGKILL to each robot's process group not reaped yet, then reap all.
  void EndAll();

  /// Per robot: its CPU seconds, and its exit code or minus the signal that
  /// ended it (unset: never started or not reaped).
  std::vector<double> cpu_seconds() const;
  std::vector<std::optional<int>> exits() const;

  // RobotRuntime
  bool StartRobot(uint16_t id, int64_t world_ns, bool resume) override;
  void StopRobot(uint16_t id, int64_t world_ns, lab::sim::StopReason reason) override;
  /// The robot's newest report says its epoch and mode.
  lab::sim::EventStamp Stamp(uint16_t id) const override { return loop_.Stamp(id); }

 private:
  struct Slot {
    process::Child process;  // not started: a joiner not yet switched on
    double cpu_seconds = 0;
    std::optional<int> exit;
  };

  const SwarmOptions& options_;
  const std::string robot_binary_;
  const lab::sim::RemoteWorld& loop_;
  std::ostream& log_;
  std::vector<int>& pids_;
  RobotProcessOptions robot_options_;
  // Above 0: robot processes start at SCHED_FIFO with this priority (--realtime where allowed).
  int fifo_priority_ = 0;
  std::vector<Slot> robots_;
  lab::sim::CpuQuotaGroup* quota_ = nullptr;
  std::string spawn_error_;  // why the last Spawn failed
};

}  // namespace syrof::sim_dds
