#include "syrof/firmware/swarm/qemu_launcher.h"

#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "syrof/firmware/config/robot_config.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/firmware/robot/boot_words.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/process/fd.h"

namespace syrof::firmware::swarm {

namespace {

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

// The scenario's activation as the image's words (boot_words.h); exits 2
// naming the field when its script is longer than the image holds.
std::string ActivationWords(const lab::scenario::Scenario& scenario) {
  const sync::ActivationConfig activation = lab::sim::ActivationConfigFor(scenario);
  std::vector<char> text(16 * robot::kMaxBootLineBytes);
  size_t length = 0;
  switch (robot::FormatActivationWords(activation, text, length)) {
    case robot::BootWordsError::kOk: return std::string(text.data(), length);
    case robot::BootWordsError::kTooManyScripted:
      Usage("--scenario: activation.active lists " + std::to_string(activation.script.size()) +
            " (epoch, robot) pairs; the robot image holds at most " +
            std::to_string(robot::kMaxBootScriptedActivations));
    case robot::BootWordsError::kTooManyCycles:
      Usage("--scenario: activation.cycles lists " + std::to_string(activation.cycles.size()) +
            " cycles; the robot image holds at most " + std::to_string(robot::kMaxBootScriptedCycles));
    case robot::BootWordsError::kRobotOutOfRange:
    case robot::BootWordsError::kInvalid:
    case robot::BootWordsError::kBufferTooSmall:
    case robot::BootWordsError::kTooManyInputs:
    case robot::BootWordsError::kNoSuchKind:
      break;
  }
  Usage("--scenario: activation: the robot image cannot be told this schedule (docs/firmware.md, \"Activation\")");
}

// Robot `id`'s own private inputs (the scenario's `inputs:`, its value of
// each, never another robot's) as the image's words (boot_words.h); exits 2
// naming the field when the image cannot be told them.
std::string InputWords(const lab::scenario::Scenario& scenario, uint16_t id) {
  if (scenario.inputs.size() > robot::kMaxBootInputs) {
    Usage("--scenario: inputs: " + std::to_string(scenario.inputs.size()) +
          " private inputs; the robot image holds at most " + std::to_string(robot::kMaxBootInputs));
  }
  std::vector<app::Parameter> own;
  for (const auto& [name, values] : scenario.inputs) {
    if (id >= values.size()) {
      Usage("--scenario: inputs." + name + " gives " + std::to_string(values.size()) + " values; robot " +
            std::to_string(id) + " has none");
    }
    if (!std::isfinite(values[id])) {
      Usage("--scenario: inputs." + name + ": robot " + std::to_string(id) + "'s value is not a finite number");
    }
    own.push_back(app::Parameter{name, values[id]});
  }
  std::vector<char> text(16 * robot::kMaxBootLineBytes);
  size_t length = 0;
  if (robot::FormatInputWords(id, own, text, length) == robot::BootWordsError::kOk) {
    return std::string(text.data(), length);
  }
  Usage("--scenario: inputs: the robot image cannot be told robot " + std::to_string(id) +
        "'s inputs (a name of at most " + std::to_string(robot::kMaxBootInputNameBytes) +
        " bytes, a letter or _ then letters, digits and _; docs/firmware.md, \"Private inputs\")");
}

// Robot `id`'s kind, its swarm's kinds and, in a mixed swarm, every robot's
// kind as the image's words (boot_words.h): none for an omni robot among
// omni robots, as before.
std::string KindWords(const lab::scenario::Scenario& scenario, uint16_t id) {
  robot::KindSet swarm = 0;
  std::vector<motion::RobotKind> members;
  for (const lab::scenario::RobotSpec& spec : scenario.robots) {
    swarm |= robot::KindBit(spec.kind);
    members.push_back(spec.kind);
  }
  char text[96];
  size_t length = 0;
  if (robot::FormatKindWords(scenario.robots[id].kind, swarm, members, text, length) != robot::BootWordsError::kOk) {
    Usage("--scenario: robot " + std::to_string(id) + "'s kind cannot be told the robot image");
  }
  return std::string(text, length);
}

}  // namespace

std::string ImageAppend(const Options& options, const lab::scenario::Scenario& scenario, uint16_t id) {
  const auto robots = static_cast<uint16_t>(scenario.robots.size());
  // Who the robot is: on the line only when asked (--config-on-boot-line);
  // else its own image's configuration block says it (WriteRobotImages).
  const std::string who = options.config_on_boot_line
                              ? "id " + std::to_string(id) + " swarm " + std::to_string(robots) + " "
                              : std::string();
  const std::string drive = "hold 1 report 1 sensors 1 align " + std::string(options.align.value_or(true) ? "1" : "0") +
                            StartPoseWords(scenario.robots[id]) + LateJoinerWords(scenario);
  if (!options.config_on_boot_line) return drive + ActivationWords(scenario);
  return who + drive + KindWords(scenario, id) + ActivationWords(scenario) + InputWords(scenario, id);
}

std::string RobotImagePath(const Options& options, uint16_t id) {
  if (options.config_on_boot_line) return options.image;
  return options.out + "/robot_" + std::to_string(id) + ".elf";
}

void CheckBootLines(const Options& options, const lab::scenario::Scenario& scenario) {
  const std::string activation = ActivationWords(scenario);
  for (uint16_t id = 0; id < scenario.robots.size(); ++id) {
    if (!options.config_on_boot_line) {
      // Each robot's block, as syrof-firmware-config makes it: a scenario
      // it cannot hold is refused by name before any image is written.
      const config::RobotBlockOrError block = config::MakeRobotBlock(scenario, id);
      if (!block.ok()) Usage("--scenario: " + block.error->ToString());
    }
    const std::string inputs = options.config_on_boot_line ? InputWords(scenario, id) : std::string();
    // qemu passes the image's path, a space and the -append text.
    const std::string line = RobotImagePath(options, id) + " " + ImageAppend(options, scenario, id);
    size_t words = 0;
    for (size_t i = 0; i < line.size(); ++i) {
      if (line[i] != ' ' && (i == 0 || line[i - 1] == ' ')) ++words;
    }
    if (line.size() > robot::kMaxBootLineBytes || words > robot::kMaxBootLineWords) {
      Usage("--scenario: robot " + std::to_string(id) + "'s boot line (the image's path and its -append words) takes " +
            std::to_string(line.size()) + " bytes in " + std::to_string(words) +
            " words; the robot image reads at most " + std::to_string(robot::kMaxBootLineBytes) + " bytes in " +
            std::to_string(robot::kMaxBootLineWords) + " words (activation.active or activation.cycles takes " +
            std::to_string(activation.size()) + " bytes of it" +
            (options.config_on_boot_line ? ", its inputs " + std::to_string(inputs.size()) : std::string()) +
            "; a shorter image path, script or input names fit)");
    }
  }
}

bool WriteRobotImages(const Options& options, const lab::scenario::Scenario& scenario) {
  if (options.config_on_boot_line) return true;
  const config::ElfOrError image = config::ReadElfFile(options.image);
  if (!image.ok()) Usage("--image: " + image.error->ToString());
  for (uint16_t id = 0; id < scenario.robots.size(); ++id) {
    const config::RobotBlockOrError block = config::MakeRobotBlock(scenario, id);
    if (!block.ok()) Usage("--scenario: " + block.error->ToString());
    config::ElfFile copy = *image.elf;
    if (const auto error = config::WriteBlock(copy, options.image, *block.block)) {
      Usage("--image: " + error->ToString());
    }
    const std::string path = RobotImagePath(options, id);
    if (const auto error = config::WriteImage(copy, path)) {
      std::fprintf(stderr, "syrof-firmware-swarm: cannot write robot %u's image: %s\n", static_cast<unsigned>(id),
                   error->ToString().c_str());
      return false;
    }
  }
  return true;
}

namespace {

// Starts robot `id`'s qemu with `hold 1`: the image sets itself up, prints
// `held id=N` and waits for its Start frame (DoHostAction), which says how
// long it runs; `paths` are its console, radio and sensor sockets (qemu
// connects to them in that order). qemu is looked for in PATH unless
// --qemu names a path; its standard output and error go to DIR/qemu_<id>.log;
// a real-time host's guests run one priority below it (SetRealtime).
process::Child LaunchQemu(const Options& options, const lab::scenario::Scenario& scenario, uint16_t id,
                 const std::string& console_path, const std::string& radio_path, const std::string& sensor_path) {
  std::vector<std::string> args = {
      options.qemu, "-M", "mps2-an386", "-nographic", "-monitor", "none", "-semihosting-config",
      "enable=on,target=native",
      "-chardev", "socket,id=console,path=" + console_path, "-serial", "chardev:console",
      "-chardev", "socket,id=radio,path=" + radio_path, "-serial", "chardev:radio",
      "-chardev", "socket,id=sensor,path=" + sensor_path, "-serial", "chardev:sensor",
      "-kernel", RobotImagePath(options, id), "-append", ImageAppend(options, scenario, id)};
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

}  // namespace

void SetRealtime() {
  sched_param parameters{};
  parameters.sched_priority = kHostPriority;
  if (sched_setscheduler(0, SCHED_FIFO, &parameters) != 0) {
    std::fprintf(stderr, "syrof-firmware-swarm: --realtime: SCHED_FIFO refused (%s); running at normal priority\n",
                 std::strerror(errno));
  }
}

QemuLauncher::QemuLauncher(const Options& options, const lab::scenario::Scenario& scenario)
    : options_(options), scenario_(scenario), sockets_(scenario.robots.size()) {}

bool QemuLauncher::OpenSockets() {
  char socket_dir_template[] = "/tmp/syrof-swarm-XXXXXX";
  const char* socket_dir = mkdtemp(socket_dir_template);
  if (socket_dir == nullptr) {
    std::perror("syrof-firmware-swarm: mkdtemp");
    return false;
  }
  socket_dir_ = socket_dir;
  for (size_t i = 0; i < sockets_.size(); ++i) {
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
  }
  return true;
}

int QemuLauncher::ListenBeside(const std::string& path) {
  const int listener = Listen(path);
  fcntl(listener, F_SETFL, fcntl(listener, F_GETFL) | O_NONBLOCK);
  paths_.push_back(path);
  return listener;
}

bool QemuLauncher::Launch(std::vector<Robot>& swarm, int timeout_ms) {
  if (options_.stress.on() && options_.stress.cpu_quota_permille > 0) {
    quota_ = std::make_unique<lab::sim::CpuQuotaGroup>(options_.stress.cpu_quota_permille);
    if (!quota_->ok()) {
      std::fprintf(stderr, "syrof-firmware-swarm: --stress-cpu-quota: %s\n", quota_->error().c_str());
      return false;
    }
  }
  for (uint16_t i = 0; i < swarm.size(); ++i) {
    Robot& robot = swarm[i];
    const RobotSockets& sockets = sockets_[i];
    robot.qemu = LaunchQemu(options_, scenario_, i, sockets.console_path, sockets.radio_path, sockets.sensor_path);
    if (!robot.qemu.started()) {
      std::fprintf(stderr, "syrof-firmware-swarm: cannot start robot %u's qemu %s: %s\n", static_cast<unsigned>(i),
                   options_.qemu.c_str(), std::strerror(robot.qemu.start_error()));
      KillAll(swarm);
      return false;
    }
    if (quota_ && !quota_->Add(robot.qemu.pid())) {
      std::fprintf(stderr, "syrof-firmware-swarm: robot %u's qemu could not join %s\n", static_cast<unsigned>(i),
                   quota_->path().c_str());
    }
    // qemu connects to its chardevs in order while starting up.
    robot.console = AcceptOne(sockets.console_listener, timeout_ms, "robot " + std::to_string(i) + "'s console");
    robot.radio = AcceptOne(sockets.radio_listener, timeout_ms, "robot " + std::to_string(i) + "'s radio");
    robot.sensor = AcceptOne(sockets.sensor_listener, timeout_ms, "robot " + std::to_string(i) + "'s sensor link");
    if (robot.console < 0 || robot.radio < 0 || robot.sensor < 0) {
      KillAll(swarm);
      return false;
    }
  }
  return true;
}

void QemuLauncher::KillAll(std::vector<Robot>& swarm) {
  for (Robot& robot : swarm) robot.qemu.Kill();
}

void QemuLauncher::RemoveSockets() {
  for (const std::string& path : paths_) unlink(path.c_str());
  paths_.clear();
  if (!socket_dir_.empty()) rmdir(socket_dir_.c_str());
  socket_dir_.clear();
}

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
bool DoHostAction(const HostAction& action, int64_t world_ns, const Options& options, Robot& robot,
                  int& open_consoles) {
  switch (action.kind) {
    case HostAction::Kind::kSwitchOn: {
      if (robot.sensor < 0 || !robot.held) return false;
      uint8_t wire_bytes[drivers::kMaxWireBytes];
      const auto encoded =
          drivers::EncodeFrame(drivers::MakeStart(0, RemainingMs(options.seconds, world_ns)), wire_bytes);
      robot.switched_on = encoded.ok() && process::WriteAll(robot.sensor, wire_bytes, encoded.value());
      return robot.switched_on;
    }
    case HostAction::Kind::kKill:
      robot.qemu.Kill();
      if (robot.console >= 0) --open_consoles;
      CloseLinks(robot);
      robot.sensor_out.clear();
      return true;
    case HostAction::Kind::kStop:
      robot.qemu.Signal(SIGSTOP);
      robot.sensor_out.clear();  // readings it would only get, stale, after the pause
      return true;
    case HostAction::Kind::kContinue:
      robot.qemu.Signal(SIGCONT);
      return true;
  }
  return false;
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

}  // namespace syrof::firmware::swarm
