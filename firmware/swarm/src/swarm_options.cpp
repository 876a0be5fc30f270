#include "syrof/firmware/swarm/swarm_options.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string_view>

#include "syrof/lab/scenario/fits_the_image.h"

namespace syrof::firmware::swarm {

namespace {

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

}  // namespace

const char* const kUsage =
    "usage: syrof-firmware-swarm --image ELF [--scenario FILE] [--robots 1..16] [--seconds S] [--loss 0..1]\n"
    "       [--seed N] [--out DIR] [--qemu PATH] [--icount SHIFT|-1] [--align 0|1] [--latency-ms MS]\n"
    "       [--expect-cooperative] [--expect-faults] [--max-estimation-error M] [--realtime]\n"
    "       [--config-on-boot-line]\n"
    "       [--base-station PATH] [--stress SEED [--stress-rate R] [--stress-late F] [--stress-cpu-quota P]]\n"
    "       [--live [ADDR:PORT] [--live-linger S]]\n"
    "Starts one qemu mps2-an386 instance of the robot image per robot of the scenario (--robots, --seed\n"
    "and --loss override it) and plays the world, the robots' sensors and the radio channel between\n"
    "them; plays the scenario's faults (crash, pause, join, deaf, mute) and partitions on world time;\n"
    "writes metrics.json, replay, firmware-swarm.json and logs in --out (docs/firmware.md).\n"
    "The guests run on the host's clock; --icount SHIFT runs them with qemu's -icount shift=SHIFT.\n"
    "Each robot boots its own copy of the image, DIR/robot_<i>.elf, with its configuration block (id, swarm,\n"
    "kinds, its inputs) written as syrof-firmware-config writes it for a class's robots; --config-on-boot-line\n"
    "gives them on each robot's boot line instead, to the image as built.\n"
    "--realtime runs this process and the qemu instances at SCHED_FIFO (root or CAP_SYS_NICE).\n"
    "--base-station PATH listens on the Unix socket PATH and sends a client there every beacon sent, as\n"
    "ReceivedBeacon frames (syrof-bridge --socket PATH; docs/bridge.md).\n"
    "--stress SEED: seeded SIGSTOP bursts of 10-200 ms of the qemu instances and the host (R a second,\n"
    "default 4), the fraction F of beacons (default 0.05) delivered 10-200 ms late, the qemu instances\n"
    "at P per mille of one core (a cgroup; root); a failing run prints the command that reruns it.\n"
    "--live serves the live page while the robots run, as `syrof swarm --live` does (docs/viewer.md \"Live\"):\n"
    "--live alone on 127.0.0.1:8765 (only this host can open it), --live ADDR:PORT or --live=ADDR:PORT\n"
    "elsewhere, --live PORT on 127.0.0.1 (port 0: a free one); it prints the page's URL. After the run the\n"
    "page links the replay and stays up --live-linger S seconds (default: until Ctrl-C; 0: exit at once).\n";

void Usage(const std::string& what) {
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
    if (key == "--config-on-boot-line") {
      options.config_on_boot_line = true;
      continue;
    }
    // --live, --live ADDR:PORT, --live PORT and --live=..., as `syrof swarm`
    // takes them (lab/live/live_command.h). This program has no positional
    // argument, so whatever follows --live and is no option is its address.
    if (key == "--live" || key.rfind("--live=", 0) == 0) {
      if (key != "--live") {
        options.live.address = key.substr(std::string_view("--live=").size());
      } else if (i + 1 < argc && argv[i + 1][0] != '-') {
        options.live.address = argv[++i];
      } else {
        options.live.address = lab::live::kDefaultLiveAddress;
      }
      std::string address, problem;
      int port = 0;
      if (!lab::live::ParseLiveAddress(options.live.address, address, port, problem)) Usage(problem);
      continue;
    }
    static const std::string_view kWithValue[] = {"--image",    "--qemu",    "--out",      "--robots",
                                                  "--seconds",  "--loss",    "--seed",     "--scenario",
                                                  "--max-estimation-error", "--latency-ms", "--align", "--icount",
                                                  "--base-station", "--stress", "--stress-rate", "--stress-late",
                                                  "--stress-cpu-quota", "--live-linger"};
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
    } else if (key == "--live-linger") {
      options.live.linger_s = number(-1, 1e6);
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
  if (!options.live.on()) {
    for (int i = 1; i < argc; ++i) {
      if (std::string_view(argv[i]) == "--live-linger") Usage("--live-linger needs --live");
    }
  }
  if (options.image.empty()) Usage("--image is required");
  if (access(options.image.c_str(), R_OK) != 0) {
    Usage("--image: cannot read " + options.image + " (build it: make test-m4, or cmake --build build-m4 --target syrof-robot-mps2)");
  }
  return options;
}

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
  // Every model runs on the image: each robot reads the activation from its
  // boot words (qemu_launcher.cpp, CheckBootLines bounds the script), and
  // every kind (its boot words name the robot's kind and its swarm's). What
  // the image has compiled in and cannot be told is refused, naming what
  // differs, by the check syrof-firmware-config makes too (lab/scenario
  // fits_the_image.h): more robots than the radio carries a beacon for
  // (kMaxImageRobots), the radio round, the default arena (its estimator
  // ranges against the default anchors while this host's world measures
  // against the scenario's: 1.3 m RMSE on a 5 m arena) and a present kind's
  // limits (a drone's drift is the world's alone, played by this host: any
  // is fine).
  if (const auto error = lab::scenario::CheckScenarioFitsTheImage(scenario)) Usage("--scenario: " + error->message);
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

}  // namespace syrof::firmware::swarm
