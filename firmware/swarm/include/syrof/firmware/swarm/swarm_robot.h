// One emulated robot as syrof-firmware-swarm holds it: its qemu, its three
// links (console, radio, sensor link; -1 once closed), its sensor feed, and what
// the host has read of it. The launcher (qemu_launcher.h) starts it, the
// channel (beacon_channel.h) reads its radio, the host (swarm_host.h) its
// console and sensor link.
#pragma once

#include <chrono>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/firmware/swarm/console_lines.h"
#include "syrof/firmware/swarm/guest_clock.h"
#include "syrof/firmware/swarm/sensor_feed.h"
#include "syrof/firmware/swarm/world_grid.h"
#include "syrof/process/spawn.h"

namespace syrof::firmware::swarm {

struct Robot {
  process::Child qemu;       // not started: LaunchRobots failed before it
  bool held = false;         // its image said `held`: prepared, waiting for its Start frame
  std::string app;           // the app its image runs, from its held line (console_lines.h)
  bool switched_on = false;  // its Start frame was sent
  SwitchOn switched_on_at;   // where its rounds lie on the world's grid
  int radio = -1;
  int console = -1;
  int sensor = -1;
  SensorFeed feed;
  std::vector<uint8_t> sensor_out;  // frames not yet taken by the socket
  drivers::FrameDecoder decoder;
  std::string pending_line;
  std::ofstream log;
  std::vector<int64_t> beacon_ns;  // host instants of its SendBeacon frames
  // Its round boundaries not yet recorded, for the round-start skew
  // (SwarmHost::RecordRound).
  BoundariesByRound boundary_ns_of_round;
  std::optional<RoundLine> latest;
  int64_t latest_ns = 0;
  int64_t last_boundary_ns = 0;
  GuestClockRate clock_rate;  // from its R lines' t_ms
  int64_t lines = 0;
  int64_t bad_lines = 0;
  std::string last_status;
  int exit_status = -1;
};

/// The host's clock (steady), in nanoseconds.
inline int64_t HostNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace syrof::firmware::swarm
