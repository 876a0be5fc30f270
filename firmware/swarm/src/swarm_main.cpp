// syrof-firmware-swarm: an emulated swarm of real firmware. Starts N qemu
// mps2-an386 instances of syrof-robot-mps2, each with its radio UART (UART1)
// and its console (UART0) on Unix sockets this process listens on, and plays
// the radio channel between them with the lab's channel model
// (lab/world/channel.h): every SendBeacon frame a robot sends is delivered
// to each other robot as a ReceivedBeacon frame unless the channel loses it
// (a hash of seed, the sender's beacon count, sender and receiver), half a
// radio round after it was sent, as the lab's radio delivers (the robots'
// round alignment expects that latency: firmware/robot/robot_image.h,
// kBeaconLatencyNs). It feeds
// the lab's metrics collector from the robots' console reports and writes
// DIR/metrics.json (docs/metrics.md) and DIR/firmware-swarm.json (timing
// mode, round-start skew, channel counts), DIR/beacons.csv (when each
// robot's beacons reached this process); DIR/robot_<i>.log holds each
// robot's console and DIR/qemu_<i>.log qemu's own output.
//
// Not here (docs/firmware.md, "The emulated swarm"): no world physics and
// no sensor UART, so the robots do not move and their estimates stay at
// their start poses; no replay.
//
//   syrof-firmware-swarm --image build-m4/bin/syrof-robot-mps2.elf --robots 4 --seconds 20
//       --loss 0 --seed 1 --out DIR [--qemu qemu-system-arm] [--icount SHIFT|-1] [--align 0|1]
//       [--latency-ms 25] [--expect-cooperative]
//
// Exit status 0 when every instance ran to the end and reported, no P3
// breach happened, and (with --expect-cooperative) all robots started one
// epoch COOPERATIVE; 1 otherwise; 2 for a usage error.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/firmware/swarm/console_lines.h"
#include "syrof/firmware/swarm/round_skew.h"
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/world/channel.h"
#include "syrof/registry/tasks.h"

namespace {

namespace drivers = syrof::firmware::drivers;
namespace swarm = syrof::firmware::swarm;
namespace metrics = syrof::lab::metrics;

struct Options {
  std::string image;
  std::string qemu = "qemu-system-arm";
  std::string out = "firmware-swarm";
  int robots = 4;
  int seconds = 20;
  double loss = 0;
  uint64_t seed = 1;
  // -icount shift=4: a guest instruction is 16 ns of its virtual time (62.5
  // MHz, near the Teensy's 72); -1: no -icount, guest clocks follow the host's
  // (docs/firmware.md, "The emulated swarm", says how this was chosen).
  int icount_shift = 4;
  bool expect_cooperative = false;
  bool align = true;  // the robots' round alignment (docs/clocks.md)
  double latency_ms = 25;  // from a beacon's send to its delivery
};

// The robot image is built with SYROF_MAX_SWARM_SIZE=32 (the Teensy's).
constexpr int kMaxImageRobots = 32;

constexpr const char* kUsage =
    "usage: syrof-firmware-swarm --image ELF [--robots 1..32] [--seconds S] [--loss 0..1] [--seed N]\n"
    "       [--out DIR] [--qemu PATH] [--icount SHIFT] [--align 0|1] [--latency-ms MS]\n"
    "       [--expect-cooperative]\n"
    "Starts --robots qemu mps2-an386 instances of the robot image and plays the radio channel between\n"
    "them; writes metrics.json, firmware-swarm.json and logs in --out (docs/firmware.md).\n";

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
    } else if (key == "--seconds") {
      options.seconds = static_cast<int>(number(1, 3600));
    } else if (key == "--loss") {
      options.loss = number(0, 1);
    } else if (key == "--seed") {
      options.seed = static_cast<uint64_t>(number(0, 1e15));
    } else if (key == "--latency-ms") {
      options.latency_ms = number(0, 1000);
    } else if (key == "--align") {
      options.align = number(0, 1) == 1;
    } else if (key == "--icount") {
      options.icount_shift = static_cast<int>(number(-1, 10));
    } else {
      Usage("unknown argument '" + key + "'");
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

bool WriteAll(int fd, const uint8_t* bytes, size_t length) {
  while (length > 0) {
    const ssize_t written = write(fd, bytes, length);
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes += written;
    length -= static_cast<size_t>(written);
  }
  return true;
}

// A ReceivedBeacon frame on its way to robot `to`.
struct Delivery {
  int64_t due_ns = 0;
  uint16_t to = 0;
  std::vector<uint8_t> bytes;
};

struct Robot {
  pid_t pid = -1;
  int radio = -1;
  int console = -1;
  drivers::FrameDecoder decoder;
  std::string pending_line;
  std::ofstream log;
  int64_t beacons_sent = 0;
  std::vector<int64_t> beacon_ns;  // host instants of its SendBeacon frames
  std::optional<swarm::RoundLine> latest;
  int64_t latest_ns = 0;
  int64_t last_boundary_ns = 0;
  int64_t lines = 0;
  int64_t bad_lines = 0;
  std::string last_status;
  int exit_status = -1;
};

}  // namespace

int main(int argc, char** argv) {
  const Options options = ParseOptions(argc, argv);
  signal(SIGPIPE, SIG_IGN);
  std::error_code made;
  std::filesystem::create_directories(options.out, made);
  if (made || !std::filesystem::is_directory(options.out)) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot make the output directory %s: %s\n", options.out.c_str(),
                 made.message().c_str());
    return 1;
  }
  char socket_dir_template[] = "/tmp/syrof-swarm-XXXXXX";
  const char* socket_dir = mkdtemp(socket_dir_template);
  if (socket_dir == nullptr) {
    std::perror("syrof-firmware-swarm: mkdtemp");
    return 1;
  }
  const auto robots = static_cast<uint16_t>(options.robots);
  const int64_t period_ns = syrof::registry::kDefaultRadioRoundNs;
  std::vector<Robot> swarm(robots);
  std::vector<int> radio_listeners(robots), console_listeners(robots);
  std::vector<std::string> paths;
  for (uint16_t i = 0; i < robots; ++i) {
    const std::string radio_path = std::string(socket_dir) + "/radio" + std::to_string(i);
    const std::string console_path = std::string(socket_dir) + "/console" + std::to_string(i);
    radio_listeners[i] = Listen(radio_path);
    console_listeners[i] = Listen(console_path);
    paths.push_back(radio_path);
    paths.push_back(console_path);
    swarm[i].log.open(options.out + "/robot_" + std::to_string(i) + ".log");
  }

  // One qemu per robot; each keeps its own virtual clock.
  std::string timing = options.icount_shift < 0 ? "host clock (no -icount)"
                                                : "-icount shift=" + std::to_string(options.icount_shift);
  const int64_t start_ns = HostNs();
  for (uint16_t i = 0; i < robots; ++i) {
    std::vector<std::string> args = {
        options.qemu, "-M", "mps2-an386", "-nographic", "-monitor", "none", "-semihosting-config",
        "enable=on,target=native",
        "-chardev", "socket,id=console,path=" + paths[2 * i + 1], "-serial", "chardev:console",
        "-chardev", "socket,id=radio,path=" + paths[2 * i], "-serial", "chardev:radio",
        "-kernel", options.image, "-append",
        "id " + std::to_string(i) + " swarm " + std::to_string(robots) + " seconds " +
            std::to_string(options.seconds) + " report 1 align " + (options.align ? "1" : "0")};
    if (options.icount_shift >= 0) {
      args.push_back("-icount");
      args.push_back("shift=" + std::to_string(options.icount_shift));
    }
    const pid_t pid = fork();
    if (pid == 0) {
      const std::string log = options.out + "/qemu_" + std::to_string(i) + ".log";
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
      }
      std::vector<char*> argv_child;
      for (std::string& arg : args) argv_child.push_back(arg.data());
      argv_child.push_back(nullptr);
      execvp(argv_child[0], argv_child.data());
      std::perror("syrof-firmware-swarm: exec qemu");
      _exit(127);
    }
    swarm[i].pid = pid;
    // qemu connects to its chardevs in order while starting up.
    swarm[i].console = AcceptOne(console_listeners[i], 15'000, "robot " + std::to_string(i) + "'s console");
    swarm[i].radio = AcceptOne(radio_listeners[i], 15'000, "robot " + std::to_string(i) + "'s radio");
    if (swarm[i].console < 0 || swarm[i].radio < 0) {
      for (Robot& robot : swarm) {
        if (robot.pid > 0) kill(robot.pid, SIGKILL);
      }
      return 1;
    }
  }
  const int64_t all_started_ns = HostNs();

  syrof::lab::world::ChannelSpec spec;
  spec.loss = options.loss;
  syrof::lab::world::Channel channel(spec, robots, options.seed);
  metrics::CollectorConfig collector_config;
  collector_config.robots = robots;
  collector_config.radio_round_ns = period_ns;
  metrics::Collector collector(collector_config);

  // Every COOPERATIVE epoch start, to find the first epoch all robots started so.
  std::map<uint16_t, std::vector<uint16_t>> cooperative_starters;
  std::optional<double> all_cooperative_s;
  int64_t round = 0;
  int64_t next_round_ns = all_started_ns + period_ns;
  int64_t link_errors = 0;
  int64_t offered = 0, delivered = 0;
  // With -icount a loaded host stretches the guests' time (1.3x for 4
  // robots on 2 busy cores, more for 8): three times the run, then give up.
  const int64_t deadline_ns = all_started_ns + (3 * options.seconds + 30) * int64_t{1'000'000'000};
  int open_consoles = robots;

  const auto latency_ns = static_cast<int64_t>(options.latency_ms * 1e6);
  std::deque<Delivery> in_flight;  // in due order: one latency for all
  std::vector<pollfd> fds;
  while (open_consoles > 0 && HostNs() < deadline_ns) {
    fds.clear();
    for (const Robot& robot : swarm) {
      fds.push_back({robot.radio, POLLIN, 0});
      fds.push_back({robot.console, POLLIN, 0});
    }
    const int64_t now_before = HostNs();
    int64_t next_event_ns = next_round_ns;
    if (!in_flight.empty()) next_event_ns = std::min(next_event_ns, in_flight.front().due_ns);
    const int wait_ms = static_cast<int>(std::max<int64_t>(0, (next_event_ns - now_before) / 1'000'000));
    poll(fds.data(), fds.size(), std::min(wait_ms, 10));
    const int64_t now = HostNs();
    while (!in_flight.empty() && in_flight.front().due_ns <= now) {
      const Delivery& delivery = in_flight.front();
      if (swarm[delivery.to].radio >= 0) {
        (void)WriteAll(swarm[delivery.to].radio, delivery.bytes.data(), delivery.bytes.size());
      }
      in_flight.pop_front();
    }
    for (uint16_t i = 0; i < robots; ++i) {
      Robot& robot = swarm[i];
      uint8_t buffer[4096];
      if (robot.radio >= 0 && (fds[2 * i].revents & (POLLIN | POLLHUP)) != 0) {
        const ssize_t count = read(robot.radio, buffer, sizeof buffer);
        if (count <= 0) {
          close(robot.radio);
          robot.radio = -1;
        }
        for (ssize_t k = 0; k < count; ++k) {
          const drivers::DecodeEvent event = robot.decoder.Push(buffer[k]);
          if (event == drivers::DecodeEvent::kError) ++link_errors;
          if (event != drivers::DecodeEvent::kFrame) continue;
          const drivers::Frame& frame = robot.decoder.frame();
          if (frame.kind != drivers::FrameKind::kSendBeacon) continue;
          robot.beacon_ns.push_back(now);
          robot.last_boundary_ns = now;
          const int64_t beacon_round = robot.beacons_sent++;
          for (uint16_t to = 0; to < robots; ++to) {
            if (to == i || swarm[to].radio < 0) continue;
            ++offered;
            if (!channel.Delivers(i, to, beacon_round, static_cast<double>(now - all_started_ns) * 1e-9)) continue;
            ++delivered;
            uint8_t wire_bytes[drivers::kMaxWireBytes];
            const auto encoded = drivers::EncodeFrame(
                drivers::MakeReceivedBeacon(frame.sequence, -60,
                                            std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length)),
                wire_bytes);
            if (encoded.ok()) {
              in_flight.push_back(
                  Delivery{now + latency_ns, to, std::vector<uint8_t>(wire_bytes, wire_bytes + encoded.value())});
            }
          }
        }
      }
      if (robot.console >= 0 && (fds[2 * i + 1].revents & (POLLIN | POLLHUP)) != 0) {
        const ssize_t count = read(robot.console, buffer, sizeof buffer);
        if (count <= 0) {
          close(robot.console);
          robot.console = -1;
          --open_consoles;
          continue;
        }
        robot.pending_line.append(reinterpret_cast<const char*>(buffer), static_cast<size_t>(count));
        size_t newline;
        while ((newline = robot.pending_line.find('\n')) != std::string::npos) {
          const std::string line = robot.pending_line.substr(0, newline);
          robot.pending_line.erase(0, newline + 1);
          robot.log << line << '\n';
          ++robot.lines;
          if (line.rfind("status ", 0) == 0) robot.last_status = line;
          const swarm::ConsoleLine parsed = swarm::ParseConsoleLine(line, robots);
          if (const auto* error = std::get_if<swarm::LineError>(&parsed)) {
            ++robot.bad_lines;
            std::fprintf(stderr, "robot %u console, column %zu: %s\n  %s\n", static_cast<unsigned>(i), error->column,
                         error->what.c_str(), line.c_str());
          } else if (const auto* round_line = std::get_if<swarm::RoundLine>(&parsed)) {
            robot.latest = *round_line;
            robot.latest_ns = now;
          } else if (const auto* epoch_line = std::get_if<swarm::EpochLine>(&parsed)) {
            collector.OnEpochStart(epoch_line->robot, round, now - all_started_ns, epoch_line->map);
            if (epoch_line->map.mode == syrof::wire::Mode::kCooperative) {
              std::vector<uint16_t>& starters = cooperative_starters[epoch_line->map.epoch];
              starters.push_back(epoch_line->robot);
              if (starters.size() == robots && !all_cooperative_s) {
                all_cooperative_s = static_cast<double>(now - all_started_ns) * 1e-9;
              }
            }
          }
        }
      }
    }
    // Round ends on the host's clock: every robot's latest report.
    while (now >= next_round_ns) {
      std::vector<metrics::RobotRound> rounds(robots);
      std::vector<int64_t> boundaries;
      for (uint16_t i = 0; i < robots; ++i) {
        const Robot& robot = swarm[i];
        metrics::RobotRound& entry = rounds[i];
        entry.id = i;
        entry.running = robot.latest.has_value() && now - robot.latest_ns < 3 * period_ns;
        if (robot.latest) {
          entry.sync_member = robot.latest->member;
          entry.member = entry.running && robot.latest->member;
          entry.epoch = robot.latest->epoch;
          entry.epoch_mode = robot.latest->mode;
          entry.phase = robot.latest->phase;
          entry.estimate_valid = robot.latest->estimate_valid;
          // No world: the bodies stay where the estimates say.
          entry.true_x_m = entry.est_x_m = robot.latest->x_m;
          entry.true_y_m = entry.est_y_m = robot.latest->y_m;
        }
        if (entry.member && robot.last_boundary_ns > 0) boundaries.push_back(robot.last_boundary_ns - all_started_ns);
      }
      collector.OnRoundPhases(boundaries);
      collector.OnRoundEnd(round, rounds);
      ++round;
      next_round_ns += period_ns;
    }
  }

  bool ok = true;
  for (uint16_t i = 0; i < robots; ++i) {
    Robot& robot = swarm[i];
    int status = 0;
    if (robot.console >= 0 || robot.radio >= 0) {  // the deadline passed
      kill(robot.pid, SIGKILL);
      ok = false;
      std::fprintf(stderr, "robot %u: still running at the deadline\n", static_cast<unsigned>(i));
    }
    waitpid(robot.pid, &status, 0);
    robot.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (robot.exit_status != 0 || !robot.latest || robot.bad_lines > 0) ok = false;
  }
  for (const std::string& path : paths) unlink(path.c_str());
  rmdir(socket_dir);
  const double wall_s = static_cast<double>(HostNs() - start_ns) * 1e-9;

  metrics::RunFacts facts;
  facts.seed = options.seed;
  facts.robots = robots;
  facts.sim_seconds = static_cast<double>(round) * static_cast<double>(period_ns) * 1e-9;
  facts.wall_seconds = wall_s;
  facts.radio_rounds = round;
  facts.min_separation_m = std::numeric_limits<double>::infinity();
  facts.goal.app = "circle";
  facts.goal.detail = "not checked: the firmware swarm has no world (robots do not move)";
  facts.app_name = "circle";
  facts.app_source = "builtin:circle";
  facts.scenario = "firmware-swarm";
  const metrics::Metrics result = collector.Finish(facts);
  std::ofstream metrics_file(options.out + "/metrics.json");
  metrics_file << metrics::ToJson(result);
  if (!metrics_file.flush()) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot write %s/metrics.json\n", options.out.c_str());
    ok = false;
  }

  std::vector<std::vector<int64_t>> beacon_times;
  std::ofstream beacons_csv(options.out + "/beacons.csv");
  beacons_csv << "robot,host_ms\n";
  for (uint16_t i = 0; i < robots; ++i) {
    beacon_times.push_back(swarm[i].beacon_ns);
    for (const int64_t t : swarm[i].beacon_ns) beacons_csv << i << ',' << static_cast<double>(t - all_started_ns) * 1e-6 << '\n';
  }
  // Skew from 5 s on: the start-up (instances boot one after another) and
  // the round alignment's first corrections are left out.
  const swarm::SkewStats skew = swarm::RoundStartSkew(beacon_times, period_ns, all_started_ns + 5'000'000'000);
  const bool cooperative = all_cooperative_s.has_value();
  if (options.expect_cooperative && !cooperative) ok = false;
  if (result.common_knowledge.violations != 0) ok = false;

  std::ofstream report(options.out + "/firmware-swarm.json");
  report << "{\n  \"robots\": " << robots << ",\n  \"seconds\": " << options.seconds << ",\n  \"loss\": " << options.loss
         << ",\n  \"seed\": " << options.seed << ",\n  \"align\": " << (options.align ? "true" : "false")
         << ",\n  \"latency_ms\": " << options.latency_ms << ",\n  \"timing\": \"" << timing << "\",\n  \"wall_seconds\": " << wall_s
         << ",\n  \"all_cooperative_s\": "
         << (cooperative ? std::to_string(*all_cooperative_s) : std::string("null"))
         << ",\n  \"p3_violations\": " << result.common_knowledge.violations
         << ",\n  \"cooperative_starts\": " << result.common_knowledge.cooperative_starts
         << ",\n  \"round_start_skew\": {\"samples\": " << skew.samples << ", \"median_ms\": " << skew.median_ns * 1e-6
         << ", \"p95_ms\": " << skew.p95_ns * 1e-6 << ", \"max_ms\": " << skew.max_ns * 1e-6 << "}"
         << ",\n  \"beacons\": {\"offered\": " << offered << ", \"delivered\": " << delivered
         << ", \"link_errors\": " << link_errors << "},\n  \"exit_statuses\": [";
  for (uint16_t i = 0; i < robots; ++i) report << (i ? ", " : "") << swarm[i].exit_status;
  report << "]\n}\n";

  std::printf("firmware swarm: %u robots, %d s, loss %.2f, seed %llu, timing %s, wall %.1f s\n",
              static_cast<unsigned>(robots), options.seconds, options.loss,
              static_cast<unsigned long long>(options.seed), timing.c_str(), wall_s);
  std::printf("  all robots COOPERATIVE in one epoch: %s; COOPERATIVE starts %lld; P3 violations %lld\n",
              cooperative ? ("at " + std::to_string(*all_cooperative_s) + " s").c_str() : "never",
              static_cast<long long>(result.common_knowledge.cooperative_starts),
              static_cast<long long>(result.common_knowledge.violations));
  std::printf("  round-start skew (beacon arrivals vs robot 0, after 5 s): median %.3f ms, p95 %.3f ms, max %.3f ms "
              "over %lld beacons\n",
              skew.median_ns * 1e-6, skew.p95_ns * 1e-6, skew.max_ns * 1e-6, static_cast<long long>(skew.samples));
  std::printf("  beacons offered %lld, delivered %lld; radio-link errors %lld\n", static_cast<long long>(offered),
              static_cast<long long>(delivered), static_cast<long long>(link_errors));
  for (uint16_t i = 0; i < robots; ++i) {
    std::printf("  robot %u: exit %d, %s\n", static_cast<unsigned>(i), swarm[i].exit_status,
                swarm[i].last_status.c_str());
  }
  std::printf("  %s/metrics.json, %s/firmware-swarm.json: %s\n", options.out.c_str(), options.out.c_str(),
              ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
