// What the `syrof` command says when its command line is wrong: option
// validators whose messages give the allowed range in words, and the report
// of a parse error (an unknown subcommand is named, with the list of real
// ones). Exit status 2 for every usage error.
#pragma once

#include <ostream>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace syrof::cli {

/// A whole number of robots, 1 to the scenario loader's maximum
/// (lab::scenario::MaxRobots()): "must be at least 1, not 0".
CLI::Validator RobotCountValidator();

/// Simulated seconds, more than 0 and at most lab::scenario::kMaxDurationS.
CLI::Validator DurationValidator();

/// Threads of `run --threads`: a whole number, 1 to lab::sim::kMaxThreads.
CLI::Validator ThreadsValidator();

/// Reports a parse error of `app` (the `syrof` command with its subcommands
/// set up) and returns the exit status: 0 for --help, 2 for a usage error.
/// A word where a subcommand belongs that is not one gets "'grade' is not a
/// syrof subcommand" and the list of subcommands; a missing subcommand the
/// list too; the same for a subcommand that requires its own ("'chek' is
/// not a subcommand of syrof assignment"); anything else CLI11's own message.
/// The scenario file a command line names, to load: the path as given when
/// it exists (or when no assignment has it); else the assignment's own file
/// when the path reads as the grader's replay commands write it,
/// `NAME/scenarios/FILE.yaml` from the folder holding the assignment NAME
/// (found as --assignment NAME is: grader::FindAssignment), said on `err`
/// unless `quiet`. So `syrof grade`'s "replay:" line runs as printed from a
/// student's project folder (docs/grading.md).
std::string ScenarioArgument(const std::string& given, std::string_view command, std::ostream& err, bool quiet);

int ReportParseError(const CLI::App& app, const CLI::ParseError& error, std::ostream& out, std::ostream& err);

}  // namespace syrof::cli
