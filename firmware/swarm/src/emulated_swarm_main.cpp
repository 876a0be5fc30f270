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
// (timing mode, round-start skew, channel and sensor-link counts),
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
// arena, anchors and timing compiled in; the start pose reaches each robot
// through -append. Every robot's qemu is launched at once with `hold 1`: it
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

#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/firmware/swarm/console_lines.h"
#include "syrof/firmware/swarm/fault_outcomes.h"
#include "syrof/firmware/swarm/fault_player.h"
#include "syrof/firmware/swarm/firmware_metrics.h"
#include "syrof/firmware/swarm/guest_clock.h"
#include "syrof/firmware/swarm/round_skew.h"
#include "syrof/firmware/swarm/sensor_feed.h"
#include "syrof/firmware/swarm/stress_player.h"
#include "syrof/firmware/swarm/world_grid.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/apps/builtin_goals.h"
#include "syrof/lab/goals/goals.h"
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sim/round_recorder.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/world/channel.h"
#include "syrof/lab/world/world.h"
#include "syrof/process/fd.h"
#include "syrof/process/spawn.h"
#include "syrof/registry/tasks.h"

namespace {

namespace drivers = syrof::firmware::drivers;
namespace swarm = syrof::firmware::swarm;
namespace metrics = syrof::lab::metrics;
namespace lab = syrof::lab;
namespace process = syrof::process;
namespace replay = syrof::lab::replay;

// Without --scenario: what the swarm ran before it had a world (the image's
// built-in app, its default arena and timing), with robots on a grid.
constexpr const char* kBuiltInScenario =
    "name: firmware-swarm\n"
    "seed: 1\n"
    "arena: { width_m: 4, height_m: 4 }\n"
    "robots: { count: 4, kind: omni, placement: grid, spacing_m: 0.6 }\n"
    "timing: { radio_round_s: 0.05, app_round_s: 1.0, duration_s: 20 }\n"
    "channel: { model: iid, loss: 0 }\n"
    "app: builtin:circle\n";

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
  syrof::lab::sim::StressOptions stress;  // --stress SEED and its options (docs/firmware.md, "Stress")
  std::string command_line;               // as given: what reruns a run that failed under stress
};

// The robot image is built with SYROF_MAX_SWARM_SIZE=32 (the Teensy's).
constexpr int kMaxImageRobots = 32;

constexpr const char* kUsage =
    "usage: syrof-firmware-swarm --image ELF [--scenario FILE] [--robots 1..32] [--seconds S] [--loss 0..1]\n"
    "       [--seed N] [--out DIR] [--qemu PATH] [--icount SHIFT|-1] [--align 0|1] [--latency-ms MS]\n"
    "       [--expect-cooperative] [--expect-faults] [--max-estimation-error M] [--realtime]\n"
    "       [--base-station PATH] [--stress SEED [--stress-rate R] [--stress-late F] [--stress-cpu-quota P]]\n"
    "Starts one qemu mps2-an386 instance of the robot image per robot of the scenario (--robots, --seed\n"
    "and --loss override it) and plays the world, the robots' sensors and the radio channel between\n"
    "them; plays the scenario's faults (crash, pause, join, deaf, mute) and partitions on world time;\n"
    "writes metrics.json, replay, firmware-swarm.json and logs in --out (docs/firmware.md).\n"
    "The guests run on the host's clock; --icount SHIFT runs them with qemu's -icount shift=SHIFT.\n"
    "--realtime runs this process and the qemu instances at SCHED_FIFO (root or CAP_SYS_NICE).\n"
    "--base-station PATH listens on the Unix socket PATH and sends a client there every beacon sent, as\n"
    "ReceivedBeacon frames (syrof-bridge --socket PATH; docs/bridge.md).\n"
    "--stress SEED: seeded SIGSTOP bursts of 10-200 ms of the qemu instances and the host (R a second,\n"
    "default 4), the fraction F of beacons (default 0.05) delivered 10-200 ms late, the qemu instances\n"
    "at P per mille of one core (a cgroup; root); a failing run prints the command that reruns it.\n";

[[noreturn]] void Usage(const std::string& what) {
  std::fprintf(stderr, "syrof-firmware-swarm: %s\n%s", what.c_str(), kUsage);
  std::exit(2);
}

Options ParseOptions(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--help" || key == "-h") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    }
    if (key == "--expect-cooperative") {
      options.expect_cooperative = true;
      continue;
    }
    if (key == "--expect-faults") {
      options.expect_faults = true;
      continue;
    }
    if (key == "--realtime") {
      options.realtime = true;
      continue;
    }
    static const std::string_view kWithValue[] = {"--image",    "--qemu",    "--out",      "--robots",
                                                  "--seconds",  "--loss",    "--seed",     "--scenario",
                                                  "--max-estimation-error", "--latency-ms", "--align", "--icount",
                                                  "--base-station", "--stress", "--stress-rate", "--stress-late",
                                                  "--stress-cpu-quota"};
    if (std::find(std::begin(kWithValue), std::end(kWithValue), key) == std::end(kWithValue)) {
      Usage("unknown argument '" + key + "'");
    }
    if (i + 1 >= argc) Usage("argument " + std::to_string(i) + " '" + key + "' has no value");
    const std::string value = argv[++i];
    char* end = nullptr;
    auto number = [&](double low, double high) {
      const double parsed = std::strtod(value.c_str(), &end);
      if (end == value.c_str() || *end != '\0' || !(parsed >= low && parsed <= high)) {
        char range[64];
        std::snprintf(range, sizeof range, "[%g, %g]", low, high);
        Usage(key + ": '" + value + "' is not a number in " + range);
      }
      return parsed;
    };
    if (key == "--image") {
      options.image = value;
    } else if (key == "--qemu") {
      options.qemu = value;
    } else if (key == "--out") {
      options.out = value;
    } else if (key == "--robots") {
      options.robots = static_cast<int>(number(1, kMaxImageRobots));
      options.robots_override = options.robots;
    } else if (key == "--seconds") {
      options.seconds = static_cast<int>(number(1, 3600));
    } else if (key == "--loss") {
      options.loss = number(0, 1);
      options.loss_override = options.loss;
    } else if (key == "--seed") {
      options.seed = static_cast<uint64_t>(number(0, 1e15));
      options.seed_override = options.seed;
    } else if (key == "--scenario") {
      options.scenario = value;
    } else if (key == "--max-estimation-error") {
      options.max_estimation_error_m = number(0, 100);
    } else if (key == "--latency-ms") {
      options.latency_ms = number(0, 1000);
    } else if (key == "--align") {
      options.align = number(0, 1) == 1;
    } else if (key == "--icount") {
      options.icount_shift = static_cast<int>(number(-1, 10));
    } else if (key == "--base-station") {
      options.base_station = value;
    } else if (key == "--stress") {
      options.stress.seed = static_cast<uint64_t>(number(1, 1e15));
    } else if (key == "--stress-rate") {
      options.stress.stalls_per_second = number(0, 100);
    } else if (key == "--stress-late") {
      options.stress.delayed_fraction = number(0, 1);
    } else if (key == "--stress-cpu-quota") {
      options.stress.cpu_quota_permille = static_cast<uint32_t>(number(1, 1000));
    } else {
      Usage("unknown argument '" + key + "'");
    }
  }
  if (!options.align) options.align = options.icount_shift >= 0;
  // The stress's own options mean nothing without its seed: refused, not ignored.
  if (!options.stress.on()) {
    for (int i = 1; i < argc; ++i) {
      const std::string_view key = argv[i];
      if (key == "--stress-rate" || key == "--stress-late" || key == "--stress-cpu-quota") {
        Usage(std::string(key) + " needs --stress SEED");
      }
    }
  }
  if (options.image.empty()) Usage("--image is required");
  if (access(options.image.c_str(), R_OK) != 0) {
    Usage("--image: cannot read " + options.image + " (build it: make test-m4, or cmake --build build-m4 --target syrof-robot-mps2)");
  }
  return options;
}

int64_t HostNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

int Listen(const std::string& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (fd < 0 || path.size() >= sizeof address.sun_path) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot make socket %s\n", path.c_str());
    std::exit(1);
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  unlink(path.c_str());
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || listen(fd, 1) != 0) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot listen on %s: %s\n", path.c_str(), std::strerror(errno));
    std::exit(1);
  }
  return fd;
}

// Accepts one connection, waiting at most `timeout_ms`.
int AcceptOne(int listener, int timeout_ms, const std::string& what) {
  pollfd entry{listener, POLLIN, 0};
  if (poll(&entry, 1, timeout_ms) != 1) {
    std::fprintf(stderr, "syrof-firmware-swarm: %s did not connect within %d ms\n", what.c_str(), timeout_ms);
    return -1;
  }
  return accept(listener, nullptr, nullptr);
}

// A ReceivedBeacon frame on its way to robot `to`.
struct Delivery {
  int64_t due_ns = 0;
  uint16_t to = 0;
  std::vector<uint8_t> bytes;
};

struct Robot {
  process::Child qemu;       // not started: LaunchRobots failed before it
  bool held = false;         // its image said `held`: prepared, waiting for its Start frame
  bool switched_on = false;  // its Start frame was sent
  swarm::SwitchOn switched_on_at;  // where its rounds lie on the world's grid
  int radio = -1;
  int console = -1;
  int sensor = -1;
  std::unique_ptr<lab::sensors::SensorBank> bank;
  swarm::SensorFeed feed;
  std::vector<uint8_t> sensor_out;  // frames not yet taken by the socket
  drivers::FrameDecoder decoder;
  std::string pending_line;
  std::ofstream log;
  std::vector<int64_t> beacon_ns;  // host instants of its SendBeacon frames
  std::optional<swarm::RoundLine> latest;
  int64_t latest_ns = 0;
  int64_t last_boundary_ns = 0;
  swarm::GuestClockRate clock_rate;  // from its R lines' t_ms
  int64_t lines = 0;
  int64_t bad_lines = 0;
  std::string last_status;
  int exit_status = -1;
};

}  // namespace

// The scenario, with the command line's overrides; exits 2 with the
// loader's file:line:column message when it is not valid.
lab::scenario::Scenario LoadScenario(const Options& options) {
  lab::scenario::Overrides overrides;
  overrides.robots = options.robots_override;
  overrides.seed = options.seed_override;
  overrides.duration_s = options.seconds;
  const lab::scenario::LoadResult loaded =
      options.scenario.empty() ? lab::scenario::LoadScenarioText(kBuiltInScenario, "<built-in scenario>", overrides)
                               : lab::scenario::LoadScenarioFile(options.scenario, overrides);
  if (!loaded.ok()) Usage("--scenario: " + loaded.error->ToString());
  lab::scenario::Scenario scenario = *loaded.scenario;
  if (options.loss_override) {
    scenario.channel.loss = *options.loss_override;
  }
  const auto robots = static_cast<int>(scenario.robots.size());
  if (robots > kMaxImageRobots) {
    Usage("--scenario: " + std::to_string(robots) + " robots; the robot image holds at most " +
          std::to_string(kMaxImageRobots));
  }
  // What the image has compiled in and cannot be told (robot_image.cpp).
  if (std::llround(scenario.timing.radio_round_s * 1e9) != syrof::registry::kDefaultRadioRoundNs) {
    Usage("--scenario: timing.radio_round_s must be 0.05 (the robot image's radio round)");
  }
  if (scenario.activation.model != syrof::sync::ActivationModel::kFsync) {
    Usage("--scenario: activation.model must be fsync (the robot image runs every robot in every epoch; "
          "docs/activation.md)");
  }
  for (const lab::scenario::RobotSpec& robot : scenario.robots) {
    if (robot.kind != lab::world::RobotKind::kOmni) Usage("--scenario: robot " + std::to_string(robot.id) + " is not omni; the robot image drives omni robots");
  }
  const bool pauses = std::any_of(scenario.faults.begin(), scenario.faults.end(), [](const auto& fault) {
    return fault.kind == lab::scenario::FaultKind::kPause;
  });
  if (pauses && options.icount_shift >= 0) {
    std::fprintf(stderr,
                 "syrof-firmware-swarm: note: under -icount a paused robot sees its stall only if qemu was stopped "
                 "while the guest slept; --icount -1 makes every pause visible (docs/firmware.md, \"Faults\")\n");
  }
  return scenario;
}

int64_t Milli(double value) { return std::llround(value * 1000.0); }

// --realtime: this process at SCHED_FIFO priority kHostPriority and the
// qemu instances it starts (their threads too) one below (LaunchQemu), so
// the world player takes a beacon and delivers it on time even when the
// guests want both cores. On two cores, four guests and this process want
// most of the machine; at normal priority a build beside them, or their own
// competition, holds a guest for tens of milliseconds, and its beacons reach
// the others a round late (docs/firmware.md, "One start for every robot").
// The kernel's real-time throttling keeps 5% of each second for everything
// else. Says so and goes on at normal priority when it may not.
constexpr int kHostPriority = 11;
constexpr int kGuestPriority = 10;

void SetRealtime() {
  sched_param parameters{};
  parameters.sched_priority = kHostPriority;
  if (sched_setscheduler(0, SCHED_FIFO, &parameters) != 0) {
    std::fprintf(stderr, "syrof-firmware-swarm: --realtime: SCHED_FIFO refused (%s); running at normal priority\n",
                 std::strerror(errno));
  }
}

// The start pose as the image's -append words (whole mm and mrad >= 0).
std::string StartPoseWords(const lab::scenario::RobotSpec& robot) {
  double heading = std::fmod(robot.heading_rad, 2 * M_PI);
  if (heading < 0) heading += 2 * M_PI;
  return " x_mm " + std::to_string(std::max<int64_t>(0, Milli(robot.x_m))) + " y_mm " +
         std::to_string(std::max<int64_t>(0, Milli(robot.y_m))) + " heading_mrad " +
         std::to_string(std::min<int64_t>(6283, Milli(heading)));
}

// The -append words every robot gets for the robots switched on later (a
// scenario's `join`): they are no initial members (the image's `late N`).
std::string LateJoinerWords(const lab::scenario::Scenario& scenario) {
  std::string words;
  for (const lab::scenario::RobotSpec& robot : scenario.robots) {
    if (!robot.present_at_start) words += " late " + std::to_string(robot.id);
  }
  return words;
}

// Starts robot `id`'s qemu with `hold 1`: the image sets itself up, prints
// `held id=N` and waits for its Start frame (DoHostAction), which says how
// long it runs; `paths` are its console, radio and sensor sockets (qemu
// connects to them in that order). qemu is looked for in PATH unless
// --qemu names a path; its standard output and error go to DIR/qemu_<id>.log;
// a real-time host's guests run one priority below it (SetRealtime).
process::Child LaunchQemu(const Options& options, const lab::scenario::Scenario& scenario, uint16_t id,
                 const std::string& console_path, const std::string& radio_path, const std::string& sensor_path) {
  const auto robots = static_cast<uint16_t>(scenario.robots.size());
  std::vector<std::string> args = {
      options.qemu, "-M", "mps2-an386", "-nographic", "-monitor", "none", "-semihosting-config",
      "enable=on,target=native",
      "-chardev", "socket,id=console,path=" + console_path, "-serial", "chardev:console",
      "-chardev", "socket,id=radio,path=" + radio_path, "-serial", "chardev:radio",
      "-chardev", "socket,id=sensor,path=" + sensor_path, "-serial", "chardev:sensor",
      "-kernel", options.image, "-append",
      "id " + std::to_string(id) + " swarm " + std::to_string(robots) +
          " hold 1 report 1 sensors 1 align " + (*options.align ? "1" : "0") + StartPoseWords(scenario.robots[id]) +
          LateJoinerWords(scenario)};
  if (options.icount_shift >= 0) {
    args.push_back("-icount");
    args.push_back("shift=" + std::to_string(options.icount_shift));
  }
  process::Command command;
  command.argv = std::move(args);
  command.search_path = true;
  command.inherit_environment = true;
  if (sched_getscheduler(0) == SCHED_FIFO) command.fifo_priority = kGuestPriority;
  const std::string log = options.out + "/qemu_" + std::to_string(id) + ".log";
  const process::Fd log_fd(open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  const int output = log_fd.valid() ? log_fd.get() : 1;
  command.descriptors = {{1, output}, {2, log_fd.valid() ? output : 2}};
  return process::Spawn(command);
}

// Writes what the socket takes now, keeps the rest (a robot that stopped
// reading must not stall the world).
void Flush(int fd, std::vector<uint8_t>& pending) {
  while (fd >= 0 && !pending.empty()) {
    const ssize_t written = send(fd, pending.data(), pending.size(), MSG_DONTWAIT);
    if (written <= 0) return;
    pending.erase(pending.begin(), pending.begin() + written);
  }
}

// --base-station: the listener, the client connected to it (one at a time)
// and the frames it has not taken yet.
struct BaseStationLink {
  static constexpr size_t kMaxPending = 64 * 1024;
  int listener = -1;
  int client = -1;
  std::vector<uint8_t> pending;
  uint8_t sequence = 0;
  int64_t frames = 0;   // ReceivedBeacon frames queued for a client
  int64_t dropped = 0;  // beacons not queued: no client, or it stopped reading

  // Takes a waiting client (non-blocking), then writes what it takes now;
  // a client that went away is closed, and the next one accepted.
  void Serve() {
    if (listener < 0) return;
    if (client < 0) {
      client = accept4(listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      pending.clear();
    }
    while (client >= 0 && !pending.empty()) {
      const ssize_t written = send(client, pending.data(), pending.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
      if (written < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
      if (written <= 0) {
        close(client);
        client = -1;
        return;
      }
      pending.erase(pending.begin(), pending.begin() + written);
    }
  }

  // One beacon heard on the air, as the base station's radio frames it.
  void Hear(std::span<const uint8_t> beacon) {
    uint8_t wire_bytes[drivers::kMaxWireBytes];
    const auto encoded = drivers::EncodeFrame(drivers::MakeReceivedBeacon(sequence, -50, beacon), wire_bytes);
    if (client < 0 || !encoded.ok() || pending.size() + encoded.value() > kMaxPending) {
      ++dropped;
      return;
    }
    ++sequence;
    ++frames;
    pending.insert(pending.end(), wire_bytes, wire_bytes + encoded.value());
  }
};

// One robot's sockets and their listeners: console, radio, sensor link.
struct RobotSockets {
  std::string console_path, radio_path, sensor_path;
  int console_listener = -1, radio_listener = -1, sensor_listener = -1;
};

// Closes a robot's three sockets.
void CloseLinks(Robot& robot) {
  for (int* fd : {&robot.console, &robot.radio, &robot.sensor}) {
    if (*fd >= 0) close(*fd);
    *fd = -1;
  }
}

// Does what the world player asks of robot `id`'s qemu at world time
// `world_ns` (docs/firmware.md, "Faults"): switching it on sends its held
// image the Start frame (its clock starts now, for what is left of the run),
// a crash kills it and closes its sockets, a pause stops it with SIGSTOP
// (its guest clock keeps running: the stall shows as a jump of its time once
// it continues, measured in FaultOutcomes) and a resume continues it. The
// player keeps the body, the lifecycle and the replay's event.
bool DoHostAction(const swarm::HostAction& action, int64_t world_ns, const Options& options, Robot& robot,
                  int& open_consoles) {
  switch (action.kind) {
    case swarm::HostAction::Kind::kSwitchOn: {
      if (robot.sensor < 0 || !robot.held) return false;
      uint8_t wire_bytes[drivers::kMaxWireBytes];
      const auto encoded =
          drivers::EncodeFrame(drivers::MakeStart(0, swarm::RemainingMs(options.seconds, world_ns)), wire_bytes);
      robot.switched_on = encoded.ok() && process::WriteAll(robot.sensor, wire_bytes, encoded.value());
      return robot.switched_on;
    }
    case swarm::HostAction::Kind::kKill:
      robot.qemu.Kill();
      if (robot.console >= 0) --open_consoles;
      CloseLinks(robot);
      robot.sensor_out.clear();
      return true;
    case swarm::HostAction::Kind::kStop:
      robot.qemu.Signal(SIGSTOP);
      robot.sensor_out.clear();  // readings it would only get, stale, after the pause
      return true;
    case swarm::HostAction::Kind::kContinue:
      robot.qemu.Signal(SIGCONT);
      return true;
  }
  return false;
}

// Host nanoseconds per world nanosecond: the mean of the running robots'
// measured clock rates (GuestClockRate), 1 before any was measured.
// Paused, crashed and not yet joined robots do not count, nor a joiner
// before its first ten beacons (its rate starts at 1 and settles over them).
double HostPerWorld(const std::vector<Robot>& swarm, const lab::sim::WorldPlayer& player) {
  double sum = 0;
  int counted = 0;
  for (uint16_t i = 0; i < swarm.size(); ++i) {
    if (!player.running(i) || swarm[i].beacon_ns.size() < 10) continue;
    sum += swarm[i].clock_rate.host_per_guest();
    ++counted;
  }
  return counted == 0 ? 1.0 : sum / counted;
}

// The end of the run on world time: paused robots continue (SIGCONT) so
// that they see their time is up and exit, and robots still held (a join
// that never came, or came too late) are killed.
void EndPausedAndHeld(std::vector<Robot>& swarm, const lab::sim::WorldPlayer& player, int& open_consoles) {
  for (uint16_t i = 0; i < swarm.size(); ++i) {
    Robot& robot = swarm[i];
    if (!robot.qemu.started() || robot.console < 0) continue;
    if (!robot.switched_on) {
      robot.qemu.Kill();
      CloseLinks(robot);
      --open_consoles;
    } else if (player.lifecycle(i) == lab::sim::Lifecycle::kPaused) {
      robot.qemu.Signal(SIGCONT);
    }
  }
}

// A running robot shows as absent until it reports (qemu starting up).
replay::Presence ReplayPresence(lab::sim::Lifecycle lifecycle, bool reporting) {
  const replay::Presence presence = lab::sim::ToPresence(lifecycle);
  return presence == replay::Presence::kRunning && !reporting ? replay::Presence::kAbsent : presence;
}

// The result of a run's last checks: the lab's metrics, the firmware's own
// figures (firmware-swarm.json) and the summary's extra words.
struct RunResult {
  bool ok = true;
  metrics::Metrics metrics;
  swarm::FirmwareMetrics report;
  std::string replay_problem;
};

metrics::CollectorConfig SwarmCollectorConfig(uint16_t robots, int64_t period_ns) {
  metrics::CollectorConfig config;
  config.robots = robots;
  config.radio_round_ns = period_ns;
  return config;
}

// One run of the emulated swarm: the robots' qemu instances and their
// links, the world they move in, the channel between them and what is
// recorded of them (metrics, replay, fault outcomes). main() calls, in
// order: OpenSockets, LaunchRobots, StartWorld, Step until Running()
// is false, Finish.
class SwarmHost {
 public:
  SwarmHost(const Options& options, const lab::scenario::Scenario& scenario);
  // The sockets and their folder go on every way out (a launch that failed too).
  ~SwarmHost() { RemoveSockets(); }
  SwarmHost(const SwarmHost&) = delete;
  SwarmHost& operator=(const SwarmHost&) = delete;

  // The socket directory, each robot's three listeners and its console log.
  bool OpenSockets();
  // One qemu per robot, joiners too, its sockets accepted, until every
  // image says it is held; false (every qemu killed) when one did not
  // connect or say so within kBootTimeoutMs.
  bool LaunchRobots();
  // The world's clock starts; the player switches on the robots present at
  // start, at one instant.
  void StartWorld();
  // Whether a console is still open and the deadline has not passed.
  bool Running() const;
  // One pass of the host loop: the world's steps due, the deliveries due,
  // every robot's links, the rounds ended.
  void Step();
  // The checks and the output files; the exit status.
  int Finish();

 private:
  bool OnHostAction(const swarm::HostAction& action, int64_t at_ns);
  bool WaitUntilHeld();
  void KillAll();
  void RemoveSockets();
  int64_t WaitForLinks();
  void AdvanceWorld(int64_t now);
  void PlayStress();
  void EndStress();
  void Deliver(int64_t now);
  void ReadSensorLink(uint16_t i);
  void ReadRadio(uint16_t i, int64_t now);
  void OnBeacon(uint16_t i, const drivers::Frame& frame, int64_t now);
  int64_t BeaconRound(const Robot& robot) const;
  int64_t DeliveryDue(const Robot& robot, int64_t round, int64_t now) const;
  void CountLateness(const Robot& robot, int64_t round);
  void ReadConsole(uint16_t i, int64_t now);
  void OnConsoleLine(uint16_t i, const std::string& line, int64_t now);
  void OnEpochLine(const swarm::EpochLine& epoch_line, int64_t now);
  void RecordRound(int64_t now);
  metrics::RobotRound RecordRobot(uint16_t i, int64_t now, std::vector<int64_t>& boundaries);
  bool ReapRobots();
  metrics::Metrics CollectMetrics(double wall_s);
  void ReadReplayBack(RunResult& result);
  void CheckEstimation(RunResult& result) const;
  void WriteMetrics(RunResult& result) const;
  void WriteBeacons(RunResult& result) const;
  void FillReport(RunResult& result) const;
  void WriteReport(RunResult& result) const;
  void PrintSummary(const RunResult& result) const;

  static constexpr int64_t kPhysicsNs = syrof::registry::kImuPeriodNs;
  // From launching the qemu instances until every image is held.
  static constexpr int kBootTimeoutMs = 30'000;
  const Options options_;
  const lab::scenario::Scenario scenario_;
  const uint16_t robots_;
  const int64_t period_ns_ = syrof::registry::kDefaultRadioRoundNs;
  std::vector<Robot> swarm_;
  std::vector<RobotSockets> sockets_;
  std::vector<std::string> paths_;
  std::string socket_dir_;
  std::string timing_;
  int64_t start_ns_ = 0;
  int64_t all_started_ns_ = 0;
  int64_t deadline_ns_ = 0;
  // Whether the robots handled the scenario's faults, and the radio faults.
  swarm::FaultOutcomes fault_outcomes_;
  const swarm::RadioFaults radio_faults_;
  // The scenario's channel (its model, loss and partitions; --loss
  // overrides the loss), drawing from the same seed stream as the lab's.
  syrof::lab::world::Channel channel_;
  // The metrics, the goal checks and the replay, as every runtime records them.
  lab::sim::RoundRecorder recorder_;
  // The world, on the host's clock from all_started_ns_.
  lab::world::World world_;
  int64_t world_ns_ = 0;       // the world's time, stepped in kPhysicsNs
  double world_clock_ns_ = 0;  // where the world's time should be now
  int64_t last_loop_ns_ = 0;
  double host_per_world_ = 1;  // this pass's HostPerWorld
  std::ofstream replay_file_;
  std::vector<replay::RobotMap> round_maps_;
  std::vector<replay::RobotFrame> frames_;
  // Every COOPERATIVE epoch start, to find the first epoch all robots started so.
  std::map<uint16_t, std::vector<uint16_t>> cooperative_starters_;
  std::optional<double> all_cooperative_s_;
  int64_t round_ = 0;
  int64_t next_round_ns_;  // on the world's time
  int64_t link_errors_ = 0;
  int64_t offered_ = 0, delivered_ = 0;
  // Without alignment: beacons that reached the host more than the latency
  // after their boundary (delivered at once), and after the next boundary
  // (too late for their round anywhere: a receiver steps them a round late).
  int64_t late_beacons_ = 0, beacons_past_their_round_ = 0;
  int open_consoles_;
  // The robots' lifecycle, the faults on world time and the join wait: the
  // lab's rules (lab::sim::WorldPlayer); the host does them to qemu.
  lab::sim::WorldPlayer player_;
  swarm::HostActions host_;
  int64_t latency_ns_;
  // By due instant: the latency is scaled by each sender's clock rate.
  std::multimap<int64_t, Delivery> in_flight_;
  BaseStationLink base_station_;  // --base-station
  // --stress: the stalls played on the qemu instances and this host, the
  // beacons it delivered late, the qemu instances' CPU quota.
  swarm::StressPlayer stress_;
  int64_t stress_late_beacons_ = 0;
  std::unique_ptr<syrof::lab::sim::CpuQuotaGroup> quota_;
  std::vector<pollfd> fds_;
  bool ended_ = false;  // EndPausedAndHeld was done
};

SwarmHost::SwarmHost(const Options& options, const lab::scenario::Scenario& scenario)
    : options_(options),
      scenario_(scenario),
      robots_(static_cast<uint16_t>(options.robots)),
      swarm_(robots_),
      sockets_(robots_),
      fault_outcomes_(robots_),
      radio_faults_(scenario_),
      channel_(scenario_.channel, robots_, lab::sim::ChannelSeed(scenario_.seed)),
      recorder_(scenario_, SwarmCollectorConfig(robots_, period_ns_)),
      world_(scenario_.arena, lab::sim::Bodies(scenario_)),
      frames_(robots_),
      next_round_ns_(period_ns_),
      open_consoles_(robots_),
      player_(scenario_, world_, recorder_.collector()),
      host_([this](const swarm::HostAction& action, int64_t at_ns) { return OnHostAction(action, at_ns); }),
      latency_ns_(static_cast<int64_t>(options.latency_ms * 1e6)),
      stress_(options.stress, int64_t{options.seconds} * 1'000'000'000, robots_) {
  if (options.icount_shift < 0) {
    for (Robot& robot : swarm_) robot.clock_rate = swarm::GuestClockRate::OnHostClock();
  }
}

bool SwarmHost::OnHostAction(const swarm::HostAction& action, int64_t at_ns) {
  const bool done = DoHostAction(action, at_ns, options_, swarm_[action.robot], open_consoles_);
  if (done && action.kind == swarm::HostAction::Kind::kSwitchOn) {
    swarm_[action.robot].switched_on_at = swarm::SwitchOn{at_ns / period_ns_, world_clock_ns_};
  }
  // Switching on the robots present at start is no join.
  const bool initial = action.kind == swarm::HostAction::Kind::kSwitchOn &&
                       scenario_.robots[action.robot].present_at_start;
  if (!initial) fault_outcomes_.OnAction(action, at_ns);
  return done;
}

bool SwarmHost::OpenSockets() {
  char socket_dir_template[] = "/tmp/syrof-swarm-XXXXXX";
  const char* socket_dir = mkdtemp(socket_dir_template);
  if (socket_dir == nullptr) {
    std::perror("syrof-firmware-swarm: mkdtemp");
    return false;
  }
  socket_dir_ = socket_dir;
  for (uint16_t i = 0; i < robots_; ++i) {
    RobotSockets& sockets = sockets_[i];
    sockets.radio_path = socket_dir_ + "/radio" + std::to_string(i);
    sockets.console_path = socket_dir_ + "/console" + std::to_string(i);
    sockets.sensor_path = socket_dir_ + "/sensor" + std::to_string(i);
    sockets.radio_listener = Listen(sockets.radio_path);
    sockets.console_listener = Listen(sockets.console_path);
    sockets.sensor_listener = Listen(sockets.sensor_path);
    paths_.push_back(sockets.radio_path);
    paths_.push_back(sockets.console_path);
    paths_.push_back(sockets.sensor_path);
    swarm_[i].log.open(options_.out + "/robot_" + std::to_string(i) + ".log");
    swarm_[i].bank =
        std::make_unique<lab::sensors::SensorBank>(scenario_.sensors, lab::sim::SensorSeed(scenario_.seed, i));
  }
  if (!options_.base_station.empty()) {
    base_station_.listener = Listen(options_.base_station);
    fcntl(base_station_.listener, F_SETFL, fcntl(base_station_.listener, F_GETFL) | O_NONBLOCK);
    paths_.push_back(options_.base_station);
  }
  return true;
}

bool SwarmHost::LaunchRobots() {
  timing_ = options_.icount_shift < 0 ? "host clock (no -icount)"
                                      : "-icount shift=" + std::to_string(options_.icount_shift);
  start_ns_ = HostNs();
  if (options_.stress.on() && options_.stress.cpu_quota_permille > 0) {
    quota_ = std::make_unique<syrof::lab::sim::CpuQuotaGroup>(options_.stress.cpu_quota_permille);
    if (!quota_->ok()) {
      std::fprintf(stderr, "syrof-firmware-swarm: --stress-cpu-quota: %s\n", quota_->error().c_str());
      return false;
    }
  }
  for (uint16_t i = 0; i < robots_; ++i) {
    Robot& robot = swarm_[i];
    const RobotSockets& sockets = sockets_[i];
    robot.qemu = LaunchQemu(options_, scenario_, i, sockets.console_path, sockets.radio_path, sockets.sensor_path);
    if (!robot.qemu.started()) {
      std::fprintf(stderr, "syrof-firmware-swarm: cannot start robot %u's qemu %s: %s\n", static_cast<unsigned>(i),
                   options_.qemu.c_str(), std::strerror(robot.qemu.start_error()));
      KillAll();
      return false;
    }
    if (quota_ && !quota_->Add(robot.qemu.pid())) {
      std::fprintf(stderr, "syrof-firmware-swarm: robot %u's qemu could not join %s\n", static_cast<unsigned>(i),
                   quota_->path().c_str());
    }
    // qemu connects to its chardevs in order while starting up.
    robot.console = AcceptOne(sockets.console_listener, kBootTimeoutMs, "robot " + std::to_string(i) + "'s console");
    robot.radio = AcceptOne(sockets.radio_listener, kBootTimeoutMs, "robot " + std::to_string(i) + "'s radio");
    robot.sensor =
        AcceptOne(sockets.sensor_listener, kBootTimeoutMs, "robot " + std::to_string(i) + "'s sensor link");
    if (robot.console < 0 || robot.radio < 0 || robot.sensor < 0) {
      KillAll();
      return false;
    }
  }
  if (!WaitUntilHeld()) {
    KillAll();
    return false;
  }
  return true;
}

// Reads the consoles until every image has printed `held` (its robot built,
// its clock not started).
bool SwarmHost::WaitUntilHeld() {
  const int64_t give_up_ns = HostNs() + int64_t{kBootTimeoutMs} * 1'000'000;
  for (;;) {
    const auto held = std::count_if(swarm_.begin(), swarm_.end(), [](const Robot& robot) { return robot.held; });
    if (held == robots_) return true;
    const int64_t now = WaitForLinks();
    if (now > give_up_ns) break;
    for (uint16_t i = 0; i < robots_; ++i) ReadConsole(i, now);
  }
  for (uint16_t i = 0; i < robots_; ++i) {
    if (!swarm_[i].held) {
      std::fprintf(stderr, "syrof-firmware-swarm: robot %u's image did not say `held` within %d s (robot_%u.log)\n",
                   static_cast<unsigned>(i), kBootTimeoutMs / 1000, static_cast<unsigned>(i));
    }
  }
  return false;
}

void SwarmHost::KillAll() {
  for (Robot& robot : swarm_) robot.qemu.Kill();
}

void SwarmHost::RemoveSockets() {
  for (const std::string& path : paths_) unlink(path.c_str());
  paths_.clear();
  if (!socket_dir_.empty()) rmdir(socket_dir_.c_str());
  socket_dir_.clear();
}

void SwarmHost::StartWorld() {
  replay_file_.open(options_.out + "/replay", std::ios::binary);
  recorder_.OpenReplay(replay_file_);
  all_started_ns_ = HostNs();
  // With -icount a loaded host stretches the guests' time (1.3x for 4
  // robots on 2 busy cores, more for 8): three times the run, then give up.
  deadline_ns_ = all_started_ns_ + (3 * options_.seconds + 30) * int64_t{1'000'000'000};
  base_station_.Serve();  // a base station already waiting hears the first beacons too
  player_.StartPresentRobots(host_);
}

bool SwarmHost::Running() const { return open_consoles_ > 0 && HostNs() < deadline_ns_; }

void SwarmHost::Step() {
  if (!ended_ && world_ns_ >= int64_t{options_.seconds} * 1'000'000'000) {
    EndPausedAndHeld(swarm_, player_, open_consoles_);
    EndStress();
    ended_ = true;
  }
  const int64_t now = WaitForLinks();
  AdvanceWorld(now);
  PlayStress();
  for (Robot& robot : swarm_) Flush(robot.sensor, robot.sensor_out);
  Deliver(now);
  for (uint16_t i = 0; i < robots_; ++i) {
    ReadSensorLink(i);
    ReadRadio(i, now);
    ReadConsole(i, now);
  }
  base_station_.Serve();
  // Round ends on the host's clock: every robot's latest report.
  while (world_ns_ >= next_round_ns_) RecordRound(now);
}

// Polls every robot's links until one has input, the next delivery is due
// or half a physics step passed (at most 10 ms); returns the host time after.
int64_t SwarmHost::WaitForLinks() {
  fds_.clear();
  for (const Robot& robot : swarm_) {
    fds_.push_back({robot.radio, POLLIN, 0});
    fds_.push_back({robot.console, POLLIN, 0});
    fds_.push_back({robot.sensor, POLLIN, 0});
  }
  const int64_t now_before = HostNs();
  int64_t next_event_ns = now_before + kPhysicsNs / 2;
  if (!in_flight_.empty()) next_event_ns = std::min(next_event_ns, in_flight_.begin()->first);
  const int wait_ms = static_cast<int>(std::max<int64_t>(0, (next_event_ns - now_before) / 1'000'000));
  poll(fds_.data(), fds_.size(), std::min(wait_ms, 10));
  return HostNs();
}

void SwarmHost::AdvanceWorld(int64_t now) {
  // The world follows the host's clock slowed to the robots' mean clock
  // rate (GuestClockRate, from the times they print; exactly 1 on the
  // host's clock), so a robot gets a second of readings per second of its
  // own time (docs/firmware.md, "How readings are timed").
  host_per_world_ = HostPerWorld(swarm_, player_);
  world_clock_ns_ += static_cast<double>(now - (last_loop_ns_ == 0 ? all_started_ns_ : last_loop_ns_)) / host_per_world_;
  last_loop_ns_ = now;
  // The world's steps due by now: bodies, contacts, then each robot's
  // readings due at the step's instant, framed to its sensor link.
  while (static_cast<double>(world_ns_ + kPhysicsNs) <= world_clock_ns_) {
    world_ns_ += kPhysicsNs;
    player_.PlayFaults(world_ns_, host_);
    world_.Step(world_ns_, static_cast<double>(kPhysicsNs) * 1e-9);
    player_.TakeContacts(host_);
    for (uint16_t i = 0; i < robots_; ++i) {
      Robot& robot = swarm_[i];
      if (robot.sensor < 0 || !player_.running(i)) continue;
      robot.bank->Sample(world_ns_, world_.true_state(i), robot.feed);
      robot.sensor_out.insert(robot.sensor_out.end(), robot.feed.bytes().begin(), robot.feed.bytes().end());
      robot.feed.clear();
    }
  }
}

// --stress: the stalls due by the world's time (stress_player.h). The host
// is one thread, so a world stall is this host sleeping for its length.
void SwarmHost::PlayStress() {
  if (ended_) return;
  const int64_t world_stall_ns = stress_.Play(
      world_ns_, [this](uint16_t i) { return player_.running(i) && swarm_[i].switched_on && swarm_[i].qemu.started(); },
      [this](uint16_t i, bool stop) { swarm_[i].qemu.Signal(stop ? SIGSTOP : SIGCONT); });
  if (world_stall_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(world_stall_ns));
}

// No qemu stays stopped by the stress past the run's end.
void SwarmHost::EndStress() {
  stress_.EndAll([this](uint16_t i) { return player_.running(i) && swarm_[i].qemu.started(); },
                 [this](uint16_t i, bool stop) { swarm_[i].qemu.Signal(stop ? SIGSTOP : SIGCONT); });
}

void SwarmHost::Deliver(int64_t now) {
  while (!in_flight_.empty() && in_flight_.begin()->first <= now) {
    const Delivery& delivery = in_flight_.begin()->second;
    if (swarm_[delivery.to].radio >= 0 && player_.running(delivery.to)) {
      (void)process::WriteAll(swarm_[delivery.to].radio, delivery.bytes.data(), delivery.bytes.size());
    }
    in_flight_.erase(in_flight_.begin());
  }
}

void SwarmHost::ReadSensorLink(uint16_t i) {
  Robot& robot = swarm_[i];
  if (robot.sensor < 0 || (fds_[3 * i + 2].revents & (POLLIN | POLLHUP)) == 0) return;
  uint8_t buffer[4096];
  const ssize_t count = read(robot.sensor, buffer, sizeof buffer);
  if (count <= 0) {
    close(robot.sensor);
    robot.sensor = -1;
  }
  for (ssize_t k = 0; k < count; ++k) {
    if (auto drive = robot.feed.PushFromRobot(buffer[k], world_ns_)) world_.SetDrive(i, *drive);
  }
}

void SwarmHost::ReadRadio(uint16_t i, int64_t now) {
  Robot& robot = swarm_[i];
  if (robot.radio < 0 || (fds_[3 * i].revents & (POLLIN | POLLHUP)) == 0) return;
  uint8_t buffer[4096];
  const ssize_t count = read(robot.radio, buffer, sizeof buffer);
  if (count <= 0) {
    close(robot.radio);
    robot.radio = -1;
  }
  for (ssize_t k = 0; k < count; ++k) {
    const drivers::DecodeEvent event = robot.decoder.Push(buffer[k]);
    if (event == drivers::DecodeEvent::kError) ++link_errors_;
    if (event != drivers::DecodeEvent::kFrame) continue;
    const drivers::Frame& frame = robot.decoder.frame();
    if (frame.kind != drivers::FrameKind::kSendBeacon) continue;
    OnBeacon(i, frame, now);
  }
}

// Robot `i`'s SendBeacon frame, read at host time `now`: a ReceivedBeacon
// frame in flight to each robot the channel delivers it to.
// The world round a beacon of `robot` reaching the host now was sent in
// (world_grid.h). A robot whose round alignment moved its boundaries
// earlier (--align 1) may be counted a round short.
int64_t SwarmHost::BeaconRound(const Robot& robot) const {
  return swarm::BeaconRound(robot.switched_on_at, world_clock_ns_, period_ns_);
}

// Host time at which a beacon of `robot` (of world round `round`, read now)
// reaches the others. With the robots on the world's grid (no alignment):
// --latency-ms after the sender's boundary on the world's clock, as the
// lab's radio delivers, and at once when that instant has passed. With
// round alignment the boundaries move: --latency-ms of the sender's clock
// after the beacon reached the host.
int64_t SwarmHost::DeliveryDue(const Robot& robot, int64_t round, int64_t now) const {
  if (*options_.align) return now + robot.clock_rate.ToHost(latency_ns_);
  const double boundary_ns = swarm::BoundaryOf(robot.switched_on_at, round, period_ns_);
  const double ahead_ns = (boundary_ns + static_cast<double>(latency_ns_) - world_clock_ns_) * host_per_world_;
  return now + std::max<int64_t>(0, std::llround(ahead_ns));
}

void SwarmHost::CountLateness(const Robot& robot, int64_t round) {
  if (*options_.align) return;
  const double late_ns = world_clock_ns_ - swarm::BoundaryOf(robot.switched_on_at, round, period_ns_);
  if (late_ns > static_cast<double>(latency_ns_)) ++late_beacons_;
  if (late_ns > static_cast<double>(period_ns_)) ++beacons_past_their_round_;
}

void SwarmHost::OnBeacon(uint16_t i, const drivers::Frame& frame, int64_t now) {
  Robot& robot = swarm_[i];
  robot.beacon_ns.push_back(now);
  robot.last_boundary_ns = now;
  if (base_station_.listener >= 0) {
    base_station_.Hear(std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length));
  }
  const int64_t beacon_round = BeaconRound(robot);
  const int64_t due_ns = DeliveryDue(robot, beacon_round, now);
  CountLateness(robot, beacon_round);
  // The lab and the DDS world ask the channel about the same (round,
  // sender, receiver), at the round's start.
  const double sent_s = static_cast<double>(beacon_round * period_ns_) * 1e-9;
  for (uint16_t to = 0; to < robots_; ++to) {
    // Paused, crashed and absent robots hear nothing (the lab's Listening).
    if (to == i || swarm_[to].radio < 0 || !player_.running(to)) continue;
    ++offered_;
    // Partitions, deaf and mute are on world time, as the lab's.
    if (!channel_.Delivers(i, to, beacon_round, sent_s) || radio_faults_.Blocked(i, to, sent_s)) continue;
    ++delivered_;
    uint8_t wire_bytes[drivers::kMaxWireBytes];
    const auto encoded = drivers::EncodeFrame(
        drivers::MakeReceivedBeacon(frame.sequence, -60,
                                    std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length)),
        wire_bytes);
    // --stress: this link's beacon late by a seeded 10-200 ms (lab/sim/stress.h).
    const int64_t late_ns =
        lab::sim::SampleDelayNs(options_.stress, lab::sim::DelayedStream::kBeacon, i, to, beacon_round);
    stress_late_beacons_ += late_ns > 0 ? 1 : 0;
    if (encoded.ok()) {
      in_flight_.emplace(due_ns + late_ns,
                         Delivery{due_ns + late_ns, to, std::vector<uint8_t>(wire_bytes, wire_bytes + encoded.value())});
    }
  }
}

void SwarmHost::ReadConsole(uint16_t i, int64_t now) {
  Robot& robot = swarm_[i];
  if (robot.console < 0 || (fds_[3 * i + 1].revents & (POLLIN | POLLHUP)) == 0) return;
  uint8_t buffer[4096];
  const ssize_t count = read(robot.console, buffer, sizeof buffer);
  if (count <= 0) {
    close(robot.console);
    robot.console = -1;
    --open_consoles_;
    return;
  }
  robot.pending_line.append(reinterpret_cast<const char*>(buffer), static_cast<size_t>(count));
  size_t newline;
  while ((newline = robot.pending_line.find('\n')) != std::string::npos) {
    const std::string line = robot.pending_line.substr(0, newline);
    robot.pending_line.erase(0, newline + 1);
    OnConsoleLine(i, line, now);
  }
}

void SwarmHost::OnConsoleLine(uint16_t i, const std::string& line, int64_t now) {
  Robot& robot = swarm_[i];
  robot.log << line << '\n';
  ++robot.lines;
  if (line.rfind("status ", 0) == 0) robot.last_status = line;
  if (line.rfind("held ", 0) == 0) robot.held = true;
  const swarm::ConsoleLine parsed = swarm::ParseConsoleLine(line, robots_);
  if (const auto* error = std::get_if<swarm::LineError>(&parsed)) {
    ++robot.bad_lines;
    std::fprintf(stderr, "robot %u console, column %zu: %s\n  %s\n", static_cast<unsigned>(i), error->column,
                 error->what.c_str(), line.c_str());
  } else if (const auto* round_line = std::get_if<swarm::RoundLine>(&parsed)) {
    robot.latest = *round_line;
    robot.latest_ns = now;
    robot.clock_rate.OnGuestTime(now, round_line->t_ms * 1'000'000);
    fault_outcomes_.OnRoundLine(*round_line, world_ns_);
  } else if (const auto* epoch_line = std::get_if<swarm::EpochLine>(&parsed)) {
    OnEpochLine(*epoch_line, now);
  }
}

void SwarmHost::OnEpochLine(const swarm::EpochLine& epoch_line, int64_t now) {
  recorder_.OnEpochStart(epoch_line.robot, round_, world_ns_, epoch_line.map);
  fault_outcomes_.OnEpochLine(epoch_line, world_ns_);
  player_.events().push_back(replay::Event{replay::EventKind::kEpochStart, epoch_line.robot, replay::kNoRobot,
                                           epoch_line.map.epoch, static_cast<uint8_t>(epoch_line.map.mode),
                                           world_ns_});
  if (std::none_of(round_maps_.begin(), round_maps_.end(),
                   [&](const replay::RobotMap& entry) { return entry.robot == epoch_line.robot; })) {
    round_maps_.push_back(replay::RobotMap{epoch_line.robot, lab::sim::ToEpochMap(epoch_line.map)});
  }
  if (epoch_line.map.mode == syrof::wire::Mode::kCooperative) {
    std::vector<uint16_t>& starters = cooperative_starters_[epoch_line.map.epoch];
    starters.push_back(epoch_line.robot);
    if (starters.size() == robots_ && !all_cooperative_s_) {
      all_cooperative_s_ = static_cast<double>(now - all_started_ns_) * 1e-9;
    }
  }
}

// The round ending at next_round_ns_ on the world's time, from every
// robot's latest report at host time `now`, to the recorder: metrics, the
// goal, the replay (its events in time order, none after the round's end);
// the events and maps start over.
void SwarmHost::RecordRound(int64_t now) {
  std::vector<metrics::RobotRound> rounds(robots_);
  std::vector<int64_t> boundaries;
  for (uint16_t i = 0; i < robots_; ++i) rounds[i] = RecordRobot(i, now, boundaries);
  const int64_t end_ns = (round_ + 1) * period_ns_;
  std::vector<replay::Event>& events = player_.events();
  lab::sim::OrderByTime(events);
  for (replay::Event& event : events) event.time_ns = std::min(event.time_ns, end_ns);
  recorder_.RecordRound(lab::sim::RecordedRound{round_, end_ns, rounds, boundaries, frames_, events, round_maps_,
                                                [this] { return player_.RunningPoses(); }});
  events.clear();
  round_maps_.clear();
  ++round_;
  next_round_ns_ += period_ns_;
}

// Robot `i`'s part of the round: its metrics entry (returned), its replay
// frame (frames_[i]) and its round boundary, if it is a member.
metrics::RobotRound SwarmHost::RecordRobot(uint16_t i, int64_t now, std::vector<int64_t>& boundaries) {
  const Robot& robot = swarm_[i];
  metrics::RobotRound entry;
  entry.id = i;
  const lab::sim::Lifecycle presence = player_.lifecycle(i);
  entry.running = presence == lab::sim::Lifecycle::kRunning && robot.latest.has_value() &&
                  static_cast<double>(now - robot.latest_ns) < 3 * static_cast<double>(period_ns_) * host_per_world_;
  entry.paused = presence == lab::sim::Lifecycle::kPaused;
  if (robot.latest) {
    entry.sync_member = robot.latest->member;
    entry.member = entry.running && robot.latest->member;
    entry.epoch = robot.latest->epoch;
    entry.epoch_mode = robot.latest->mode;
    entry.phase = robot.latest->phase;
    // Scored once the filter had its warm-up after the world started.
    entry.estimate_valid =
        entry.running && robot.latest->estimate_valid && (round_ + 1) * period_ns_ >= player_.scored_from_ns(i);
    entry.est_x_m = robot.latest->x_m;
    entry.est_y_m = robot.latest->y_m;
  }
  const lab::world::BodyState& body = world_.state(i);
  entry.true_x_m = body.x_m;
  entry.true_y_m = body.y_m;
  replay::RobotFrame& frame = frames_[i];
  frame.id = i;
  frame.presence = ReplayPresence(presence, entry.running);
  frame.status = entry.sync_member ? 0 : 1;
  frame.phase = static_cast<uint8_t>(entry.phase);
  frame.mode = static_cast<uint8_t>(entry.epoch_mode);
  frame.epoch = entry.epoch;
  frame.true_x_m = static_cast<float>(body.x_m);
  frame.true_y_m = static_cast<float>(body.y_m);
  frame.true_heading_rad = static_cast<float>(body.heading_rad);
  // The report line has no heading: the replay shows the true one.
  frame.est_x_m = static_cast<float>(entry.est_x_m);
  frame.est_y_m = static_cast<float>(entry.est_y_m);
  frame.est_heading_rad = frame.true_heading_rad;
  if (entry.member && robot.last_boundary_ns > 0) boundaries.push_back(robot.last_boundary_ns - all_started_ns_);
  return entry;
}

int SwarmHost::Finish() {
  RunResult result;
  EndStress();
  result.ok = ReapRobots();
  std::vector<lab::sim::Lifecycle> final_presence;
  for (uint16_t i = 0; i < robots_; ++i) final_presence.push_back(player_.lifecycle(i));
  result.report.faults = fault_outcomes_.Finish(final_presence);
  for (const swarm::FaultOutcome& outcome : result.report.faults) {
    if (options_.expect_faults && !outcome.ok) result.ok = false;
  }
  RemoveSockets();
  if (base_station_.listener >= 0) {
    base_station_.Serve();
    if (base_station_.client >= 0) close(base_station_.client);
    close(base_station_.listener);
    std::fprintf(stderr, "syrof-firmware-swarm: base station: %lld beacons sent to %s, %lld not (no client, or it lagged)\n",
                 static_cast<long long>(base_station_.frames), options_.base_station.c_str(),
                 static_cast<long long>(base_station_.dropped));
  }
  result.report.wall_seconds = static_cast<double>(HostNs() - start_ns_) * 1e-9;
  result.metrics = CollectMetrics(result.report.wall_seconds);
  ReadReplayBack(result);
  CheckEstimation(result);
  WriteMetrics(result);
  WriteBeacons(result);
  if (options_.expect_cooperative && !all_cooperative_s_) result.ok = false;
  if (result.metrics.common_knowledge.violations != 0) result.ok = false;
  FillReport(result);
  WriteReport(result);
  PrintSummary(result);
  if (!result.ok && options_.stress.on()) {
    std::fprintf(stderr, "syrof-firmware-swarm: failed under stress seed %llu: rerun with  %s\n",
                 static_cast<unsigned long long>(options_.stress.seed), options_.command_line.c_str());
  }
  return result.ok ? 0 : 1;
}

// Waits for every qemu (killing one still running at the deadline) and
// keeps its exit status; false when one never started, ran past the
// deadline, exited badly or never reported, or printed a bad line.
bool SwarmHost::ReapRobots() {
  bool ok = true;
  for (uint16_t i = 0; i < robots_; ++i) {
    Robot& robot = swarm_[i];
    if (!robot.qemu.started()) continue;  // never launched: LaunchRobots failed
    // A crashed robot was killed (exit 137), perhaps before it reported or
    // even before it was switched on (a crash while waiting to join).
    const bool crashed = player_.lifecycle(i) == lab::sim::Lifecycle::kCrashed;
    if (robot.console >= 0 || robot.radio >= 0) {  // the deadline passed
      robot.qemu.Kill();
      ok = false;
      std::fprintf(stderr, "robot %u: still running at the deadline\n", static_cast<unsigned>(i));
    }
    if (!robot.switched_on && !crashed) {  // a joiner whose time never came: killed at the end
      ok = false;
      std::fprintf(stderr, "robot %u: never switched on\n", static_cast<unsigned>(i));
    }
    const process::ExitStatus status = robot.qemu.Reap();
    robot.exit_status = status.exited() ? status.code : status.signaled() ? 128 + status.signal : -1;
    if (robot.switched_on && !crashed && (robot.exit_status != 0 || !robot.latest)) ok = false;
    if (robot.bad_lines > 0) ok = false;
  }
  return ok;
}

metrics::Metrics SwarmHost::CollectMetrics(double wall_s) {
  // The image runs its compiled-in app (builtin:circle unless built with APP=).
  // The goal over the robots running at the end, as in every runtime (a
  // crashed or never-started robot used to count, and kept the goal from
  // being met).
  const lab::sim::RunEnd end{static_cast<double>(round_) * static_cast<double>(period_ns_) * 1e-9, wall_s, round_};
  metrics::Metrics result = recorder_.Finish(recorder_.Facts(end, player_, world_));
  // The robots' consoles do not carry the app's returns, so agreement stays
  // unset: metrics.json says null, not a measurement of nothing.
  result.runtime = "firmware";
  return result;
}

// The replay, then read back as the viewer reads it.
void SwarmHost::ReadReplayBack(RunResult& result) {
  recorder_.FinishReplay();
  replay_file_.close();
  {
    std::ifstream in(options_.out + "/replay", std::ios::binary);
    replay::Reader reader(in);
    replay::Header header;
    replay::Round replay_round;
    if (reader.ReadHeader(header)) {
      while (reader.Next(replay_round)) ++result.report.replay_rounds;
    }
    if (!reader.complete()) result.replay_problem = reader.error().ToString();
  }
  if (!result.replay_problem.empty() || result.report.replay_rounds != round_) {
    std::fprintf(stderr, "syrof-firmware-swarm: %s/replay does not read back (%lld of %lld rounds): %s\n",
                 options_.out.c_str(), static_cast<long long>(result.report.replay_rounds), static_cast<long long>(round_),
                 result.replay_problem.c_str());
    result.ok = false;
  }
}

void SwarmHost::CheckEstimation(RunResult& result) const {
  const std::optional<double> max_error_m = result.metrics.estimation.max_error_m;
  if (options_.max_estimation_error_m &&
      (!max_error_m || result.metrics.estimation.samples == 0 || *max_error_m > *options_.max_estimation_error_m)) {
    std::fprintf(stderr, "syrof-firmware-swarm: largest estimation error %s m over %lld samples, above --max-estimation-error %g\n",
                 max_error_m ? std::to_string(*max_error_m).c_str() : "(none)",
                 static_cast<long long>(result.metrics.estimation.samples), *options_.max_estimation_error_m);
    result.ok = false;
  }
}

void SwarmHost::WriteMetrics(RunResult& result) const {
  std::ofstream metrics_file(options_.out + "/metrics.json");
  metrics_file << metrics::ToJson(result.metrics);
  if (!metrics_file.flush()) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot write %s/metrics.json\n", options_.out.c_str());
    result.ok = false;
  }
}

// beacons.csv, and the round-start skew from the same instants.
void SwarmHost::WriteBeacons(RunResult& result) const {
  std::vector<std::vector<int64_t>> beacon_times;
  std::ofstream beacons_csv(options_.out + "/beacons.csv");
  beacons_csv << "robot,host_ms\n";
  for (uint16_t i = 0; i < robots_; ++i) {
    beacon_times.push_back(swarm_[i].beacon_ns);
    for (const int64_t t : swarm_[i].beacon_ns) beacons_csv << i << ',' << static_cast<double>(t - all_started_ns_) * 1e-6 << '\n';
  }
  // Skew from 5 s on: the start-up (instances boot one after another) and
  // the round alignment's first corrections are left out.
  result.report.round_start_skew = swarm::RoundStartSkew(beacon_times, period_ns_, all_started_ns_ + 5'000'000'000);
}

// The firmware's own figures of the run, as measured, beside those the
// earlier steps put in (wall time, faults, replay rounds, skew).
void SwarmHost::FillReport(RunResult& result) const {
  swarm::FirmwareMetrics& report = result.report;
  const metrics::Metrics& run = result.metrics;
  report.robots = robots_;
  report.seconds = options_.seconds;
  report.loss = options_.loss;
  report.seed = options_.seed;
  report.align = *options_.align;
  report.latency_ms = options_.latency_ms;
  report.timing = timing_;
  report.all_cooperative_s = all_cooperative_s_;
  report.p3_violations = run.common_knowledge.violations;
  report.cooperative_starts = run.common_knowledge.cooperative_starts;
  report.beacons = swarm::BeaconCounts{offered_, delivered_, link_errors_, late_beacons_, beacons_past_their_round_};
  for (const Robot& robot : swarm_) {
    report.sensor_link.imu += robot.feed.counters().imu;
    report.sensor_link.flow += robot.feed.counters().flow;
    report.sensor_link.uwb += robot.feed.counters().uwb;
    report.sensor_link.not_encoded += robot.feed.counters().not_encoded;
    report.sensor_link.drives += robot.feed.counters().drives;
    report.sensor_link.rejected_from_robots += robot.feed.link_counters().rejected;
    report.exit_statuses.push_back(robot.exit_status);
  }
  report.scenario = scenario_.name;
  report.estimation = swarm::EstimationFigures{run.estimation.samples, run.estimation.position_rmse_m,
                                               run.estimation.max_error_m};
  report.partitioned_beacons = channel_.partitioned();
  if (options_.stress.on()) {
    report.stress = swarm::StressFigures{options_.stress.seed,          options_.stress.stalls_per_second,
                                         stress_.robot_stalls(),        stress_.world_stalls(),
                                         options_.stress.delayed_fraction, stress_late_beacons_,
                                         options_.stress.cpu_quota_permille};
  }
}

void SwarmHost::WriteReport(RunResult& result) const {
  std::ofstream file(options_.out + "/firmware-swarm.json");
  file << swarm::ToJson(result.report);
  if (!file.flush()) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot write %s/firmware-swarm.json\n", options_.out.c_str());
    result.ok = false;
  }
}

void SwarmHost::PrintSummary(const RunResult& result) const {
  const metrics::Metrics& run = result.metrics;
  const swarm::SkewStats& skew = result.report.round_start_skew;
  const swarm::SensorLinkCounts& sensor_totals = result.report.sensor_link;
  const std::optional<double> max_error_m = run.estimation.max_error_m;
  const bool cooperative = all_cooperative_s_.has_value();
  std::printf("firmware swarm: %u robots, %d s, loss %.2f, seed %llu, timing %s, wall %.1f s\n",
              static_cast<unsigned>(robots_), options_.seconds, options_.loss,
              static_cast<unsigned long long>(options_.seed), timing_.c_str(), result.report.wall_seconds);
  std::printf("  all robots COOPERATIVE in one epoch: %s; COOPERATIVE starts %lld; P3 violations %lld\n",
              cooperative ? ("at " + std::to_string(*all_cooperative_s_) + " s").c_str() : "never",
              static_cast<long long>(run.common_knowledge.cooperative_starts),
              static_cast<long long>(run.common_knowledge.violations));
  std::printf("  round-start skew (beacon arrivals vs robot 0, after 5 s): median %.3f ms, p95 %.3f ms, max %.3f ms "
              "over %lld beacons\n",
              skew.median_ns * 1e-6, skew.p95_ns * 1e-6, skew.max_ns * 1e-6, static_cast<long long>(skew.samples));
  std::printf("  beacons offered %lld, delivered %lld; radio-link errors %lld; %lld beacons reached the host past "
              "their delivery instant, %lld past their round\n",
              static_cast<long long>(offered_), static_cast<long long>(delivered_),
              static_cast<long long>(link_errors_), static_cast<long long>(late_beacons_),
              static_cast<long long>(beacons_past_their_round_));
  std::printf("  scenario %s; sensor link: %lld IMU, %lld flow, %lld UWB frames sent, %lld drive commands back\n",
              scenario_.name.c_str(), static_cast<long long>(sensor_totals.imu),
              static_cast<long long>(sensor_totals.flow), static_cast<long long>(sensor_totals.uwb),
              static_cast<long long>(sensor_totals.drives));
  std::printf("  estimation error over %lld samples: RMSE %s m, max %s m; collisions %lld; goal %s (%s)\n",
              static_cast<long long>(run.estimation.samples),
              run.estimation.position_rmse_m ? std::to_string(*run.estimation.position_rmse_m).c_str() : "-",
              max_error_m ? std::to_string(*max_error_m).c_str() : "-",
              static_cast<long long>(run.collisions.count), run.goal.reached ? "reached" : "not reached",
              run.goal.detail.c_str());
  std::printf("  %s/replay: %lld rounds%s\n", options_.out.c_str(), static_cast<long long>(result.report.replay_rounds),
              result.replay_problem.empty() ? "" : (", " + result.replay_problem).c_str());
  if (options_.stress.on()) {
    std::printf("  stress seed %llu: %lld qemu stalls, %lld host stalls, %lld beacons late%s (rerun: --stress %llu)\n",
                static_cast<unsigned long long>(options_.stress.seed), static_cast<long long>(stress_.robot_stalls()),
                static_cast<long long>(stress_.world_stalls()), static_cast<long long>(stress_late_beacons_),
                quota_ ? (", qemu at " + std::to_string(options_.stress.cpu_quota_permille) + " per mille of a core").c_str() : "",
                static_cast<unsigned long long>(options_.stress.seed));
  }
  for (uint16_t i = 0; i < robots_; ++i) {
    std::printf("  robot %u: exit %d, %s\n", static_cast<unsigned>(i), swarm_[i].exit_status,
                swarm_[i].last_status.c_str());
  }
  for (const swarm::FaultOutcome& outcome : result.report.faults) {
    std::printf("  fault: %s: %s\n", outcome.ok ? "ok" : (options_.expect_faults ? "FAILED" : "not seen"),
                outcome.detail.c_str());
  }
  std::printf("  %s/metrics.json, %s/firmware-swarm.json: %s\n", options_.out.c_str(), options_.out.c_str(),
              result.ok ? "ok" : "FAILED");
}

int main(int argc, char** argv) {
  const Options parsed_options = ParseOptions(argc, argv);
  const lab::scenario::Scenario scenario = LoadScenario(parsed_options);
  Options options = parsed_options;
  for (int i = 0; i < argc; ++i) options.command_line += (i == 0 ? "" : " ") + std::string(argv[i]);
  options.robots = static_cast<int>(scenario.robots.size());
  options.seed = scenario.seed;
  options.loss = scenario.channel.loss;
  signal(SIGPIPE, SIG_IGN);
  if (options.realtime) SetRealtime();
  std::error_code made;
  std::filesystem::create_directories(options.out, made);
  if (made || !std::filesystem::is_directory(options.out)) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot make the output directory %s: %s\n", options.out.c_str(),
                 made.message().c_str());
    return 1;
  }
  SwarmHost host(options, scenario);
  if (!host.OpenSockets() || !host.LaunchRobots()) return 1;
  host.StartWorld();
  while (host.Running()) host.Step();
  return host.Finish();
}
