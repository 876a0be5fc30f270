// syrof-robot: one robot of a DDS swarm (syrof/sim_dds/robot_process.h).
// Started by `syrof swarm`, never by hand: its arguments are RobotArguments'.
#include <iostream>
#include <string>
#include <vector>

#include "syrof/sim_dds/robot_process.h"

int main(int argc, char** argv) {
  const std::vector<std::string> arguments(argv + 1, argv + argc);
  const syrof::sim_dds::ParsedRobotArguments parsed = syrof::sim_dds::ParseRobotArguments(arguments);
  if (!parsed.options) {
    std::cerr << "syrof-robot: " << parsed.error->ToString() << " (it is started by `syrof swarm`, docs/dds.md)\n";
    return 2;
  }
  return syrof::sim_dds::RunRobotProcess(*parsed.options, std::cerr);
}
