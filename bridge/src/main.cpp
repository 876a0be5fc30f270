// syrof-bridge: the base station (docs/bridge.md). Reads the robots' radio
// traffic as a base-station radio hands it over (the radio link's framing,
// docs/radio-link.md) from a serial device, a Unix socket (the emulated
// swarm's --base-station) or a file, and feeds a BaseStation: the replay,
// DDS, and the live page (--live). This file only wires:
// options, the input, the clock that ends rounds, the outputs.
#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "syrof/bridge/base_station.h"
#include "syrof/bridge/dds_output.h"
#include "syrof/bridge/link_input.h"
#include "syrof/bridge/replay_sink.h"
#include "syrof/bridge/summary.h"
#include "syrof/lab/live/live_command.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/registry/tasks.h"
#include "syrof/wire/member_set.h"

namespace {

namespace bridge = syrof::bridge;
namespace replay = syrof::lab::replay;

constexpr int kOk = 0;
constexpr int kFailed = 1;
constexpr int kBadInput = 2;

struct Options {
  std::string serial;
  uint32_t baud = 1'000'000;
  std::string socket;
  int connect_wait_ms = 10'000;
  std::string input;
  std::string rounds;  // "stream" or "wall"; empty: stream for --input, wall otherwise
  int robots = 0;
  std::string scenario;
  double round_ms = 0;  // 0: the scenario's, else the protocol's 50 ms
  int silent_rounds = 6;
  double seconds = 0;  // 0: until the input ends or a signal
  std::string out = "out/bridge";
  std::string capture;  // empty: none; else every link byte read, as read (replay it with --input)
  bool no_replay = false;
  bool no_dds = false;
  std::optional<uint32_t> domain;
  std::string interface = "lo";
  bool quiet = false;
  syrof::lab::live::LiveCommandOptions live;  // the live page (docs/viewer.md, "Live")
};

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The replay's header, or why there is none.
struct HeaderOrError {
  std::optional<replay::Header> header;
  std::optional<syrof::lab::Error> error;
  bool ok() const { return header.has_value(); }
};

// The replay's header: the scenario's (arena, robots, radio round), or
// --robots N robots in the default 4 m arena.
HeaderOrError MakeHeader(const Options& options) {
  replay::Header header;
  if (!options.scenario.empty()) {
    syrof::lab::scenario::Overrides overrides;
    if (options.robots > 0) overrides.robots = options.robots;
    const auto loaded = syrof::lab::scenario::LoadScenarioFile(options.scenario, overrides);
    if (!loaded.ok()) {
      return {std::nullopt, syrof::lab::Error{.where = "--scenario", .message = loaded.error->ToString()}};
    }
    header = syrof::lab::sim::ReplayHeader(*loaded.scenario);
  } else {
    header.radio_round_ns = syrof::registry::kDefaultRadioRoundNs;
    header.arena_width_m = 4;
    header.arena_height_m = 4;
    header.scenario_name = "base-station";
    header.app_name = "robots on the air";
    for (int i = 0; i < options.robots; ++i) {
      header.robots.push_back(replay::RobotInfo{static_cast<uint16_t>(i), 0, 0.1f, {}});
    }
  }
  if (options.round_ms > 0) header.radio_round_ns = std::llround(options.round_ms * 1e6);
  if (header.robots.empty() || header.robots.size() > syrof::wire::kMaxSwarmSize) {
    return {std::nullopt, syrof::lab::Error{.where = "",
                                            .message = "the swarm has " + std::to_string(header.robots.size()) +
                                                       " robots; it must have 1 to " +
                                                       std::to_string(syrof::wire::kMaxSwarmSize)}};
  }
  return {std::move(header), std::nullopt};
}

// Reads the link until it ends, a signal, or --seconds; ends rounds on the
// wall clock (or lets the stream end them). Returns why it stopped.
std::string RunLink(int fd, bool wall_rounds, const Options& options, bridge::BaseStation& station, double& wall_s,
                    std::ofstream* capture) {
  const int64_t round_ns = station.header().radio_round_ns;
  const int64_t start_ns = NowNs();
  const int64_t stop_ns = options.seconds > 0 ? start_ns + std::llround(options.seconds * 1e9) : INT64_MAX;
  int64_t next_round_ns = start_ns + round_ns;
  std::vector<uint8_t> buffer(4096);
  std::string end;
  for (;;) {
    const int64_t now = NowNs();
    if (wall_rounds) {
      while (now >= next_round_ns) {
        station.EndRound(next_round_ns - start_ns);
        next_round_ns += round_ns;
      }
    }
    if (g_stop) {
      end = "signal";
      break;
    }
    if (now >= stop_ns) {
      end = "--seconds";
      break;
    }
    int64_t wait_ns = std::min(stop_ns, wall_rounds ? next_round_ns : now + 200'000'000) - now;
    pollfd entry{fd, POLLIN, 0};
    const int ready = poll(&entry, 1, static_cast<int>(std::max<int64_t>(0, (wait_ns + 999'999) / 1'000'000)));
    if (ready < 0) {
      if (errno == EINTR) continue;
      end = std::string("link error: poll: ") + std::strerror(errno);
      break;
    }
    if (ready == 0) continue;
    const ssize_t count = read(fd, buffer.data(), buffer.size());
    if (count < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      end = std::string("link error: ") + std::strerror(errno);
      break;
    }
    if (count == 0) {
      // A serial device ends only when it goes away (unplugged, reset).
      end = options.serial.empty() ? "end of input" : "link error: the device hung up (unplugged or reset?)";
      break;
    }
    if (capture != nullptr) capture->write(reinterpret_cast<const char*>(buffer.data()), count);
    station.Push(std::span<const uint8_t>(buffer.data(), static_cast<size_t>(count)));
  }
  wall_s = static_cast<double>(NowNs() - start_ns) * 1e-9;
  return end;
}

int Run(const Options& options) {
  const HeaderOrError made_header = MakeHeader(options);
  if (!made_header.ok()) {
    std::fprintf(stderr, "syrof-bridge: %s\n", made_header.error->ToString().c_str());
    return kBadInput;
  }
  const std::optional<replay::Header>& header = made_header.header;

  // The input.
  bridge::LinkOrError link;
  bridge::BridgeRunInfo run;
  if (!options.serial.empty()) {
    link = bridge::OpenSerial(options.serial, options.baud);
    run.input = "serial " + options.serial + " at " + std::to_string(options.baud) + " baud";
  } else if (!options.socket.empty()) {
    link = bridge::ConnectSocket(options.socket, options.connect_wait_ms);
    run.input = "socket " + options.socket;
  } else {
    link = bridge::OpenInputFile(options.input);
    run.input = options.input == "-" ? "stdin" : "file " + options.input;
  }
  if (!link.ok()) {
    std::fprintf(stderr, "syrof-bridge: %s\n", link.error->ToString().c_str());
    return kBadInput;
  }
  const bool wall_rounds = options.rounds.empty() ? options.input.empty() : options.rounds == "wall";

  // The outputs: the replay, DDS, and the live page.
  std::error_code made;
  std::filesystem::create_directories(options.out, made);
  if (made) {
    std::fprintf(stderr, "syrof-bridge: --out %s: %s\n", options.out.c_str(), made.message().c_str());
    bridge::CloseLink(link.fd);
    return kFailed;
  }
  std::vector<replay::RoundSink*> sinks;
  std::ofstream replay_file;
  std::unique_ptr<bridge::ReplaySink> replay_sink;
  if (!options.no_replay) {
    run.replay_path = options.out + "/replay";
    replay_file.open(run.replay_path, std::ios::binary | std::ios::trunc);
    if (!replay_file) {
      std::fprintf(stderr, "syrof-bridge: cannot write %s\n", run.replay_path.c_str());
      bridge::CloseLink(link.fd);
      return kFailed;
    }
    replay_sink = std::make_unique<bridge::ReplaySink>(replay_file);
    sinks.push_back(replay_sink.get());
  }
  syrof::lab::live::LiveResult started_live =
      syrof::lab::live::StartLive(options.live, "the base station (" + run.input + ")", std::cerr, sinks);
  if (!started_live.ok()) {
    std::cerr << "syrof-bridge: " << started_live.error->ToString() << "\n";
    bridge::CloseLink(link.fd);
    return kBadInput;
  }
  const std::unique_ptr<syrof::lab::live::LiveServer> live = std::move(started_live.server);

  std::vector<bridge::BeaconOutput*> outputs;
  std::unique_ptr<bridge::DdsBeaconOutput> dds;
  if (!options.no_dds) {
    run.dds_domain = options.domain.value_or(0);
    bridge::DdsOutputOrError created = bridge::DdsBeaconOutput::Create(run.dds_domain, options.interface);
    if (!created.ok()) {
      std::fprintf(stderr, "syrof-bridge: DDS: %s\n", created.error->ToString().c_str());
      bridge::CloseLink(link.fd);
      return kBadInput;
    }
    dds = std::move(created.output);
    outputs.push_back(dds.get());
    run.dds = true;
  }

  bridge::StationConfig config;
  config.silent_rounds = static_cast<uint16_t>(options.silent_rounds);
  config.rounds_from_stream = !wall_rounds;
  bridge::BaseStation station(config, *header, sinks, outputs);
  if (!options.quiet) {
    std::fprintf(stderr, "syrof-bridge: listening on %s for %zu robots, %.1f ms rounds%s\n", run.input.c_str(),
                 header->robots.size(), static_cast<double>(header->radio_round_ns) * 1e-6,
                 run.dds ? (", publishing on DDS domain " + std::to_string(run.dds_domain)).c_str() : "");
  }

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  std::ofstream capture;
  if (!options.capture.empty()) {
    capture.open(options.capture, std::ios::binary | std::ios::trunc);
    if (!capture) {
      std::fprintf(stderr, "syrof-bridge: cannot write --capture %s\n", options.capture.c_str());
      bridge::CloseLink(link.fd);
      return kFailed;
    }
  }
  run.end = RunLink(link.fd, wall_rounds, options, station, run.wall_s, capture.is_open() ? &capture : nullptr);
  bridge::CloseLink(link.fd);
  station.Finish(run.end == "end of input" || run.end == "--seconds" || run.end == "signal");
  if (dds) {
    run.dds_published = dds->published();
    run.dds_failed = dds->failed();
  }

  int status = kOk;
  std::optional<bridge::ReplayFacts> facts;
  if (replay_sink) {
    replay_file.close();
    if (!replay_sink->ok()) {
      std::fprintf(stderr, "syrof-bridge: replay: %s\n", replay_sink->error().ToString().c_str());
      status = kFailed;
    }
    std::ifstream in(run.replay_path, std::ios::binary);
    facts = bridge::ReadReplayFacts(in);
    if (!facts->read) {
      std::fprintf(stderr, "syrof-bridge: the replay does not read back: %s\n",
                   facts->error->ToString().c_str());
      status = kFailed;
    }
  }
  const std::string json_path = options.out + "/bridge.json";
  std::ofstream json(json_path);
  json << bridge::SummaryJson(station, run, facts);
  if (!json) {
    std::fprintf(stderr, "syrof-bridge: cannot write %s\n", json_path.c_str());
    status = kFailed;
  }
  if (!options.quiet) std::fputs(bridge::SummaryText(station, run).c_str(), stdout);
  if (run.end.rfind("link error", 0) == 0) {
    std::fprintf(stderr, "syrof-bridge: %s\n", run.end.c_str());
    status = kFailed;
  }
  if (live) syrof::lab::live::EndLive(*live, options.live, replay_sink ? run.replay_path : "", std::cerr);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "syrof-bridge: the base station. Reads the robots' radio traffic (the radio link's framing, "
      "docs/radio-link.md) from a serial device, a Unix socket or a file; checks every beacon as untrusted "
      "input; records a replay, publishes the beacons on DDS (rt/syrof/beacon) and prints what it refused "
      "(docs/bridge.md).",
      "syrof-bridge"};
  Options options;
  auto* inputs = app.add_option_group("input", "where the bytes come from (exactly one of these)");
  inputs->add_option("--serial", options.serial, "the base-station radio's serial device, e.g. /dev/ttyACM0 (raw mode)");
  inputs->add_option("--socket", options.socket,
                     "a Unix stream socket to connect to: syrof-firmware-swarm --base-station PATH");
  inputs->add_option("--input", options.input, "a capture file of link bytes (--capture); - reads stdin");
  bool from_stdin = false;
  inputs->add_flag("--stdin", from_stdin, "read link bytes from stdin (the same as --input -)");
  app.add_option("--baud", options.baud, "--serial's line rate (default 1000000, the radio link's; a USB CDC device ignores it)")
      ->check([](const std::string& text) {
        try {
          return bridge::IsSupportedBaud(static_cast<uint32_t>(std::stoul(text))) ? std::string()
                                                                                 : "unsupported baud rate " + text;
        } catch (...) {
          return "not a baud rate: " + text;
        }
      });
  app.add_option("--connect-wait-ms", options.connect_wait_ms,
                 "--socket: keep trying to connect this long while the socket is not there (default 10000)")
      ->check(CLI::Range(0, 600'000));
  app.add_option("--robots", options.robots,
                 "the swarm's size N: beacons are decoded for N robots (ids 0 .. N-1); overrides the scenario's")
      ->check(CLI::Range(1, static_cast<int>(syrof::wire::kMaxSwarmSize)));
  app.add_option("--scenario", options.scenario,
                 "a scenario file: the replay's arena, robots and radio round (the robots' own app is not run)")
      ->check(CLI::ExistingFile);
  app.add_option("--round-ms", options.round_ms,
                 "the radio round in ms (default: the scenario's, else the protocol's 50)")
      ->check(CLI::Range(1.0, 10'000.0));
  app.add_option("--rounds", options.rounds,
                 "what ends a round: wall (the clock, every --round-ms; default for --serial and --socket) or "
                 "stream (a second beacon from one robot; default for --input)")
      ->check(CLI::IsMember({"wall", "stream"}));
  app.add_option("--silent-rounds", options.silent_rounds,
                 "rounds a robot may be unheard and still count as RUNNING; after that the replay marks it CRASHED "
                 "(default 6, the synchronizer's F)")
      ->check(CLI::Range(1, 60'000));
  app.add_option("--seconds", options.seconds, "stop after this many seconds (default: at the end of the input, or Ctrl-C)")
      ->check(CLI::Range(0.0, 1e7));
  app.add_option("--out", options.out, "the output folder: replay and bridge.json (default out/bridge)");
  app.add_flag("--no-replay", options.no_replay, "do not write a replay");
  app.add_option("--capture", options.capture,
                 "also write every link byte read, as read, to this file (feed it back with --input FILE)");
  bool dds = false;
  auto* no_dds = app.add_flag("--no-dds", options.no_dds, "do not publish on DDS");
  app.add_flag("--dds", dds, "publish every accepted beacon on rt/syrof/beacon (the default)")->excludes(no_dds);
  app.add_option("--domain", options.domain,
                 "the DDS domain id (default $SYROF_DDS_DOMAIN, else 0, where ROS 2 tools look)")
      ->check(CLI::Range(0, 232));
  app.add_option("--interface", options.interface, "the network interface DDS uses (default lo: this host only)");
  app.add_flag("--quiet", options.quiet, "print nothing but errors");
  syrof::lab::live::SetupLiveOptions(app, options.live);

  try {
    // `--live ADDR:PORT` as well as `--live=ADDR:PORT` (CLI11 takes only the latter).
    std::vector<std::string> arguments = syrof::lab::live::JoinLiveAddress(argc, argv);
    std::vector<char*> pointers;
    for (std::string& argument : arguments) pointers.push_back(argument.data());
    app.parse(static_cast<int>(pointers.size()), pointers.data());
  } catch (const CLI::CallForHelp& help) {
    std::cout << app.help();
    return kOk;
  } catch (const CLI::ParseError& parse_error) {
    std::cerr << "syrof-bridge: " << parse_error.what() << "\n(syrof-bridge --help lists the options)\n";
    return kBadInput;
  }
  const int sources = !options.serial.empty() + !options.socket.empty() + !options.input.empty() + from_stdin;
  if (sources != 1) {
    std::cerr << "syrof-bridge: give exactly one input: --serial DEVICE, --socket PATH, --input FILE or --stdin\n"
              << "(syrof-bridge --help lists the options)\n";
    return kBadInput;
  }
  if (from_stdin) options.input = "-";
  if (options.robots == 0 && options.scenario.empty()) {
    std::cerr << "syrof-bridge: say how many robots there are: --robots N or --scenario FILE\n";
    return kBadInput;
  }
  if (!options.domain) {
    if (const char* text = std::getenv("SYROF_DDS_DOMAIN")) {
      char* end = nullptr;
      const unsigned long value = std::strtoul(text, &end, 10);
      if (*text == '\0' || *end != '\0' || value > 232) {
        std::cerr << "syrof-bridge: SYROF_DDS_DOMAIN='" << text << "' is not a domain id 0 .. 232\n";
        return kBadInput;
      }
      options.domain = static_cast<uint32_t>(value);
    }
  }
  return Run(options);
}
