// syrof-firmware-swarm's command line and the scenario it runs: the
// options (docs/firmware.md, "The emulated swarm"), their usage text, and
// the scenario loaded with the command line's overrides and checked against
// what the robot image has compiled in. A usage error exits 2 with the
// reason and the usage (these run in the program's main only).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "syrof/lab/live/live_command.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/stress.h"
#include "syrof/wire/beacon_layout.h"

namespace syrof::firmware::swarm {

/// What the command line says (ParseOptions); main fills in the robots,
/// seed and loss the scenario gives, and the command line as given.
struct Options {
  std::string image;
  std::string qemu = "qemu-system-arm";
  std::string out = "firmware-swarm";
  int robots = 4;
  int seconds = 20;
  double loss = 0;
  uint64_t seed = 1;
  // -1 (the default): no -icount, the guests' clocks are the host's; 4:
  // -icount shift=4, a guest instruction is 16 ns of its virtual time (62.5
  // MHz, near the Teensy's 72), each guest's clock at its own rate
  // (docs/firmware.md, "The emulated swarm", says how this was chosen).
  int icount_shift = -1;
  bool expect_cooperative = false;
  bool expect_faults = false;  // every crash, pause and join handled (FaultOutcomes)
  bool realtime = false;       // this process and every qemu at SCHED_FIFO (SetRealtime)
  // --config-on-boot-line: each robot's id, swarm, kinds and inputs on its
  // boot line, as the image's words, on the image as built; by default they
  // are in its own copy of the image's configuration block, as a class
  // flashes them (qemu_launcher.h, WriteRobotImages).
  bool config_on_boot_line = false;
  // The robots' round alignment (docs/clocks.md): by default on under
  // -icount, where each guest's clock runs at its own rate, and off on the
  // host's clock, which every guest shares from its Start frame on.
  std::optional<bool> align;
  double latency_ms = 25;  // from a beacon's send to its delivery, on the sender's clock (GuestClockRate)
  std::string scenario;    // empty: kBuiltInScenario
  std::optional<int> robots_override;
  std::optional<uint64_t> seed_override;
  std::optional<double> loss_override;
  std::optional<double> max_estimation_error_m;
  std::string base_station;  // empty: none; else the Unix socket a base station's client connects to
  lab::sim::StressOptions stress;  // --stress SEED and its options (docs/firmware.md, "Stress")
  std::string command_line;        // as given: what reruns a run that failed under stress
  // --live[=ADDR:PORT] and --live-linger S: the live page, as `syrof swarm
  // --live` serves it (docs/viewer.md, "Live"); off when its address is empty.
  lab::live::LiveCommandOptions live;
};

// The most robots an emulated swarm runs: as many as the robots' radio
// carries a beacon for (one BLE advertisement, wire::LargestRadioSwarm: 16),
// within the image's SYROF_MAX_SWARM_SIZE of 32 (the Teensy's).
constexpr int kMaxImageRobots = wire::LargestRadioSwarm();
static_assert(kMaxImageRobots >= 1 && kMaxImageRobots <= 32, "the image is built for 32 robots");

/// The usage text --help prints.
extern const char* const kUsage;

/// Prints `what` and the usage to stderr and exits 2.
[[noreturn]] void Usage(const std::string& what);

/// The command line; --help prints the usage and exits 0, a usage error
/// exits 2 (an unknown argument, a value out of its range, a stress option
/// without --stress, a --live address that is none, --live-linger without
/// --live, an image that cannot be read).
Options ParseOptions(int argc, char** argv);

/// The scenario, with the command line's overrides; exits 2 with the
/// loader's file:line:column message when it is not valid, or naming what
/// the robot image cannot run.
lab::scenario::Scenario LoadScenario(const Options& options);

}  // namespace syrof::firmware::swarm
