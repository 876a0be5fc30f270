// The launcher of syrof-firmware-swarm: the robots' qemu processes and the
// Unix sockets their three UARTs connect to (console, radio, sensor link),
// and what the host does to a qemu when the world player asks (switch on,
// crash, pause, resume). Every robot's qemu starts with `hold 1`: the
// image sets itself up, prints `held id=N` and waits for the Start frame
// that switches it on (docs/firmware.md, "One start for every robot").
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "syrof/firmware/swarm/fault_player.h"
#include "syrof/firmware/swarm/swarm_options.h"
#include "syrof/firmware/swarm/swarm_robot.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/stress.h"
#include "syrof/lab/sim/world_player.h"

namespace syrof::firmware::swarm {

// One robot's sockets and their listeners: console, radio, sensor link.
struct RobotSockets {
  std::string console_path, radio_path, sensor_path;
  int console_listener = -1, radio_listener = -1, sensor_listener = -1;
};

class QemuLauncher {
 public:
  /// `options` and `scenario` outlive the launcher.
  QemuLauncher(const Options& options, const lab::scenario::Scenario& scenario);
  // The sockets and their folder go on every way out (a launch that failed too).
  ~QemuLauncher() { RemoveSockets(); }
  QemuLauncher(const QemuLauncher&) = delete;
  QemuLauncher& operator=(const QemuLauncher&) = delete;

  /// A folder under /tmp and each robot's three listening sockets in it;
  /// false when the folder cannot be made (a socket that cannot be made
  /// ends the program with status 1).
  bool OpenSockets();
  /// A non-blocking listener on `path` (--base-station), removed with the others.
  int ListenBeside(const std::string& path);
  /// One qemu per robot of `swarm` (joiners too) in the stress's CPU quota
  /// if it has one, its console, radio and sensor link accepted in the order
  /// qemu connects them; false (every qemu killed) when one cannot be started
  /// or a link did not connect within `timeout_ms`.
  bool Launch(std::vector<Robot>& swarm, int timeout_ms);
  void KillAll(std::vector<Robot>& swarm);
  /// The sockets and their folder, once.
  void RemoveSockets();
  /// Whether the qemu instances run under --stress-cpu-quota.
  bool cpu_quota() const { return quota_ != nullptr; }

 private:
  const Options& options_;
  const lab::scenario::Scenario& scenario_;
  std::vector<RobotSockets> sockets_;
  std::vector<std::string> paths_;
  std::string socket_dir_;
  std::unique_ptr<lab::sim::CpuQuotaGroup> quota_;
};

/// Robot `id`'s -append text: what drives the emulation (`hold 1`, the
/// console reports, the sensor link, the round alignment, its start pose,
/// the late joiners and the scenario's activation; boot_words.h). Who the
/// robot is (its id, the swarm's size, its kind and the swarm's kinds, its
/// private inputs) is in its own image's configuration block
/// (WriteRobotImages), as a class flashes a robot; with
/// --config-on-boot-line (Options::config_on_boot_line) it is on this line
/// instead, and the image is the one built. Exits 2 (Usage) naming the
/// field when the activation's script or the inputs cannot be told the image.
std::string ImageAppend(const Options& options, const lab::scenario::Scenario& scenario, uint16_t id);

/// The image robot `id`'s qemu boots: DIR/robot_<id>.elf, the copy
/// WriteRobotImages fills, or the built image with --config-on-boot-line.
std::string RobotImagePath(const Options& options, uint16_t id);

/// Exits 2 (Usage) naming the field when some robot's configuration block
/// cannot be made from the scenario (firmware/config robot_config.h,
/// MakeRobotBlock: the words syrof-firmware-config refuses it with), or
/// its boot line (the image's path and ImageAppend) is longer than the
/// image reads (boot_words.h, kMaxBootLineBytes and kMaxBootLineWords): qemu
/// would refuse it, or the image stop on it.
void CheckBootLines(const Options& options, const lab::scenario::Scenario& scenario);

/// Writes each robot's own copy of the image, DIR/robot_<id>.elf, with its
/// configuration block filled from the scenario by the code
/// syrof-firmware-config runs (MakeRobotBlock, WriteBlock, WriteImage): the
/// images a class flashes onto its robots. Nothing with
/// --config-on-boot-line. Exits 2 (Usage) naming the file when the image is
/// no robot image with the block's section; false, said on stderr, when a
/// copy cannot be written.
bool WriteRobotImages(const Options& options, const lab::scenario::Scenario& scenario);

/// --realtime: this process at SCHED_FIFO, its qemu instances one priority
/// below (qemu_launcher.cpp says why); says so and goes on at normal
/// priority when it may not.
void SetRealtime();

/// Closes a robot's three sockets.
void CloseLinks(Robot& robot);

/// Does what the world player asks of a robot's qemu at world time
/// `world_ns` (qemu_launcher.cpp); whether it was done.
bool DoHostAction(const HostAction& action, int64_t world_ns, const Options& options, Robot& robot,
                  int& open_consoles);

/// The end of the run on world time: paused robots continue, robots still
/// held are killed.
void EndPausedAndHeld(std::vector<Robot>& swarm, const lab::sim::WorldPlayer& player, int& open_consoles);

}  // namespace syrof::firmware::swarm
