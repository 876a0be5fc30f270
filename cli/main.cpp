// The `syrof` command: one file per subcommand (run, validate, apps,
// replay, view, compare, new, grade, gradescope, swarm, assignment, search);
// main only wires them.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "apps_command.h"
#include "assignment_command.h"
#include "compare_command.h"
#include "grade_command.h"
#include "gradescope_command.h"
#include "new_command.h"
#include "replay_command.h"
#include "run_command.h"
#include "search_command.h"
#include "swarm_command.h"
#include "syrof/lab/live/live_command.h"
#include "usage.h"
#include "validate_command.h"
#include "view_command.h"

int main(int argc, char** argv) {
  using namespace syrof::cli;
  CLI::App app{"SyROF: the Synchronous Robotic Framework's lab"};
  app.require_subcommand(1);
  RunOptions run_options;
  CLI::App* run = SetupRunCommand(app, run_options);
  ValidateOptions validate_options;
  CLI::App* validate = SetupValidateCommand(app, validate_options);
  AppsOptions apps_options;
  CLI::App* apps = SetupAppsCommand(app, apps_options);
  ReplayOptions replay_options;
  CLI::App* replay = SetupReplayCommand(app, replay_options);
  ViewOptions view_options;
  CLI::App* view = SetupViewCommand(app, view_options);
  CompareOptions compare_options;
  CLI::App* compare = SetupCompareCommand(app, compare_options);
  NewOptions new_options;
  CLI::App* new_command = SetupNewCommand(app, new_options);
  GradeOptions grade_options;
  CLI::App* grade = SetupGradeCommand(app, grade_options);
  GradescopeOptions gradescope_options;
  CLI::App* gradescope = SetupGradescopeCommand(app, gradescope_options);
  SwarmOptions swarm_options;
  CLI::App* swarm = SetupSwarmCommand(app, swarm_options);
  SearchOptions search_options;
  CLI::App* search = SetupSearchCommand(app, search_options);
  AssignmentOptions assignment_options;
  CLI::App* assignment = SetupAssignmentCommand(app, assignment_options);
  try {
    // `--live ADDR:PORT` as well as `--live=ADDR:PORT` (CLI11 takes only the latter).
    std::vector<std::string> arguments = syrof::lab::live::JoinLiveAddress(argc, argv);
    std::vector<char*> pointers;
    for (std::string& argument : arguments) pointers.push_back(argument.data());
    app.parse(static_cast<int>(pointers.size()), pointers.data());
  } catch (const CLI::ParseError& error) {
    return ReportParseError(app, error, std::cout, std::cerr);
  }
  try {
    if (run->parsed()) return RunRunCommand(run_options, std::cout, std::cerr, isatty(STDERR_FILENO) != 0);
    if (validate->parsed()) return RunValidateCommand(validate_options, std::cout, std::cerr);
    if (apps->parsed()) return RunAppsCommand(apps_options, std::cout);
    if (replay->parsed()) return RunReplayCommand(replay_options, std::cout, std::cerr);
    if (new_command->parsed()) return RunNewCommand(new_options, std::cout, std::cerr);
    if (view->parsed()) return RunViewCommand(view_options, std::cout, std::cerr);
    if (compare->parsed()) return RunCompareCommand(compare_options, std::cout, std::cerr);
    if (grade->parsed()) return RunGradeCommand(grade_options, std::cout, std::cerr);
    if (gradescope->parsed()) return RunGradescopeCommand(gradescope_options, std::cout, std::cerr);
    if (swarm->parsed()) return RunSwarmCommand(swarm_options, std::cout, std::cerr);
    if (search->parsed()) {
      return RunSearchCommand(search_options, std::cout, std::cerr, isatty(STDERR_FILENO) != 0);
    }
    if (assignment->parsed()) return RunAssignmentCommand(assignment_options, std::cout, std::cerr);
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "syrof: internal error: " << error.what() << "\n";
    return 1;
  }
}
