#include "usage.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "syrof/grader/grade.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::cli {
namespace {

constexpr int kUsageError = 2;

// "run, validate, apps, replay": every subcommand of `app`, in the order
// they were added.
std::string SubcommandList(const CLI::App& app) {
  std::string list;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (!list.empty()) list += ", ";
    list += command->get_name();
  }
  return list;
}

}  // namespace

CLI::Validator RobotCountValidator() {
  const int max = lab::scenario::MaxRobots();
  return CLI::Validator(
      [max](std::string& text) -> std::string {
        int64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [rest, error] = std::from_chars(text.data(), end, value);
        if (error != std::errc() || rest != end) {
          return fmt::format("must be a whole number from 1 to {}, not '{}'", max, text);
        }
        if (value < 1) return fmt::format("must be at least 1, not {}", value);
        if (value > max) return fmt::format("must be at most {} (the largest swarm a scenario holds), not {}", max, value);
        return {};
      },
      fmt::format("1..{}", max), "ROBOTS");
}

CLI::Validator ThreadsValidator() {
  static constexpr int kMax = lab::sim::kMaxThreads;
  return CLI::Validator(
      [](std::string& text) -> std::string {
        int64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [rest, error] = std::from_chars(text.data(), end, value);
        if (error != std::errc() || rest != end) {
          return fmt::format("must be a whole number of threads from 1 to {}, not '{}'", kMax, text);
        }
        if (value < 1) return fmt::format("must be at least 1 thread, not {}", value);
        if (value > kMax) {
          return fmt::format("must be at most {} threads (more than the machine's cores only slows a run), not {}",
                             kMax, value);
        }
        return {};
      },
      fmt::format("1..{}", kMax), "THREADS");
}

CLI::Validator DurationValidator() {
  const double max = lab::scenario::kMaxDurationS;
  return CLI::Validator(
      [max](std::string& text) -> std::string {
        double value = 0;
        const char* end = text.data() + text.size();
        const auto [rest, error] = std::from_chars(text.data(), end, value);
        if (error != std::errc() || rest != end || !std::isfinite(value)) {
          return fmt::format("must be a number of seconds, more than 0 and at most {}, not '{}'", max, text);
        }
        if (!(value > 0)) return fmt::format("must be more than 0 seconds, not {}", text);
        if (value > max) return fmt::format("must be at most {} seconds (a day), not {}", max, text);
        return {};
      },
      fmt::format("(0..{}]", max), "SECONDS");
}

std::string ScenarioArgument(const std::string& given, std::string_view command, std::ostream& err, bool quiet) {
  const std::string found = grader::FindAssignmentFile(given, SYROF_SOURCE_ASSIGNMENTS_DIR);
  if (found.empty()) return given;  // the loader names the path it cannot open
  if (found != given && !quiet) fmt::print(err, "syrof {}: {} is the assignment's file {}\n", command, given, found);
  return found;
}

int ReportParseError(const CLI::App& app, const CLI::ParseError& error, std::ostream& out, std::ostream& err) {
  if (error.get_exit_code() == 0) return app.exit(error, out, err);  // --help
  const bool no_subcommand = app.get_subcommands().empty();
  if (no_subcommand && dynamic_cast<const CLI::RequiredError*>(&error) != nullptr) {
    const std::vector<std::string> words = app.remaining();
    if (!words.empty() && !words.front().starts_with("-")) {
      fmt::print(err, "syrof: '{}' is not a syrof subcommand; the subcommands are: {}\n", words.front(),
                 SubcommandList(app));
    } else if (!words.empty()) {
      fmt::print(err, "syrof: unknown option '{}'; a subcommand comes first: {}\n", words.front(),
                 SubcommandList(app));
    } else {
      fmt::print(err, "syrof: a subcommand is required: {}\n", SubcommandList(app));
    }
    fmt::print(err, "Run with --help for more information.\n");
    return kUsageError;
  }
  // A subcommand that requires its own (`syrof assignment chek`): name the
  // word it did not know, or the choices.
  const CLI::App* given = &app;
  std::string command = "syrof";
  while (!given->get_subcommands().empty()) {
    given = given->get_subcommands().front();
    command += " " + given->get_name();
  }
  if (given != &app && given->get_require_subcommand_min() > 0 &&
      dynamic_cast<const CLI::RequiredError*>(&error) != nullptr) {
    const std::vector<std::string> words = given->remaining();
    if (!words.empty() && !words.front().starts_with("-")) {
      fmt::print(err, "{}: '{}' is not a subcommand of {}; its subcommands are: {}\n", command, words.front(),
                 command, SubcommandList(*given));
    } else {
      fmt::print(err, "{}: a subcommand is required: {}\n", command, SubcommandList(*given));
    }
    fmt::print(err, "Run with --help for more information.\n");
    return kUsageError;
  }
  // A required argument missing beside an option the command does not know
  // (`syrof run --sead 3`): the unknown option is the mistake to name, not
  // the argument CLI11 checks first.
  if (given != &app && dynamic_cast<const CLI::RequiredError*>(&error) != nullptr) {
    for (const std::string& word : given->remaining()) {
      if (!word.starts_with("-") || word == "-") continue;
      fmt::print(err, "{}: unknown option '{}'\n", command, word);
      fmt::print(err, "Run with --help for more information.\n");
      return kUsageError;
    }
  }
  // A word the command does not take, after what it needs (`syrof grade .
  // --bogus`): named with the command, as above, not CLI11's bare line.
  if (given != &app && dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr) {
    const std::vector<std::string> words = given->remaining();
    if (!words.empty()) {
      const std::string& word = words.front();
      if (word.starts_with("-") && word != "-") {
        fmt::print(err, "{}: unknown option '{}'\n", command, word);
      } else {
        fmt::print(err, "{}: unexpected argument '{}'\n", command, word);
      }
      fmt::print(err, "Run with --help for more information.\n");
      return kUsageError;
    }
  }
  app.exit(error, out, err);
  return kUsageError;
}

}  // namespace syrof::cli
