// The `syrof` command line's usage errors: option ranges said in words, and
// an unknown subcommand named as such with the list of real ones; exit 2.
#include "usage.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <sstream>
#include <string>

#include "apps_command.h"
#include "replay_command.h"
#include "run_command.h"
#include "swarm_command.h"
#include "syrof/lab/scenario/scenario.h"
#include "validate_command.h"

namespace syrof::cli {
namespace {

// The `syrof` command as main() sets it up.
struct Command {
  CLI::App app{"syrof"};
  RunOptions run;
  ValidateOptions validate;
  AppsOptions apps;
  ReplayOptions replay;
  SwarmOptions swarm;
  Command() {
    app.require_subcommand(1);
    SetupRunCommand(app, run);
    SetupValidateCommand(app, validate);
    SetupAppsCommand(app, apps);
    SetupReplayCommand(app, replay);
    SetupSwarmCommand(app, swarm);
  }
};

struct Report {
  int status = -1;
  std::string err;
};

// Parses `line` (without the program name); on a parse error returns what
// ReportParseError prints and returns.
Report Parse(const std::string& line) {
  Command command;
  try {
    command.app.parse(line, false);
  } catch (const CLI::ParseError& error) {
    std::ostringstream out, err;
    const int status = ReportParseError(command.app, error, out, err);
    return Report{status, err.str()};
  }
  return Report{0, ""};
}

TEST(UsageTest, RobotsZeroSaysAtLeastOne) {
  const Report report = Parse("run s.yaml --robots 0");
  EXPECT_EQ(report.status, 2);
  EXPECT_NE(report.err.find("--robots: must be at least 1, not 0"), std::string::npos) << report.err;
  EXPECT_LT(report.err.size(), 200u) << report.err;  // not CLI11's 300-digit range
}

TEST(UsageTest, RobotsAboveTheLoadersMaximumSaysTheMaximum) {
  const int max = lab::scenario::MaxRobots();
  const Report report = Parse("run s.yaml --robots " + std::to_string(max + 1));
  EXPECT_EQ(report.status, 2);
  EXPECT_NE(report.err.find("must be at most " + std::to_string(max)), std::string::npos) << report.err;
  EXPECT_EQ(Parse("run s.yaml --robots " + std::to_string(max)).status, 0);
}

TEST(UsageTest, RobotsThatAreNotAWholeNumberAreRefused) {
  const Report report = Parse("run s.yaml --robots 2.5");
  EXPECT_EQ(report.status, 2);
  EXPECT_NE(report.err.find("--robots: must be a whole number from 1 to"), std::string::npos) << report.err;
}

TEST(UsageTest, ThreadsBelowOneAboveTheMaximumOrNotWholeAreRefused) {
  const Report zero = Parse("run s.yaml --threads 0");
  EXPECT_EQ(zero.status, 2);
  EXPECT_NE(zero.err.find("--threads: must be at least 1 thread, not 0"), std::string::npos) << zero.err;
  const Report absurd = Parse("run s.yaml --threads 1000");
  EXPECT_EQ(absurd.status, 2);
  EXPECT_NE(absurd.err.find("--threads: must be at most 64 threads"), std::string::npos) << absurd.err;
  const Report fraction = Parse("run s.yaml --threads 1.5");
  EXPECT_EQ(fraction.status, 2);
  EXPECT_NE(fraction.err.find("--threads: must be a whole number of threads from 1 to 64, not '1.5'"),
            std::string::npos)
      << fraction.err;
  EXPECT_EQ(Parse("run s.yaml --threads 64").status, 0);
  EXPECT_EQ(Parse("run s.yaml --threads 2").status, 0);
}

// `syrof run` and `syrof swarm` say the same (swarm printed CLI11's
// 300-digit range).
TEST(UsageTest, DurationZeroOrNegativeSaysMoreThanZero) {
  for (const std::string command : {"run", "swarm"}) {
    for (const std::string value : {"0", "-1", "-0.5"}) {
      const Report report = Parse(command + " s.yaml --duration " + value);
      EXPECT_EQ(report.status, 2) << command << " " << value;
      EXPECT_NE(report.err.find("--duration: must be more than 0 seconds, not " + value), std::string::npos)
          << report.err;
      EXPECT_LT(report.err.size(), 200u) << report.err;
    }
  }
}

TEST(UsageTest, DurationAboveADaySaysTheMaximum) {
  const Report report = Parse("run s.yaml --duration 86401");
  EXPECT_EQ(report.status, 2);
  EXPECT_NE(report.err.find("--duration: must be at most 86400 seconds"), std::string::npos) << report.err;
  EXPECT_EQ(Parse("run s.yaml --duration 0.5").status, 0);
}

// The stress's own options without its seed are refused (they were ignored).
TEST(UsageTest, StressOptionsWithoutTheSeedAreRefused) {
  for (const std::string option : {"--stress-rate 2", "--stress-late 0.2", "--stress-cpu-quota 500"}) {
    const Report report = Parse("swarm s.yaml " + option);
    EXPECT_EQ(report.status, 2) << option;
    EXPECT_NE(report.err.find("requires --stress"), std::string::npos) << report.err;
    EXPECT_EQ(Parse("swarm s.yaml --stress 7 " + option).status, 0) << option;
  }
}

TEST(UsageTest, UnknownSubcommandIsNamedWithTheRealOnes) {
  const Report report = Parse("frobnicate");
  EXPECT_EQ(report.status, 2);
  EXPECT_NE(report.err.find("'frobnicate' is not a syrof subcommand"), std::string::npos) << report.err;
  EXPECT_NE(report.err.find("run, validate, apps, replay"), std::string::npos) << report.err;
  EXPECT_EQ(report.err.find("A subcommand is required"), std::string::npos) << report.err;
}

TEST(UsageTest, MissingSubcommandListsThem) {
  const Report report = Parse("");
  EXPECT_EQ(report.status, 2);
  EXPECT_NE(report.err.find("a subcommand is required: run, validate, apps, replay"), std::string::npos)
      << report.err;
}

// A wrong option and no scenario: the option is named (CLI11 said
// only "scenario is required").
TEST(UsageTest, AnUnknownOptionIsNamedBeforeAMissingArgument) {
  for (const std::string command : {"run", "swarm", "validate"}) {
    const Report report = Parse(command + " --sead");
    EXPECT_EQ(report.status, 2) << command;
    EXPECT_NE(report.err.find("syrof " + command + ": unknown option '--sead'"), std::string::npos) << report.err;
    EXPECT_EQ(report.err.find("is required"), std::string::npos) << report.err;
  }
  const Report missing = Parse("run");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("scenario is required"), std::string::npos) << missing.err;
}

// After the scenario, a wrong option or a second word is named with the
// command (CLI11 said "The following argument was not expected").
TEST(UsageTest, AWordTheCommandDoesNotTakeIsNamedWithTheCommand) {
  const Report option = Parse("run s.yaml --bogus");
  EXPECT_EQ(option.status, 2);
  EXPECT_NE(option.err.find("syrof run: unknown option '--bogus'"), std::string::npos) << option.err;
  const Report extra = Parse("apps extra");
  EXPECT_EQ(extra.status, 2);
  EXPECT_NE(extra.err.find("syrof apps: unexpected argument 'extra'"), std::string::npos) << extra.err;
  EXPECT_EQ(extra.err.find("was not expected"), std::string::npos) << extra.err;
}

TEST(UsageTest, HelpIsNotAnError) { EXPECT_EQ(Parse("--help").status, 0); }

// The built command prints the same (main wires ReportParseError).
std::string StderrOf(const std::string& arguments, int& status) {
  const std::string line = std::string(SYROF_EXECUTABLE) + " " + arguments + " 2>&1 >/dev/null";
  FILE* pipe = popen(line.c_str(), "r");
  std::string text;
  std::array<char, 256> buffer{};
  while (pipe != nullptr && fgets(buffer.data(), buffer.size(), pipe) != nullptr) text += buffer.data();
  status = pipe == nullptr ? -1 : WEXITSTATUS(pclose(pipe));
  return text;
}

TEST(UsageTest, TheExecutableSaysTheSame) {
  int status = 0;
  std::string err = StderrOf("frobnicate", status);
  EXPECT_EQ(status, 2);
  EXPECT_NE(err.find("'frobnicate' is not a syrof subcommand; the subcommands are: run, validate, apps, replay, view, compare, new"),
            std::string::npos)
      << err;
  err = StderrOf(std::string("run ") + SYROF_SCENARIOS_DIR + "/idle.yaml --robots 0", status);
  EXPECT_EQ(status, 2);
  EXPECT_NE(err.find("--robots: must be at least 1, not 0"), std::string::npos) << err;
}

}  // namespace
}  // namespace syrof::cli
