// A scenario's faults as the emulated swarm's host plays them on qemu
// instances (docs/firmware.md, "Faults"): which robot is switched on, running,
// paused or crashed at each instant of world time, and what the host has to do
// to its qemu process to get there. Times are world time; a fault takes
// effect on the radio-round grid, exactly as in the lab (lab::sim::FaultSchedule,
// docs/scenarios.md, "Pause timing").
//
//   kLaunch    a `join`: start the robot's qemu now (absent until then);
//   kKill      a `crash`: SIGKILL its qemu, close its sockets; for good;
//   kStop      a `pause`: SIGSTOP its qemu (the guest's clock keeps running);
//   kContinue  the pause's end: SIGCONT.
//
// The radio faults (`deaf`, `mute`) change no process: Blocked() says which
// beacons the host's channel drops for them. Pure: no processes or clocks here.
#pragma once

#include <cstdint>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/fault_schedule.h"

namespace syrof::firmware::swarm {

enum class Presence : uint8_t {
  kAbsent,   ///< not switched on yet (a later `join`)
  kRunning,  ///< its qemu runs
  kPaused,   ///< its qemu is stopped (SIGSTOP) until the pause ends
  kCrashed,  ///< its qemu was killed
};

const char* ToString(Presence presence);

struct HostAction {
  enum class Kind : uint8_t { kLaunch, kKill, kStop, kContinue };
  Kind kind = Kind::kLaunch;
  uint16_t robot = 0;

  bool operator==(const HostAction&) const = default;
};

const char* ToString(HostAction::Kind kind);

class FaultPlayer {
 public:
  /// `scenario`'s robots (present_at_start) and faults; `radio_round_ns` > 0
  /// is the grid.
  FaultPlayer(const lab::scenario::Scenario& scenario, int64_t radio_round_ns);

  /// The host actions due at `world_ns` (non-decreasing; call at every
  /// physics step, the grid's points included), applied to the presences
  /// before returning. A resume for a robot that is no longer paused (it
  /// crashed meanwhile) and a pause of a robot that is not running are
  /// dropped, as the lab and the DDS world drop them.
  std::vector<HostAction> Advance(int64_t world_ns);

  Presence presence(uint16_t robot) const { return presence_[robot]; }
  uint16_t robots() const { return static_cast<uint16_t>(presence_.size()); }

  /// Whether the host drops a beacon `from` sends to `to` at `time_s` for a
  /// radio fault: `from` is mute or `to` is deaf then ([at_s, until_s)).
  bool Blocked(uint16_t from, uint16_t to, double time_s) const;

  /// Whole seconds of its own time a robot launched at `launch_ns` runs so
  /// that it stops with the others after `run_seconds` (at least 1).
  static int RemainingSeconds(int run_seconds, int64_t launch_ns);

 private:
  std::vector<Presence> presence_;
  lab::sim::FaultSchedule schedule_;
  std::vector<lab::scenario::FaultSpec> radio_faults_;
};

}  // namespace syrof::firmware::swarm
