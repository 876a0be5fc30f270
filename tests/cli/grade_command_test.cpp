// `syrof grade`'s command line: --help, and every wrong way to call it
// exiting 2 with a message that says what to do. (Grading itself is
// tests/grader/grade_test.cpp's.)
#include "grade_command.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_test_support.h"
#include "usage.h"

namespace syrof::cli {
namespace {

using testing::Outcome;

// `syrof grade ARGS...` parsed as main() parses it, then run.
Outcome Grade(std::vector<std::string> arguments) {
  return testing::ParseAndRun<GradeOptions>(
      "grade", std::move(arguments), SetupGradeCommand,
      [](const GradeOptions& options, std::ostream& out, std::ostream& err) { return RunGradeCommand(options, out, err); });
}

TEST(GradeCommandTest, HelpListsTheModesAndOptions) {
  const Outcome outcome = Grade({"--help"});
  EXPECT_EQ(outcome.status, 0);
  for (const char* option : {"--assignment", "--class", "--mix", "--public-only", "--jobs", "--out", "--shard",
                             "--build-timeout-s", "merge", "--student-seed", "--gradescope-metadata",
                             "--per-student-seeds", "--course-secret-file"}) {
    EXPECT_NE(outcome.out.find(option), std::string::npos) << option << " missing from\n" << outcome.out;
  }
}

TEST(GradeCommandTest, NothingToGradeIsAUsageError) {
  const Outcome outcome = Grade({"--assignment", "gather"});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_EQ(outcome.err,
            "syrof grade: give one of SUBMISSION_DIR, --class SUBMISSIONS_DIR or --mix SUB1 SUB2 ...\n"
            "Run with --help for more information.\n");
}

TEST(GradeCommandTest, AMissingAssignmentIsAUsageError) {
  EXPECT_EQ(Grade({SYROF_ASSIGNMENTS_DIR}).status, 2);
  const Outcome outcome = Grade({SYROF_ASSIGNMENTS_DIR, "--assignment", "no_such_assignment"});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_TRUE(outcome.err.starts_with("syrof grade: no assignment 'no_such_assignment'; looked in:\n")) << outcome.err;
}

TEST(GradeCommandTest, ASubmissionThatIsNoFolderIsAUsageError) {
  const Outcome outcome = Grade({"/no/such/folder", "--assignment", "gather"});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_EQ(outcome.err, "syrof grade: the submission '/no/such/folder' is not a folder\n");
}

TEST(GradeCommandTest, WrongOptionsAreUsageErrors) {
  EXPECT_EQ(Grade({"x", "--assignment", "gather", "--jobs", "0"}).status, 2);
  EXPECT_EQ(Grade({"x", "--assignment", "gather", "--shard", "1/2"}).status, 2) << "--shard needs --class";
  const Outcome shard = Grade({"--class", SYROF_ASSIGNMENTS_DIR, "--assignment", "gather", "--shard", "5/2"});
  EXPECT_EQ(shard.status, 2);
  EXPECT_EQ(shard.err, "syrof grade: --shard I/N needs 1 <= I <= N <= 10000, not '5/2'\n");
  EXPECT_EQ(Grade({"merge"}).status, 2) << "merge needs folders and --out";
}

TEST(GradeCommandTest, MixRefusesAnAssignmentThatIsNotMixable) {
  // circle's README fixes no message format (gather's does: it is mixable).
  const std::string circle = std::string(SYROF_ASSIGNMENTS_DIR) + "/circle";
  const Outcome outcome =
      Grade({"--mix", circle + "/reference", circle + "/reference", "--assignment", circle});
  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("assignment 'circle' is not mixable"), std::string::npos) << outcome.err;
}

// On a kernel without Landlock (pretended here) a submission's build could
// read the hidden tests: grading is refused unless the instructor says
// otherwise, and then every output says so.
TEST(GradeCommandTest, WithoutLandlockGradingIsRefusedUnlessTheInstructorSaysSo) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / ("grade_no_landlock_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "submission");
  std::ofstream(dir / "submission" / "app.c") << "this is not C\n";
  const std::string gather = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  setenv("SYROF_PRETEND_NO_LANDLOCK", "1", 1);
  const Outcome refused = Grade({(dir / "submission").string(), "--assignment", gather, "--out", (dir / "out").string()});
  const bool built_anyway = fs::exists(dir / "out" / "source");
  const Outcome unsafe = Grade({(dir / "submission").string(), "--assignment", gather, "--out", (dir / "out").string(),
                                "--public-only", "--unsafe-no-file-isolation"});
  unsetenv("SYROF_PRETEND_NO_LANDLOCK");

  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("this kernel has no Landlock"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--unsafe-no-file-isolation"), std::string::npos) << refused.err;
  EXPECT_FALSE(built_anyway) << "nothing was built";

  EXPECT_EQ(unsafe.status, 0) << unsafe.err;
  EXPECT_NE(unsafe.out.find("WARNING: no Landlock on this kernel"), std::string::npos) << unsafe.out;
  EXPECT_NE(unsafe.out.find("sandbox: build: NO FILE ISOLATION"), std::string::npos) << unsafe.out;
  std::ifstream grade_json(dir / "out" / "grade.json");
  const std::string json((std::istreambuf_iterator<char>(grade_json)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("build: NO FILE ISOLATION"), std::string::npos) << json;
}

// Per-student hidden seeds need the course secret, from a file or the
// environment, never from the command line; each refusal comes before
// anything is built.
TEST(GradeCommandTest, PerStudentSeedsWithoutAUsableSecretAreRefused) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / ("grade_student_seed_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "submission");
  std::ofstream(dir / "submission" / "app.c") << "this is not C\n";
  std::ofstream(dir / "short") << "abc\n";
  const std::string submission = (dir / "submission").string();
  const std::string gather = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  const std::string out = (dir / "out").string();
  unsetenv("SYROF_COURSE_SECRET");

  const Outcome none = Grade({submission, "--assignment", gather, "--out", out, "--student-seed", "alice"});
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.err.find("per-student hidden seeds need the course secret: set SYROF_COURSE_SECRET or give "
                          "--course-secret-file FILE"),
            std::string::npos)
      << none.err;

  const Outcome short_file = Grade({submission, "--assignment", gather, "--out", out, "--student-seed", "alice",
                                    "--course-secret-file", (dir / "short").string()});
  EXPECT_EQ(short_file.status, 2);
  EXPECT_NE(short_file.err.find("the course secret has 3 bytes; it needs at least 16"), std::string::npos)
      << short_file.err;

  setenv("SYROF_COURSE_SECRET", "short", 1);
  const Outcome short_variable = Grade({submission, "--assignment", gather, "--out", out, "--student-seed", "alice"});
  setenv("SYROF_COURSE_SECRET", "0123456789abcdef-course-secret", 1);
  const Outcome no_metadata = Grade({submission, "--assignment", gather, "--out", out, "--gradescope-metadata",
                                     (dir / "submission_metadata.json").string()});
  unsetenv("SYROF_COURSE_SECRET");
  EXPECT_EQ(short_variable.status, 2);
  EXPECT_NE(short_variable.err.find("SYROF_COURSE_SECRET: the course secret has 5 bytes"), std::string::npos)
      << short_variable.err;
  EXPECT_EQ(no_metadata.status, 2);
  EXPECT_NE(no_metadata.err.find("cannot read Gradescope's submission metadata"), std::string::npos)
      << no_metadata.err;

  const Outcome secret_alone =
      Grade({submission, "--assignment", gather, "--out", out, "--course-secret-file", (dir / "short").string()});
  EXPECT_EQ(secret_alone.status, 2);
  EXPECT_NE(secret_alone.err.find("--course-secret-file is for per-student hidden seeds"), std::string::npos)
      << secret_alone.err;
  EXPECT_EQ(Grade({"--class", submission, "--assignment", gather, "--student-seed", "alice"}).status, 2)
      << "a class takes its ids from the folders' names";
  EXPECT_EQ(Grade({submission, "--assignment", gather, "--per-student-seeds"}).status, 2) << "needs --class";
  EXPECT_FALSE(fs::exists(dir / "out" / "source")) << "nothing was built";
}

}  // namespace
}  // namespace syrof::cli
