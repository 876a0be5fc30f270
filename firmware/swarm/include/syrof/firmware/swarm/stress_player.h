// Seeded stress on the emulated swarm (docs/firmware.md, "Stress"): the
// plan is lab/sim/stress.h's, the one the DDS world plays (docs/dds.md,
// "Stress"); this player applies it to qemu instances and to the host.
//
//   - a stall of robot i: SIGSTOP to its qemu, SIGCONT when the stall ends
//     (a "qemu stall": the guest's vCPU and its I/O thread stop, its clock
//     on the host's time runs on, as for a guest the host did not schedule);
//   - a stall of the world: the host itself does nothing for the stall's
//     length (it is one thread, so sleeping is being stopped): no world
//     steps, no sensor frames, no beacons delivered, while the guests run.
//
// A robot the scenario has not switched on, has paused or crashed is left
// alone, and a stall ends (SIGCONT) only for a robot still running then.
// Times are world time, as the faults' (fault_player.h). Pure: the
// signals go through the `Signal` callback.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "syrof/lab/sim/stress.h"

namespace syrof::firmware::swarm {

class StressPlayer {
 public:
  /// `stop` true: SIGSTOP robot's qemu; false: SIGCONT.
  using Signal = std::function<void(uint16_t robot, bool stop)>;
  /// Whether `robot` runs now (switched on, not paused, not crashed).
  using Running = std::function<bool(uint16_t robot)>;

  /// The plan of a run of `duration_ns` of world time with `robots`
  /// robots (lab::sim::PlanStalls); nothing when the stress is off.
  StressPlayer(const lab::sim::StressOptions& options, int64_t duration_ns, uint16_t robots);

  /// The stalls due by `world_ns`: ends the robot stalls that are over,
  /// starts those due. Returns how long the world must stall now (ns; 0:
  /// none), the longest of the world's stalls that came due.
  int64_t Play(int64_t world_ns, const Running& running, const Signal& signal);

  /// The end of the run: every robot still stopped by the stress and
  /// running continues; no stall starts after this.
  void EndAll(const Running& running, const Signal& signal);

  /// SIGSTOP bursts applied to robots, and world stalls played.
  int64_t robot_stalls() const { return robot_stalls_; }
  int64_t world_stalls() const { return world_stalls_; }
  const std::vector<lab::sim::Stall>& plan() const { return plan_; }

 private:
  std::vector<lab::sim::Stall> plan_;
  size_t next_ = 0;
  std::vector<int64_t> stopped_until_;  // per robot, world ns; -1: not stopped by the stress
  int64_t robot_stalls_ = 0;
  int64_t world_stalls_ = 0;
};

}  // namespace syrof::firmware::swarm
