#include "validate_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "syrof/app.h"
#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/scenario/scenario.h"
#include "usage.h"

namespace syrof::cli {

namespace scenario = lab::scenario;

CLI::App* SetupValidateCommand(CLI::App& app, ValidateOptions& options) {
  CLI::App* validate = app.add_subcommand("validate", "Check a scenario file and show what it resolves to");
  validate->add_option("scenario", options.scenario_path, "Scenario file (YAML)")->required();
  return validate;
}

int RunValidateCommand(const ValidateOptions& options, std::ostream& out, std::ostream& err) {
  const std::string scenario_file = ScenarioArgument(options.scenario_path, "validate", err, false);
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(scenario_file);
  if (!loaded.ok()) {
    fmt::print(err, "syrof validate: {}\n", loaded.error->ToString());
    return 2;
  }
  const scenario::Scenario& s = *loaded.scenario;
  // A library is loaded once in the sandboxed host, as `syrof run` does, so
  // validate refuses what run would refuse.
  std::string library_line;
  if (s.app.is_library()) {
    app_host::HostOptions host;
    host.library_path = s.app.library;
    const app_host::LibraryCheck check = app_host::CheckLibrary(host);
    if (!check.ok()) {
      fmt::print(err, "syrof validate: {}\n", check.error->ToString());
      return 2;
    }
    library_line = fmt::format("  library {} (app '{}'): entry symbol and ABI version {} check out\n",
                               s.app.library, check.app_name, SYROF_APP_ABI_VERSION);
  }
  fmt::print(out, "{}: ok\n  name {}, seed {}, app {}\n  arena {} x {} m, {} anchors\n", options.scenario_path, s.name,
             s.seed, s.app.name, s.arena.width_m, s.arena.height_m, s.arena.anchors.size());
  fmt::print(out, "{}", library_line);
  fmt::print(out, "  {} robots ({} placement), radio round {} s, maneuver {} s, K {}, F {}, {} s\n", s.robots.size(),
             scenario::ToString(s.placement), s.timing.radio_round_s, s.timing.app_round_s, s.timing.vote_rounds,
             s.timing.silence_rounds, s.timing.duration_s);
  fmt::print(out, "  channel {} (loss {}), {} link overrides, {} partitions, {} cuts, {} faults\n",
             lab::world::ToString(s.channel.model), s.channel.loss, s.channel.links.size(), s.channel.partitions.size(),
             s.channel.cuts.size(), s.faults.size());
  for (const scenario::RobotSpec& robot : s.robots) {
    fmt::print(out, "    robot {:>4} {:<5} at ({:.3f}, {:.3f}) heading {:.3f}{}\n", robot.id,
               lab::world::ToString(robot.kind), robot.x_m, robot.y_m, robot.heading_rad,
               robot.present_at_start ? "" : " (joins later)");
  }
  return 0;
}

}  // namespace syrof::cli
