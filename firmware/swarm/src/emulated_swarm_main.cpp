// syrof-firmware-swarm: an emulated swarm of real firmware. Starts N qemu
// mps2-an386 instances of syrof-robot-mps2, each with its console (UART0),
// its radio UART (UART1) and its sensor UART (UART2) on Unix sockets this
// process listens on. It plays the world: a scenario's arena and bodies
// (lab::world::World, stepped every 10 ms of world time with the drive
// commands the robots send back on their sensor links; world time is the
// host's clock slowed to the robots' mean clock rate, guest_clock.h) and each robot's
// simulated sensors (lab::sensors::SensorBank, seeded as the lab and the DDS
// world seed them), whose readings go out as sensor-link frames
// (docs/radio-link.md, "The sensor link"). It plays the radio channel
// between the robots with the lab's channel model
// (lab/world/channel.h): every SendBeacon frame a robot sends is delivered
// to each other robot as a ReceivedBeacon frame unless the channel loses it
// (a hash of seed, the world's round the beacon was sent in, sender and
// receiver: the lab's and the DDS world's decision), half a
// radio round of the sender's clock after it was sent (scaled to host time
// by the sender's measured clock rate, guest_clock.h), as the lab's radio
// delivers (the robots' round alignment expects that latency:
// firmware/robot/robot_image.h, kBeaconLatencyNs). It feeds
// the lab's metrics collector from the robots' console reports (their
// estimates) and the world's true poses (collisions, estimation error), and
// writes DIR/metrics.json (docs/metrics.md), DIR/replay (lab/replay, for
// `syrof view`; read back before the run ends), DIR/firmware-swarm.json
// (timing mode, channel and sensor-link counts),
// DIR/beacons.csv (when each robot's beacons reached this process);
// DIR/robot_<i>.log holds each robot's console and DIR/qemu_<i>.log qemu's
// own output.
//
// --base-station PATH plays a base station's radio: this process listens on
// the Unix socket PATH, and a client there (syrof-bridge --socket PATH,
// docs/bridge.md) gets every beacon a robot sends as a ReceivedBeacon frame
// (docs/radio-link.md), the moment the host reads it, with a fixed RSSI of
// -50 dBm and no channel loss: a base station in the middle of the arena
// that hears every advertisement on the air. Deaf, mute and partitions are
// between robots and do not apply to it. A client may connect (and
// reconnect) at any time; it never slows the swarm (what it does not read
// is dropped past 64 KiB). Nothing else of the run changes.
//
// The scenario (--scenario FILE, else the built-in one below: 4 omni robots
// on a grid in the default 4 m arena, builtin:circle, no loss) gives the
// arena, the robots' start poses, the sensors' noise, the channel and the
// goal; --robots, --seed and --loss override it. The robot image has its app,
// arena, anchors and timing compiled in. Each robot boots its own copy of
// the image, DIR/robot_<i>.elf, whose configuration block holds its id, the
// swarm's size, its kinds and its private inputs, written with
// syrof-firmware-config's code as a class flashes a robot
// (qemu_launcher.h, WriteRobotImages); its start pose, the late joiners and
// the activation reach it through -append (--config-on-boot-line: all of
// it). Each image names its app on its held line: the replay and
// metrics.json name that app, and a scenario naming another gets one warning
// line on standard error (image_app.h). Every robot's qemu is launched at once with `hold 1`: it
// boots and waits; the world starts when all are held, and a robot's clock
// starts when the host sends it a Start frame on its sensor link (the
// robots present at start at one instant, a joiner when it joins), so every
// robot's rounds lie on the world's grid. The scenario's faults are played
// on world time with the lab's rules (lab::sim::WorldPlayer,
// fault_player.h): a join switches the robot on (once its start disc is
// clear), a crash kills it,
// a pause stops it (SIGSTOP/SIGCONT), deaf and mute drop beacons; partitions
// are the channel's. fault_outcomes.h judges, from the robots' reports,
// whether the swarm handled each (--expect-faults makes that a check).
//
//   syrof-firmware-swarm --image build-m4/bin/syrof-robot-mps2.elf [--scenario FILE] --robots 4
//       --seconds 20 --loss 0 --seed 1 --out DIR [--qemu qemu-system-arm] [--icount SHIFT|-1]
//       [--align 0|1] [--latency-ms 25] [--expect-cooperative] [--expect-faults] [--max-estimation-error M]
//       [--realtime] [--base-station PATH] [--stress SEED [--stress-rate R] [--stress-late F] [--stress-cpu-quota P]]
//       [--live [ADDR:PORT] [--live-linger S]]
//
// --live serves the live page (docs/viewer.md, "Live") as `syrof swarm
// --live` does, with the same server and options (lab/live): a reader of the
// rounds the host records, so the page shows each round as the robots'
// reports make it; after the run it links the replay.
//
// --stress SEED plays lab/sim/stress.h's seeded stress (stress_player.h):
// qemu instances and the host stopped for 10-200 ms, a fraction of the
// beacons delivered late, the qemu instances under one CPU quota; a run
// that fails under it prints the command that reruns it.
//
// Exit status 0 when every instance ran to the end and reported, no P3
// breach happened, the replay reads back whole, (with --expect-cooperative)
// all robots started one epoch COOPERATIVE, and (with
// --max-estimation-error) the largest scored estimation error stayed within
// M metres, and (with --expect-faults) every crash, pause and join was
// handled; 1 otherwise; 2 for a usage error.

#include <signal.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "syrof/firmware/swarm/qemu_launcher.h"
#include "syrof/firmware/swarm/swarm_host.h"
#include "syrof/firmware/swarm/swarm_options.h"
#include "syrof/lab/live/live_command.h"
#include "syrof/lab/live/live_server.h"

namespace swarm = syrof::firmware::swarm;
namespace live = syrof::lab::live;

int main(int argc, char** argv) {
  const swarm::Options parsed_options = swarm::ParseOptions(argc, argv);
  const syrof::lab::scenario::Scenario scenario = swarm::LoadScenario(parsed_options);
  swarm::CheckBootLines(parsed_options, scenario);
  swarm::Options options = parsed_options;
  for (int i = 0; i < argc; ++i) options.command_line += (i == 0 ? "" : " ") + std::string(argv[i]);
  options.robots = static_cast<int>(scenario.robots.size());
  options.seed = scenario.seed;
  options.loss = scenario.channel.loss;
  signal(SIGPIPE, SIG_IGN);
  if (options.realtime) swarm::SetRealtime();
  std::error_code made;
  std::filesystem::create_directories(options.out, made);
  if (made || !std::filesystem::is_directory(options.out)) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot make the output directory %s: %s\n", options.out.c_str(),
                 made.message().c_str());
    return 1;
  }
  // Each robot's own image with its configuration block, as a class flashes it.
  if (!swarm::WriteRobotImages(options, scenario)) return 1;
  // The live page listens before any qemu starts: an address it cannot
  // have is a usage error (exit 2), as for `syrof swarm --live`.
  std::vector<syrof::lab::replay::RoundSink*> sinks;
  live::LiveResult started_live = live::StartLive(options.live, scenario.name + " (firmware swarm)", std::cout, sinks);
  if (!started_live.ok()) {
    std::cerr << "syrof-firmware-swarm: " << started_live.error->ToString() << "\n";
    return 2;
  }
  const std::unique_ptr<live::LiveServer> live_page = std::move(started_live.server);
  swarm::SwarmHost host(options, scenario, sinks);
  if (!host.OpenSockets() || !host.LaunchRobots()) {
    // The page says the run stopped, with no replay to link.
    if (live_page) {
      live_page->OnFinish(false);
      live_page->SetReplayPage(std::nullopt);
    }
    return 1;
  }
  host.StartWorld();
  while (host.Running()) host.Step();
  const int status = host.Finish();
  if (live_page) live::EndLive(*live_page, options.live, options.out + "/replay", std::cout);
  return status;
}
