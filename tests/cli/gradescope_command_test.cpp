// `syrof gradescope`: the assignment found by name or path, the
// self-contained SyROF folder found beside the build (or refused with what
// to do: missing, incomplete, older than the build), and the zip written
// with that folder under syrof/ (modes kept) and the assignment (hidden
// sets, not the reference or broken folders).
// gradescope_autograder_test.cpp runs the bundle's scripts.
#include "gradescope_command.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
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

// A folder shaped as scripts/gradescope-prefix.sh makes one (its contents
// stand-ins): what GradescopeBundle requires of it, and a bundled library.
void MakeSyrofFolder(const fs::path& folder) {
  for (const char* file : {"bin/syrof", "libexec/syrof/syrof-app-host", "lib/libsyrof_app.so.1",
                           "lib/cmake/SyROF/SyROFConfig.cmake", "include/syrof/app.h", "gradescope-prefix.txt",
                           "lib/syrof-deps/libyaml-cpp.so.0.7"}) {
    fs::create_directories((folder / file).parent_path());
    std::ofstream(folder / file) << file << "\n";
  }
  for (const char* program : {"bin/syrof", "libexec/syrof/syrof-app-host"}) {
    fs::permissions(folder / program, fs::perms::owner_exec, fs::perm_options::add);
  }
}

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
    prefix_ = dir_ / "prefix";
    MakeSyrofFolder(prefix_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  fs::path prefix_;
};

TEST_F(GradescopeCommandTest, WritesTheBundleOfAnAssignmentFolder) {
  GradescopeOptions options;
  options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  options.output = (dir_ / "autograder.zip").string();
  options.prefix = prefix_.string();

  const Outcome outcome = Gradescope(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("wrote " + options.output), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("'Gather the swarm': 5 public and 3 hidden tests"), std::string::npos) << outcome.out;
  std::string error;
  std::set<std::string> names;
  for (const auto& entry : grader::report::testing::ReadZip(options.output, error)) names.insert(entry.name);
  ASSERT_EQ(error, "");
  for (const std::string& name : std::vector<std::string>{
           "setup.sh", "run_autograder", "syrof/bin/syrof", "syrof/libexec/syrof/syrof-app-host",
           "syrof/lib/libsyrof_app.so.1", "syrof/lib/syrof-deps/libyaml-cpp.so.0.7",
           "syrof/lib/cmake/SyROF/SyROFConfig.cmake", "syrof/include/syrof/app.h", "syrof/gradescope-prefix.txt",
           "assignment/assignment.yaml", "assignment/README.md", "assignment/scenarios/gather_6.yaml",
           "assignment/hidden/gather_10_join.yaml"}) {
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
  options.prefix = prefix_.string();
  options.per_student_seeds = true;
  unsetenv("SYROF_COURSE_SECRET");
  const Outcome refused = Gradescope(options);
  EXPECT_EQ(refused.status, 2);
  EXPECT_EQ(refused.err, "syrof gradescope: --per-student-seeds needs the course secret: set SYROF_COURSE_SECRET or "
                         "give --course-secret-file FILE\n");
  EXPECT_FALSE(fs::exists(options.output));
  setenv("SYROF_COURSE_SECRET", "short", 1);
  const Outcome too_short = Gradescope(options);
  unsetenv("SYROF_COURSE_SECRET");
  EXPECT_EQ(too_short.status, 2);
  EXPECT_EQ(too_short.err, "syrof gradescope: SYROF_COURSE_SECRET: the course secret has 5 bytes; it needs at least "
                           "16 (for example `openssl rand -hex 32`)\n");
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
  const std::string gather = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";

  EXPECT_EQ(FindAssignmentFolder(gather + "/assignment.yaml").folder, gather);
  EXPECT_EQ(FindAssignmentFolder(gather).folder, gather);
  const fs::path here = fs::current_path();
  fs::current_path(fs::path(SYROF_ASSIGNMENTS_DIR).parent_path());
  const FolderOrError by_name = FindAssignmentFolder("gather");
  const FolderOrError missing = FindAssignmentFolder("no_such_assignment");
  fs::current_path(here);
  EXPECT_EQ(by_name.folder, "assignments/gather");
  EXPECT_FALSE(by_name.error);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error->ToString(),
            "no assignment 'no_such_assignment': neither a folder nor ./assignments/no_such_assignment/assignment.yaml");
  const FolderOrError no_file = FindAssignmentFolder(dir_.string());
  ASSERT_FALSE(no_file.ok());
  EXPECT_EQ(no_file.error->ToString(), dir_.string() + " holds no assignment.yaml");
  const FolderOrError nowhere = FindAssignmentFolder((dir_ / "nowhere").string());
  ASSERT_FALSE(nowhere.ok());
  EXPECT_EQ(nowhere.error->ToString(), "no assignment at " + (dir_ / "nowhere").string());
}

TEST_F(GradescopeCommandTest, RefusesAnAssignmentThatIsNotThereOrDoesNotLoad) {
  GradescopeOptions options;
  options.prefix = prefix_.string();
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

TEST_F(GradescopeCommandTest, FindsTheSyrofFolderBesideTheBuildOrSaysHowToMakeOne) {
  const fs::path build = dir_ / "build";
  fs::create_directories(build / "bin");
  const FolderOrError none = PrefixBesideBuild(build);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error->ToString(), "no self-contained SyROF for Gradescope beside this build (" +
                                        (build / "gradescope-prefix").string() +
                                        "): make it with `make gradescope-prefix` (scripts/gradescope-prefix.sh), or "
                                        "give one with --prefix DIR");

  std::ofstream(build / "bin/syrof") << "the build's syrof\n";
  MakeSyrofFolder(build / "gradescope-prefix");
  const FolderOrError made = PrefixBesideBuild(build);
  ASSERT_TRUE(made.ok()) << made.error->ToString();
  EXPECT_EQ(*made.folder, (build / "gradescope-prefix").string());

  // The build's syrof rebuilt after the folder was made: the folder would ship the old one.
  fs::last_write_time(build / "bin/syrof",
                      fs::last_write_time(build / "gradescope-prefix/gradescope-prefix.txt") + std::chrono::seconds(5));
  const FolderOrError old = PrefixBesideBuild(build);
  ASSERT_FALSE(old.ok());
  EXPECT_EQ(old.error->ToString(), (build / "gradescope-prefix").string() + " is older than " +
                                       (build / "bin/syrof").string() + ": make it again with `make gradescope-prefix`");
}

TEST_F(GradescopeCommandTest, KeepsTheProgramsExecutableInTheZip) {
  GradescopeOptions options;
  options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  options.output = (dir_ / "autograder.zip").string();
  options.prefix = prefix_.string();
  ASSERT_EQ(Gradescope(options).status, 0);
  const fs::path unpacked = dir_ / "unpacked";
  ASSERT_EQ(grader::report::testing::ExtractZip(options.output, unpacked), "");
  for (const char* program : {"syrof/bin/syrof", "syrof/libexec/syrof/syrof-app-host", "setup.sh", "run_autograder"}) {
    EXPECT_NE(fs::status(unpacked / program).permissions() & fs::perms::owner_exec, fs::perms::none) << program;
  }
  EXPECT_EQ(fs::status(unpacked / "syrof/lib/libsyrof_app.so.1").permissions() & fs::perms::owner_exec,
            fs::perms::none);
}

TEST_F(GradescopeCommandTest, RefusesAFolderThatIsNotASelfContainedSyrof) {
  GradescopeOptions options;
  options.assignment = std::string(SYROF_ASSIGNMENTS_DIR) + "/gather";
  options.output = (dir_ / "autograder.zip").string();
  options.prefix = prefix_.string();
  fs::remove(prefix_ / "gradescope-prefix.txt");  // not made (and checked) by scripts/gradescope-prefix.sh

  const Outcome unchecked = Gradescope(options);
  options.prefix = (dir_ / "nowhere").string();
  const Outcome missing = Gradescope(options);

  EXPECT_EQ(unchecked.status, 2);
  EXPECT_NE(unchecked.err.find("is not a self-contained SyROF for Gradescope: it has no gradescope-prefix.txt"),
            std::string::npos)
      << unchecked.err;
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("it has no bin/syrof"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(options.output));
}

}  // namespace
}  // namespace syrof::cli
