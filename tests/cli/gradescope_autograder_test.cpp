// The Gradescope bundle's scripts, run as Gradescope runs them, in a
// temporary folder laid out as Gradescope lays out /autograder
// (AUTOGRADER_ROOT): source/ holds the zip's contents (extracted with their
// modes), submission/ the student's files, results/ what Gradescope reads.
// The bundle's SyROF is this build's, made self-contained once for the
// suite by scripts/gradescope-prefix.sh, so the programs that grade are the
// bundle's own (source/syrof/bin/syrof), with no build tree on PATH.
// setup.sh runs without its apt-get step (SYROF_SKIP_INSTALL=1). A grader
// that fails is tested with a stand-in source/syrof/bin/syrof.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "gradescope_command.h"
#include "syrof/grader/student_seeds.h"
#include "zip_test_support.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::FreshDir;
using testing::ReadFile;

// Runs `command` with bash; its exit status, and its output in `output`.
int Shell(const std::string& command, std::string& output) {
  const std::string line = "bash -c '" + command + "' 2>&1";
  FILE* pipe = popen(line.c_str(), "r");
  output.clear();
  char buffer[4096];
  size_t got = 0;
  while (pipe != nullptr && (got = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, got);
  const int status = pipe == nullptr ? -1 : pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// PATH for the scripts: the system's programs only, no build tree.
constexpr const char* kSystemPath = "/usr/bin:/bin";

// Replaces the bundle's syrof with a shell script.
void StandInSyrof(const fs::path& root, const std::string& script) {
  const fs::path syrof = root / "source/syrof/bin/syrof";
  fs::remove(syrof);
  std::ofstream(syrof) << "#!/bin/sh\n" << script;
  fs::permissions(syrof, fs::perms::owner_all);
}

// /autograder as Gradescope lays it out, under a temporary root.
class AutograderTest : public ::testing::Test {
 protected:
  // This build as the bundle's self-contained SyROF, made once.
  static void SetUpTestSuite() {
    prefix_ = fs::temp_directory_path() / ("syrof_autograder_prefix_" + std::to_string(getpid()));
    const fs::path build = fs::path(SYROF_EXECUTABLE).parent_path().parent_path();
    const fs::path script = fs::path(SYROF_ASSIGNMENTS_DIR).parent_path() / "scripts/gradescope-prefix.sh";
    std::string output;
    prefix_status_ = Shell("bash " + script.string() + " " + build.string() + " " + prefix_.string(), output);
    prefix_output_ = output;
    if (prefix_status_ != 0) return;
    // gather's bundle, written once: each test unzips it afresh.
    GradescopeOptions options;
    options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
    options.output = (prefix_.string() + ".zip");
    options.prefix = prefix_.string();
    std::ostringstream out;
    std::ostringstream err;
    if (RunGradescopeCommand(options, out, err) != 0) {
      prefix_status_ = -1;
      prefix_output_ = "syrof gradescope: " + err.str();
    }
  }
  static void TearDownTestSuite() {
    fs::remove_all(prefix_);
    fs::remove(prefix_.string() + ".zip");
  }

  void SetUp() override {
    ASSERT_EQ(prefix_status_, 0) << "scripts/gradescope-prefix.sh failed: " << prefix_output_;
    root_ = FreshDir("syrof_autograder_", ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                                              std::string("_") + std::to_string(getpid()));
    fs::create_directories(root_ / "source");
    fs::create_directories(root_ / "submission");
    fs::create_directories(root_ / "results");
    ASSERT_EQ(grader::report::testing::ExtractZip(prefix_.string() + ".zip", root_ / "source"), "");
  }
  void TearDown() override { fs::remove_all(root_); }

  // Runs one of the bundle's scripts from source/ with only the system's programs on PATH.
  int Script(const std::string& script, std::string& output, const std::string& environment = "") {
    return Shell("cd " + root_.string() + " && AUTOGRADER_ROOT=" + root_.string() + " PATH=" + kSystemPath + " " +
                     environment + " ./source/" + script,
                 output);
  }

  json Results() { return json::parse(ReadFile(root_ / "results/results.json"), nullptr, false); }

  fs::path root_;
  static inline fs::path prefix_;
  static inline int prefix_status_ = -1;
  static inline std::string prefix_output_;
};

TEST_F(AutograderTest, TheScriptsAreExecutableAfterUnzipping) {
  for (const std::string script : {"setup.sh", "run_autograder", "syrof/bin/syrof", "syrof/libexec/syrof/syrof-app-host"}) {
    const fs::perms perms = fs::status(root_ / "source" / script).permissions();
    EXPECT_NE(perms & fs::perms::owner_exec, fs::perms::none) << script;
  }
  EXPECT_EQ(fs::status(root_ / "source/assignment/assignment.yaml").permissions() & fs::perms::owner_exec,
            fs::perms::none);
}

TEST_F(AutograderTest, SetupChecksThatTheBundledSyrofRunsHere) {
  std::string output;
  EXPECT_EQ(Script("setup.sh", output, "SYROF_SKIP_INSTALL=1"), 0) << output;
  EXPECT_NE(output.find("is ready to grade " + (root_ / "source/assignment").string()), std::string::npos) << output;

  // A syrof that cannot run here (as on an image whose glibc is too old) stops it, saying why.
  StandInSyrof(root_, "echo 'version `GLIBC_2.35` not found' >&2\nexit 127\n");
  EXPECT_NE(Script("setup.sh", output, "SYROF_SKIP_INSTALL=1"), 0);
  EXPECT_NE(output.find("the bundled syrof does not run on this image: version `GLIBC_2.35` not found"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("it needs glibc 2.35 or newer"), std::string::npos) << output;

  fs::remove(root_ / "source/syrof/bin/syrof");
  EXPECT_NE(Script("setup.sh", output, "SYROF_SKIP_INSTALL=1"), 0);
  EXPECT_NE(output.find("no syrof/bin/syrof in"), std::string::npos) << output;
}

// What the bundle's programs load comes from the bundle, glibc and the C++
// runtime: nothing of SyROF's Debian dependencies from the system.
TEST_F(AutograderTest, TheBundledProgramsLoadTheirLibrariesFromTheBundle) {
  const fs::path syrof = root_ / "source/syrof";
  for (const char* program : {"bin/syrof", "libexec/syrof/syrof-app-host"}) {
    std::string output;
    ASSERT_EQ(Shell("env -i ldd " + (syrof / program).string(), output), 0) << output;
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
      if (line.find("=>") == std::string::npos || line.find("linux-vdso") != std::string::npos) continue;
      const bool system = line.find("libc.so.6") != std::string::npos || line.find("libm.so.6") != std::string::npos ||
                          line.find("libstdc++.so.6") != std::string::npos ||
                          line.find("libgcc_s.so.1") != std::string::npos;
      if (!system) {
        EXPECT_NE(line.find(syrof.string()), std::string::npos) << program << ": " << line;
      }
    }
  }
}

TEST_F(AutograderTest, AGraderThatFailsStillGivesAResultsJsonWithTheReason) {
  StandInSyrof(root_, "echo 'syrof: internal error' >&2\nexit 3\n");

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;

  const json results = Results();
  ASSERT_TRUE(results.is_object()) << ReadFile(root_ / "results/results.json");
  EXPECT_EQ(results["score"], 0);
  EXPECT_NE(results["output"].get<std::string>().find("syrof grade stopped with status 3 and wrote no results.json"),
            std::string::npos)
      << results["output"];
  EXPECT_EQ(results["tests"], json::array());
}

TEST_F(AutograderTest, GradesTheReferenceToFullMarks) {
  fs::copy(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather/reference", root_ / "submission",
           fs::copy_options::recursive);
  fs::remove(root_ / "submission/expected.yaml");

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;

  const json results = Results();
  ASSERT_TRUE(results.is_object()) << output;
  EXPECT_EQ(results["score"], 100.0) << results.dump(2);
  ASSERT_EQ(results["tests"].size(), 8u);
  int hidden = 0;
  for (const json& test : results["tests"]) {
    EXPECT_EQ(test["status"], "passed") << test.dump(2);
    hidden += test["visibility"] == "after_due_date" ? 1 : 0;
  }
  EXPECT_EQ(hidden, 3);
  EXPECT_TRUE(fs::exists(root_ / "results/grade/report.html"));
  EXPECT_TRUE(fs::exists(root_ / "results/grade/junit.xml"));
}

TEST_F(AutograderTest, ASubmissionThatDoesNotBuildScoresZeroAndSaysWhy) {
  std::ofstream(root_ / "submission/gather.c") << "this is not C\n";

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;

  const json results = Results();
  ASSERT_TRUE(results.is_object()) << output;
  EXPECT_EQ(results["score"], 0.0);
  EXPECT_NE(results["output"].get<std::string>().find("did not build"), std::string::npos) << results["output"];
}

// The bundle's deadline (syrof gradescope --deadline-s): no test starts
// after it; each says why it was not run, and results.json stays Gradescope's.
TEST_F(AutograderTest, TestsPastTheBundlesDeadlineAreNotRunAndSaySo) {
  EXPECT_EQ(ReadFile(root_ / "source/deadline_s"), "480\n") << "the default: 8 of Gradescope's 10 minutes";
  fs::copy(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather/reference", root_ / "submission",
           fs::copy_options::recursive);
  fs::remove(root_ / "submission/expected.yaml");
  // A deadline of 1 s (the least the bundle's file takes), and a build that
  // outlasts it for sure: a cached compile of the reference can take less.
  std::ofstream(root_ / "submission/CMakeLists.txt", std::ios::app) << "execute_process(COMMAND sleep 2)\n";
  std::ofstream(root_ / "source/deadline_s") << "1\n";

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;

  const json results = Results();
  ASSERT_TRUE(results.is_object()) << output;
  EXPECT_EQ(results["score"], 0.0);
  ASSERT_EQ(results["tests"].size(), 8u) << results.dump(2);
  for (const json& test : results["tests"]) {
    EXPECT_NE(test["output"].get<std::string>().find("not run: grading reached its deadline"), std::string::npos)
        << test.dump(2);
  }
}

// assignment.yaml's per-test visibility and its cap on hidden-test
// feedback, read from Gradescope's metadata: the first submission sees the
// hidden tests at once (`gradescope: visible`), the third only after the due date.
TEST_F(AutograderTest, TheHiddenFeedbackCapCountsTheStudentsSubmissions) {
  const fs::path yaml = root_ / "source/assignment/assignment.yaml";
  std::string text = ReadFile(yaml);
  text.replace(text.find("points: 100\n"), 12, "points: 100\nhidden_feedback_submissions: 1\n");
  text.replace(text.find("time_limit_s: 120 }"), 19, "time_limit_s: 120, gradescope: visible }");
  std::ofstream(yaml) << text;
  fs::copy(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather/reference", root_ / "submission",
           fs::copy_options::recursive);
  fs::remove(root_ / "submission/expected.yaml");
  const auto hidden_visibility = [this](const std::string& previous) {
    std::ofstream(root_ / "submission_metadata.json")
        << R"({"users": [{"id": 7}], "previous_submissions": [)" << previous << "]}";
    std::string output;
    EXPECT_EQ(Script("run_autograder", output), 0) << output;
    const json results = Results();  // (a range-for over Results()["tests"] would read a destroyed temporary)
    EXPECT_EQ(results["tests"].size(), 8u) << output;
    std::set<std::string> seen;
    for (const json& test : results["tests"]) {
      if (test["name"].get<std::string>().starts_with("gather_10_join/")) seen.insert(test["visibility"].get<std::string>());
    }
    return seen;
  };

  EXPECT_EQ(hidden_visibility(""), std::set<std::string>{"visible"});
  EXPECT_EQ(hidden_visibility("{}, {}"), std::set<std::string>{"after_due_date"});
  EXPECT_NE(Results()["output"].get<std::string>().find("given for your first 1 submissions, and this is submission 3"),
            std::string::npos)
      << Results()["output"];
}

// The attacks of tests/grader/hostile_build_test.cpp through the bundle, as
// a student would send them to Gradescope: the hidden scenarios sit under
// /autograder/source, the results under /autograder/results.
TEST_F(AutograderTest, ABuildThatPrintsAHiddenScenarioGetsNoneOfItsText) {
  const fs::path hidden = root_ / "source/assignment/hidden/gather_10_join.yaml";
  ASSERT_TRUE(fs::exists(hidden));
  std::ofstream(root_ / "submission/CMakeLists.txt")
      << "cmake_minimum_required(VERSION 3.16)\nproject(steal LANGUAGES C)\n"
      << "file(READ " << hidden.string() << " text)\nmessage(FATAL_ERROR \"${text}\")\n";

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;

  const std::string results = ReadFile(root_ / "results/results.json");
  EXPECT_EQ(results.find("robot 9 is switched on"), std::string::npos) << results;
  EXPECT_NE(results.find("Permission denied"), std::string::npos) << results;
  EXPECT_EQ(Results()["score"], 0.0);
}

TEST_F(AutograderTest, ABuildThatRewritesTheAssignmentAndTheResultsChangesNothing) {
  fs::copy(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather/reference", root_ / "submission",
           fs::copy_options::recursive);
  fs::remove(root_ / "submission/expected.yaml");
  const fs::path yaml = root_ / "source/assignment/assignment.yaml";
  const std::string before = ReadFile(yaml);
  std::string cmake = ReadFile(root_ / "submission/CMakeLists.txt");
  cmake.insert(cmake.find("find_package"), "execute_process(COMMAND sh -c \"echo 'points: 1000' > " + yaml.string() +
                                               "; echo '{\\\"score\\\": 100}' > " +
                                               (root_ / "results/results.json").string() + "\")\n");
  std::ofstream(root_ / "submission/CMakeLists.txt") << cmake;

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;

  EXPECT_EQ(ReadFile(yaml), before);
  const json results = Results();
  ASSERT_TRUE(results.is_object()) << output;
  EXPECT_EQ(results["score"], 100.0) << "graded as usual: " << results.dump(2);
  EXPECT_EQ(results["tests"].size(), 8u) << "the grader's own results.json, not the build's";
}

// Hidden seeds per student: a bundle made with --per-student-seeds holds
// the course secret, and run_autograder derives the hidden seeds from the
// users in Gradescope's submission_metadata.json.
constexpr const char* kCourseSecret = "0123456789abcdef-course-secret";

class PerStudentAutograderTest : public AutograderTest {
 protected:
  void SetUp() override {
    AutograderTest::SetUp();
    std::ofstream(root_ / "secret") << kCourseSecret << "\n";
    GradescopeOptions options;
    options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
    options.output = (root_ / "autograder_seeds.zip").string();
    options.prefix = prefix_.string();
    options.per_student_seeds = true;
    options.course_secret_file = (root_ / "secret").string();
    std::ostringstream out;
    std::ostringstream err;
    ASSERT_EQ(RunGradescopeCommand(options, out, err), 0) << err.str();
    fs::remove_all(root_ / "source");
    fs::create_directories(root_ / "source");
    ASSERT_EQ(grader::report::testing::ExtractZip(options.output, root_ / "source"), "");
    ASSERT_TRUE(fs::exists(root_ / "source/course_secret"));
  }
};

TEST_F(PerStudentAutograderTest, RunAutograderPassesTheMetadataAndTheSecretToSyrofGrade) {
  StandInSyrof(root_, "echo \"$@\" > " + (root_ / "arguments").string() + "\nexit 3\n");

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;
  const std::string arguments = ReadFile(root_ / "arguments");
  EXPECT_NE(arguments.find("--gradescope-metadata " + (root_ / "submission_metadata.json").string()),
            std::string::npos)
      << arguments;
  EXPECT_NE(arguments.find("--course-secret-file " + (root_ / "source/course_secret").string()), std::string::npos)
      << arguments;
  EXPECT_NE(arguments.find("--deadline-s 480 --gradescope-results " + (root_ / "results/results.json").string()),
            std::string::npos)
      << arguments;
}

TEST_F(PerStudentAutograderTest, WithoutMetadataGradingStopsAndSaysSo) {
  fs::copy(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather/reference", root_ / "submission",
           fs::copy_options::recursive);
  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;
  EXPECT_NE(output.find("cannot read Gradescope's submission metadata"), std::string::npos) << output;
  const json results = Results();
  ASSERT_TRUE(results.is_object()) << output;
  EXPECT_EQ(results["score"], 0);
  EXPECT_NE(results["output"].get<std::string>().find("syrof grade stopped with status 2"), std::string::npos)
      << results["output"];

  std::ofstream(root_ / "submission_metadata.json") << "{\"users\": [{\"email\": \"a@example.edu\"}]}";
  EXPECT_EQ(Script("run_autograder", output), 0) << output;
  EXPECT_NE(output.find("users[0] has no 'id'"), std::string::npos) << output;
  EXPECT_EQ(Results()["score"], 0);
}

TEST_F(PerStudentAutograderTest, AGroupsHiddenTestsUseSeedsDerivedFromItsUsers) {
  fs::copy(std::string(SYROF_ASSIGNMENTS_DIR) + "/gather/reference", root_ / "submission",
           fs::copy_options::recursive);
  fs::remove(root_ / "submission/expected.yaml");
  std::ofstream(root_ / "submission_metadata.json")
      << R"({"id": 77, "users": [{"email": "b@example.edu", "id": 4343, "name": "B"},)"
      << R"( {"email": "a@example.edu", "id": 4242, "name": "A"}]})";

  std::string output;
  EXPECT_EQ(Script("run_autograder", output), 0) << output;

  const json results = Results();
  ASSERT_TRUE(results.is_object()) << output;
  // Not full marks: gather's reference misses its goal on some unlisted
  // seeds of gather_10_join (docs/grading.md, "Hidden seeds per student").
  std::vector<std::string> hidden;
  std::vector<std::string> visible;
  for (const json& test : results["tests"]) {
    (test["visibility"] == "after_due_date" ? hidden : visible).push_back(test["name"]);
    if (test["visibility"] == "visible") {
      EXPECT_EQ(test["status"], "passed") << test.dump(2);
    }
  }
  EXPECT_EQ(visible, (std::vector<std::string>{"gather_6/seed-1", "gather_6/seed-2", "gather_6/seed-3",
                                               "gather_8_loss/seed-4", "gather_8_loss/seed-5"}))
      << "public seeds stay as listed";
  ASSERT_EQ(hidden.size(), 3u) << results.dump(2);
  for (uint64_t index = 0; index < 3; ++index) {
    EXPECT_EQ(hidden[index], "gather_10_join/seed-" + std::to_string(grader::DeriveSeed(
                                                          kCourseSecret, "Gather the swarm", "gather_10_join",
                                                          "4242+4343", index)));
  }
  EXPECT_EQ(results.dump().find(kCourseSecret), std::string::npos) << "the secret is in no output";
  const std::string grade_json = ReadFile(root_ / "results/grade/grade.json");
  EXPECT_NE(grade_json.find("\"seed_student\": \"4242+4343\""), std::string::npos);
  EXPECT_EQ(grade_json.find(kCourseSecret), std::string::npos);
}

}  // namespace
}  // namespace syrof::cli
