// A scenario's faults as the emulated swarm's host plays them on qemu
// instances (docs/firmware.md, "Faults"). The rules (which robot is switched
// on, running, paused or crashed at each instant of world time, the join
// wait, the radio-round grid) are lab::sim::WorldPlayer's, the same for the
// lab, the DDS world and this host; HostActions turns what the player asks
// for into what the host does to a qemu process:
//
//   kSwitchOn  the start, or a `join`: send the robot's held image its Start
//              frame (its qemu runs from the beginning, held until then);
//   kKill      a `crash`: SIGKILL its qemu, close its sockets; for good;
//   kStop      a `pause`: SIGSTOP its qemu (the guest's clock keeps running);
//   kContinue  the pause's end: SIGCONT.
//
// The radio faults (`deaf`, `mute`) change no process: RadioFaults says
// which beacons the host's channel drops for them. Pure: no processes or
// clocks here.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/world_player.h"

namespace syrof::firmware::swarm {

struct HostAction {
  enum class Kind : uint8_t { kSwitchOn, kKill, kStop, kContinue };
  Kind kind = Kind::kSwitchOn;
  uint16_t robot = 0;

  bool operator==(const HostAction&) const = default;
};

const char* ToString(HostAction::Kind kind);

/// The host's RobotRuntime: each start and stop the world player asks for
/// becomes one HostAction handed to `act` with its world time. An app fault
/// asks for nothing: the firmware stops its own app.
class HostActions final : public lab::sim::RobotRuntime {
 public:
  /// `act` does the action; false when it could not (the image was not held).
  using Act = std::function<bool(const HostAction& action, int64_t world_ns)>;
  explicit HostActions(Act act) : act_(std::move(act)) {}

  bool StartRobot(uint16_t id, int64_t world_ns, bool resume) override;
  void StopRobot(uint16_t id, int64_t world_ns, lab::sim::StopReason reason) override;

 private:
  Act act_;
};

/// The scenario's radio faults.
class RadioFaults {
 public:
  explicit RadioFaults(const lab::scenario::Scenario& scenario);

  /// Whether the host drops a beacon `from` sends to `to` at `time_s`:
  /// `from` is mute or `to` is deaf then ([at_s, until_s)).
  bool Blocked(uint16_t from, uint16_t to, double time_s) const;

 private:
  std::vector<lab::scenario::FaultSpec> faults_;
};

/// Milliseconds of its own time a robot switched on at world time
/// `start_ns` runs so that it stops with the others after `run_seconds`
/// (at least 1): its Start frame's run_ms.
uint32_t RemainingMs(int run_seconds, int64_t start_ns);

}  // namespace syrof::firmware::swarm
