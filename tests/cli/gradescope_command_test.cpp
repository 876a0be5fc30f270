// `syrof gradescope`: the assignment found by name or path, the package
// found beside the build or refused with what to do, and the zip written
// with the assignment (hidden sets, not the reference or broken folders).
// gradescope_autograder_test.cpp runs the bundle's scripts.
#include "gradescope_command.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "cli_test_support.h"
#include "zip_test_support.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::Outcome;

constexpr const char* kDebHead = "!<arch>\ndebian-binary   0           0     0     100644  4         `\n2.0\n";

Outcome Gradescope(const GradescopeOptions& options) {
  std::ostringstream out;
  std::ostringstream err;
  const int status = RunGradescopeCommand(options, out, err);
  return {status, out.str(), err.str()};
}

class GradescopeCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = FreshDir("syrof_gradescope_", ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                                             std::string("_") + std::to_string(getpid()));
    fs::create_directories(dir_);
    deb_ = dir_ / ("syrof_" + std::string(SYROF_VERSION) + "_amd64.deb");
    std::ofstream(deb_, std::ios::binary) << kDebHead;
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  fs::path deb_;
};

TEST_F(GradescopeCommandTest, WritesTheBundleOfAnAssignmentFolder) {
  GradescopeOptions options;
  options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  options.output = (dir_ / "autograder.zip").string();
  options.deb = deb_.string();

  const Outcome outcome = Gradescope(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("wrote " + options.output), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("'Gather the swarm': 5 public and 3 hidden tests"), std::string::npos) << outcome.out;
  std::string error;
  std::set<std::string> names;
  for (const auto& entry : grader::report::testing::ReadZip(options.output, error)) names.insert(entry.name);
  ASSERT_EQ(error, "");
  for (const std::string& name : std::vector<std::string>{
           "setup.sh", "run_autograder", deb_.filename().string(), "assignment/assignment.yaml", "assignment/README.md",
           "assignment/scenarios/gather_6.yaml", "assignment/hidden/gather_10_join.yaml"}) {
    EXPECT_TRUE(names.contains(name)) << name;
  }
  for (const std::string& name : names) {
    EXPECT_FALSE(name.starts_with("assignment/reference")) << name;
    EXPECT_FALSE(name.starts_with("assignment/broken")) << name;
  }
}

TEST_F(GradescopeCommandTest, PerStudentSeedsPutTheCourseSecretInTheBundleOrRefuseWithoutOne) {
  GradescopeOptions options;
  options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  options.output = (dir_ / "autograder.zip").string();
  options.deb = deb_.string();
  options.per_student_seeds = true;
  unsetenv("SYROF_COURSE_SECRET");
  const Outcome refused = Gradescope(options);
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("--per-student-seeds needs the course secret"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(options.output));

  std::ofstream(dir_ / "secret") << "0123456789abcdef-course-secret\n";
  options.course_secret_file = (dir_ / "secret").string();
  const Outcome outcome = Gradescope(options);
  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("keep this zip private"), std::string::npos) << outcome.out;
  std::string error;
  std::string secret;
  for (const auto& entry : grader::report::testing::ReadZip(options.output, error)) {
    if (entry.name == "course_secret") secret = entry.bytes;
  }
  EXPECT_EQ(secret, "0123456789abcdef-course-secret\n");

  // Without the flag the bundle holds no secret.
  options.per_student_seeds = false;
  options.course_secret_file.clear();
  ASSERT_EQ(Gradescope(options).status, 0);
  for (const auto& entry : grader::report::testing::ReadZip(options.output, error)) {
    EXPECT_NE(entry.name, "course_secret");
  }
}

TEST_F(GradescopeCommandTest, FindsAnAssignmentByItsFileOrByNameUnderAssignments) {
  std::string error;
  const std::string gather = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";

  EXPECT_EQ(FindAssignmentFolder(gather + "/assignment.yaml", error), gather);
  EXPECT_EQ(FindAssignmentFolder(gather, error), gather);
  const fs::path here = fs::current_path();
  fs::current_path(fs::path(SYROF_ASSIGNMENTS_DIR).parent_path());
  EXPECT_EQ(FindAssignmentFolder("gather", error), "assignments/gather");
  fs::current_path(here);
}

TEST_F(GradescopeCommandTest, RefusesAnAssignmentThatIsNotThereOrDoesNotLoad) {
  GradescopeOptions options;
  options.deb = deb_.string();
  options.output = (dir_ / "autograder.zip").string();
  options.assignment = "no_such_assignment";
  const Outcome missing = Gradescope(options);

  fs::create_directories(dir_ / "bad");
  std::ofstream(dir_ / "bad/assignment.yaml") << "title: Bad\npoints: 100\n";
  options.assignment = (dir_ / "bad").string();
  const Outcome bad = Gradescope(options);

  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("no assignment 'no_such_assignment'"), std::string::npos) << missing.err;
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("the assignment does not load: "), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("assignment.yaml:"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(options.output));
}

TEST_F(GradescopeCommandTest, FindsThePackageBesideTheBuildOrSaysHowToMakeOne) {
  const fs::path build = dir_ / "build";
  fs::create_directories(build);
  std::string error;

  EXPECT_EQ(PackageBesideBuild(build, error), "");
  EXPECT_NE(error.find("no Debian package of SyROF"), std::string::npos) << error;
  EXPECT_NE(error.find("make package"), std::string::npos) << error;
  EXPECT_NE(error.find("--deb FILE"), std::string::npos) << error;

  const fs::path deb = build / ("syrof_" + std::string(SYROF_VERSION) + "_amd64.deb");
  fs::copy_file(deb_, deb);
  std::ofstream(build / "syrof_0.0.1_amd64.deb") << kDebHead;  // another version: not this build's
  error.clear();
  EXPECT_EQ(PackageBesideBuild(build, error), deb.string()) << error;

  std::ofstream(build / ("syrof_" + std::string(SYROF_VERSION) + "_arm64.deb")) << kDebHead;
  EXPECT_EQ(PackageBesideBuild(build, error), "");
  EXPECT_NE(error.find("choose one with --deb FILE"), std::string::npos) << error;
}

TEST_F(GradescopeCommandTest, RefusesAPackageThatIsNotOne) {
  GradescopeOptions options;
  options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  options.output = (dir_ / "autograder.zip").string();
  options.deb = (dir_ / "syrof_notes.txt").string();
  std::ofstream(options.deb) << "hello\n";

  const Outcome outcome = Gradescope(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("must be named syrof_<version>_<arch>.deb"), std::string::npos) << outcome.err;
}

}  // namespace
}  // namespace syrof::cli
