// `syrof assignment`'s command line and everything it refuses before
// grading: --help for it and both subcommands, a missing subcommand or
// argument, a missing or malformed assignment.yaml or expected.yaml
// (exit 2 with file:line:column), an unknown --only; `new`'s name rules and
// its refusal to overwrite, and the skeleton it writes loading with its
// subjects. (Checking by grading: assignment_check_test.cpp.)
#include "assignment_command.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_support.h"
#include "syrof/assignment/assignment.h"
#include "syrof/grader/assignment_check.h"
#include "usage.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::Outcome;
using testing::ReadFile;

// `syrof assignment ARGS...` parsed as main() parses it, then run.
Outcome Assignment(std::vector<std::string> arguments) {
  return testing::ParseAndRun<AssignmentOptions>("assignment", std::move(arguments), SetupAssignmentCommand,
                                                 [](const AssignmentOptions& options, std::ostream& out,
                                                    std::ostream& err) { return RunAssignmentCommand(options, out, err); });
}

fs::path Fresh(const std::string& name) {
  return FreshDir("syrof_assignment_test_" + std::to_string(getpid()) + "_", name);
}

void Write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

TEST(AssignmentCommandTest, HelpNamesTheSubcommandsAndTheirOptions) {
  const Outcome top = Assignment({"--help"});
  EXPECT_EQ(top.status, 0);
  EXPECT_NE(top.out.find("check"), std::string::npos) << top.out;
  EXPECT_NE(top.out.find("new"), std::string::npos) << top.out;
  const Outcome check = Assignment({"check", "--help"});
  EXPECT_EQ(check.status, 0);
  for (const char* option : {"--jobs", "--only", "--out", "--build-timeout-s", "--unsafe-no-file-isolation"}) {
    EXPECT_NE(check.out.find(option), std::string::npos) << option << " missing from\n" << check.out;
  }
  const Outcome make = Assignment({"new", "--help"});
  EXPECT_EQ(make.status, 0);
  EXPECT_NE(make.out.find("--dir"), std::string::npos) << make.out;
}

TEST(AssignmentCommandTest, AMissingSubcommandOrArgumentIsAUsageError) {
  const Outcome none = Assignment({});
  EXPECT_EQ(none.status, 2);
  EXPECT_EQ(none.err, "syrof assignment: a subcommand is required: check, new\nRun with --help for more information.\n");
  const Outcome wrong = Assignment({"chek", "x"});
  EXPECT_EQ(wrong.status, 2);
  EXPECT_EQ(wrong.err,
            "syrof assignment: 'chek' is not a subcommand of syrof assignment; its subcommands are: check, new\n"
            "Run with --help for more information.\n");
  const Outcome no_dir = Assignment({"check"});
  EXPECT_EQ(no_dir.status, 2);
  EXPECT_NE(no_dir.err.find("assignment is required"), std::string::npos) << no_dir.err;
  EXPECT_EQ(Assignment({"check", SYROF_ASSIGNMENTS_DIR "/gather", "--jobs", "0"}).status, 2);
  EXPECT_EQ(Assignment({"new"}).status, 2);
}

TEST(AssignmentCommandTest, CheckWithoutAnAssignmentFileIsAUsageError) {
  const fs::path dir = Fresh("no_file");
  fs::create_directories(dir);
  const Outcome outcome = Assignment({"check", dir.string()});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_TRUE(outcome.err.starts_with("syrof assignment check: no assignment.yaml in '" + dir.string() + "'"))
      << outcome.err;
  fs::remove_all(dir);
}

TEST(AssignmentCommandTest, CheckNamesTheFileLineAndKeyOfABadAssignmentFile) {
  const fs::path dir = Fresh("bad_yaml");
  Write(dir / "assignment.yaml", "title: T\nscenaros: {}\nrubric: { goal: 100 }\n");
  const Outcome outcome = Assignment({"check", dir.string()});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_EQ(outcome.err, "syrof assignment check: " + (dir / "assignment.yaml").string() +
                             ":2:1: unknown key 'scenaros' (did you mean 'scenarios'?)\n");
  EXPECT_EQ(outcome.out, "") << "nothing graded";
  fs::remove_all(dir);
}

// A copy of the skeleton `new` writes, to break in one place.
class SkeletonTest : public ::testing::Test {
 protected:
  void SetUp() override {
    parent_ = Fresh(::testing::UnitTest::GetInstance()->current_test_info()->name());
    const Outcome made = Assignment({"new", "spread", "--dir", parent_.string()});
    ASSERT_EQ(made.status, 0) << made.err;
    dir_ = parent_ / "spread";
  }
  void TearDown() override { fs::remove_all(parent_); }
  fs::path parent_;
  fs::path dir_;
};

TEST_F(SkeletonTest, NewWritesAnAssignmentThatLoadsWithItsThreeSubjects) {
  for (const char* file : {"assignment.yaml", "README.md", "scenarios/spread_6.yaml", "hidden/spread_8_loss.yaml",
                           "search/spread_3_vote1.yaml",
                           "search/spread_3_ssync.yaml",
                           "reference/CMakeLists.txt", "reference/spread.c", "reference/expected.yaml",
                           "starter/CMakeLists.txt", "starter/spread.c", "starter/expected.yaml",
                           "broken/off_by_one/NOTE.md", "broken/off_by_one/expected.yaml",
                           "broken/off_by_one/mistake.patch"}) {
    EXPECT_TRUE(fs::is_regular_file(dir_ / file)) << file;
  }
  const grader::assignment::LoadResult loaded = grader::assignment::LoadAssignmentFile(dir_.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();
  EXPECT_EQ(loaded.assignment->public_runs.size(), 1u);
  EXPECT_EQ(loaded.assignment->hidden_runs.size(), 1u);
  std::vector<grader::CheckSubject> subjects;
  const std::optional<lab::Error> problem = grader::FindCheckSubjects(*loaded.assignment, subjects);
  ASSERT_FALSE(problem) << problem->ToString();
  ASSERT_EQ(subjects.size(), 3u);
  EXPECT_EQ(subjects[0].name, "reference");
  EXPECT_EQ(subjects[1].name, "starter");
  EXPECT_EQ(subjects[2].name, "broken/off_by_one");
  ASSERT_TRUE(subjects[2].expected.has_value());
  EXPECT_LT(subjects[2].expected->points, loaded.assignment->points);
  EXPECT_NE(ReadFile(dir_ / "reference" / "spread.c").find("SYROF_APP_DEFINE(\"spread\""), std::string::npos);
  EXPECT_NE(ReadFile(dir_ / "broken" / "off_by_one" / "mistake.patch").find("--- a/spread.c\n"), std::string::npos);
}

// The search tests assignment.yaml shows commented out load as written once
// switched on: a loss search and a schedule search, each on the scenario
// the skeleton carries. (That the reference then keeps full marks and the
// starter loses both: tests/cli/walkthrough_test.sh runs the loss search's
// block of docs/grading.md; the schedule search was checked by hand.)
TEST_F(SkeletonTest, TheCommentedSearchTestsLoadWhenSwitchedOn) {
  std::string text = ReadFile(dir_ / "assignment.yaml");
  for (const std::string line : {"# search:", "#   - { scenario: search/spread_3_vote1.yaml",
                                 "#   - { scenario: search/spread_3_ssync.yaml"}) {
    const size_t at = text.find("\n" + line);
    ASSERT_NE(at, std::string::npos) << line;
    text.erase(at + 1, 2);  // "# ", as an instructor switches a line on
  }
  Write(dir_ / "assignment.yaml", text);
  const grader::assignment::LoadResult loaded = grader::assignment::LoadAssignmentFile(dir_.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();
  const auto& tests = loaded.assignment->search_tests;
  ASSERT_EQ(tests.size(), 2u);
  EXPECT_FALSE(tests[0].activations);
  EXPECT_TRUE(tests[1].activations);
  EXPECT_EQ(tests[1].epochs, 3);
}

// The skeleton's projects go to students, as the shipped starters do: no
// hint (an instructor's path), no comment claiming one, SyROF found beneath
// the `syrof` on PATH as the comment says, and no placeholder left.
TEST_F(SkeletonTest, NewWritesProjectsThatFindSyROFThroughPathWithoutAHint) {
  for (const char* project : {"reference", "starter"}) {
    const std::string cmake = ReadFile(dir_ / project / "CMakeLists.txt");
    EXPECT_NE(cmake.find("find_package(SyROF 0.1 REQUIRED)\n"), std::string::npos) << project << ":\n" << cmake;
    EXPECT_EQ(cmake.find("The hint is"), std::string::npos) << project << ":\n" << cmake;
    EXPECT_EQ(cmake.find("HINTS"), std::string::npos) << project << ":\n" << cmake;
    EXPECT_NE(cmake.find("beneath the `syrof`\n# on your PATH"), std::string::npos) << project << ":\n" << cmake;
    EXPECT_EQ(cmake.find("{{"), std::string::npos) << project << ":\n" << cmake;
  }
}

TEST_F(SkeletonTest, NewRefusesToOverwriteAFolder) {
  Write(dir_ / "README.md", "mine\n");
  const Outcome again = Assignment({"new", "spread", "--dir", parent_.string()});
  EXPECT_EQ(again.status, 2);
  EXPECT_EQ(again.err, "syrof assignment new: " + dir_.string() +
                           " exists; nothing was written (choose another name or --dir)\n");
  EXPECT_EQ(ReadFile(dir_ / "README.md"), "mine\n");
  fs::create_directories(parent_ / "empty");
  EXPECT_EQ(Assignment({"new", "empty", "--dir", parent_.string()}).status, 2) << "even an empty folder";
  EXPECT_TRUE(fs::is_empty(parent_ / "empty"));
}

TEST_F(SkeletonTest, NewRefusesPathsAndNamesThatAreNoIdentifier) {
  for (const char* name : {"../up", "a/b", "..", "x..y"}) {
    const Outcome outcome = Assignment({"new", name, "--dir", parent_.string()});
    EXPECT_EQ(outcome.status, 2) << name;
    EXPECT_EQ(outcome.err, std::string("syrof assignment new: '") + name +
                               "' is a path, not a name; give the folder to write in with --dir\n");
  }
  const Outcome dash = Assignment({"new", "my-task", "--dir", parent_.string()});
  EXPECT_EQ(dash.status, 2);
  EXPECT_NE(dash.err.find("bad assignment name: 'my-task' may hold only letters, digits and '_', not '-'"),
            std::string::npos)
      << dash.err;
  EXPECT_FALSE(fs::exists(parent_ / "my-task"));
  EXPECT_FALSE(fs::exists(parent_.parent_path() / "up"));
}

TEST_F(SkeletonTest, CheckNamesTheFileLineAndKeyOfABadExpectedFile) {
  Write(dir_ / "broken" / "off_by_one" / "expected.yaml", "points: 50\nloses: [gaol]\n");
  const Outcome outcome = Assignment({"check", dir_.string()});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_EQ(outcome.err, "syrof assignment check: " + (dir_ / "broken/off_by_one/expected.yaml").string() +
                             ":2:9: loses[0]: unknown value 'gaol' (did you mean 'goal'?); expected one of goal, "
                             "collisions, synchrony, common_knowledge, agreement, faults\n");
}

TEST_F(SkeletonTest, CheckRefusesExpectationsThatWouldCatchNothing) {
  Write(dir_ / "starter" / "expected.yaml", "points: 100\nloses: []\n");
  const Outcome starter = Assignment({"check", dir_.string()});
  EXPECT_EQ(starter.status, 2);
  EXPECT_NE(starter.err.find("starter/expected.yaml:1:9: points: the starter is expected to get full marks"),
            std::string::npos)
      << starter.err;
  Write(dir_ / "starter" / "expected.yaml", "points: 50\nloses: [goal]\n");
  Write(dir_ / "reference" / "expected.yaml", "points: 90\nloses: [goal]\n");
  const Outcome reference = Assignment({"check", dir_.string()});
  EXPECT_EQ(reference.status, 2);
  EXPECT_NE(reference.err.find("reference/expected.yaml:1:9: points: a reference gets full marks"), std::string::npos)
      << reference.err;
}

TEST_F(SkeletonTest, CheckRefusesAMissingReferenceOrVariantFile) {
  fs::remove(dir_ / "broken" / "off_by_one" / "mistake.patch");
  const Outcome patch = Assignment({"check", dir_.string()});
  EXPECT_EQ(patch.status, 2);
  EXPECT_NE(patch.err.find("broken/off_by_one/mistake.patch: missing"), std::string::npos) << patch.err;
  fs::remove_all(dir_ / "reference");
  const Outcome reference = Assignment({"check", dir_.string()});
  EXPECT_EQ(reference.status, 2);
  EXPECT_NE(reference.err.find("/reference: no such folder"), std::string::npos) << reference.err;
}

TEST_F(SkeletonTest, CheckOnlyNamesTheSubjectsWhenItNamesNone) {
  // Before the folder too: --only takes one word each time.
  const Outcome outcome = Assignment({"check", "--only", "starter", "--only", "off_by_two", dir_.string()});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_EQ(outcome.err,
            "syrof assignment check: --only 'off_by_two' names no subject of this assignment; its subjects are: "
            "reference, starter, broken/off_by_one\n");
}

}  // namespace
}  // namespace syrof::cli
