// syrof-demo: the foundation demo (see demo.h). Exit status 0 on success,
// 2 on bad options.
#include <CLI/CLI.hpp>

#include <chrono>
#include <iostream>

#include "demo.h"

int main(int argc, char** argv) {
  syrof::lab::demo::DemoOptions options;
  CLI::App app{"SyROF foundation demo: simulated robots exchanging beacons through their brokers in virtual time"};
  app.add_option("--robots", options.robots, "robots in the swarm (2..8)")->capture_default_str();
  app.add_option("--seconds", options.seconds, "virtual time to simulate")->capture_default_str();
  app.add_option("--loss", options.loss, "probability that a beacon misses one receiver")->capture_default_str();
  app.add_option("--seed", options.seed, "seed of the radio channel")->capture_default_str();
  bool quiet_rounds = false;
  app.add_flag("--no-rounds", quiet_rounds, "omit the per-round table");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int status = app.exit(error);
    return status == 0 ? 0 : 2;
  }
  options.show_rounds = !quiet_rounds;
  if (const std::string problem = syrof::lab::demo::Validate(options); !problem.empty()) {
    std::cerr << "syrof-demo: " << problem << "\n";
    return 2;
  }

  const auto started = std::chrono::steady_clock::now();
  syrof::lab::demo::RunDemo(options, std::cout);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::cout << "Wall time " << wall_s * 1000.0 << " ms (" << options.seconds / wall_s << "x real time).\n";
  return 0;
}
