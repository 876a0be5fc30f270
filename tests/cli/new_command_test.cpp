// `syrof new`: the name rules, a folder that is not empty left alone, and the
// files written with the name, the language and the package hint filled in.
// (Building and running the project: new_project_test.sh.)
#include "new_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include "cli_test_support.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::Outcome;
using testing::ReadFile;

fs::path TempDir(const std::string& name) {
  const fs::path dir = FreshDir("syrof_new_test_", name);
  return dir;
}

Outcome New(const NewOptions& options) {
  std::ostringstream out, err;
  const int status = RunNewCommand(options, out, err);
  return Outcome{status, out.str(), err.str()};
}

TEST(CheckProjectName, AcceptsCIdentifiers) {
  EXPECT_EQ(CheckProjectName("myapp"), std::nullopt);
  EXPECT_EQ(CheckProjectName("_flock2"), std::nullopt);
  EXPECT_EQ(CheckProjectName("Swarm_App"), std::nullopt);
}

TEST(CheckProjectName, RefusesWhatIsNoIdentifierWithTheReason) {
  auto why = [](const std::string& name) {
    const std::optional<lab::Error> problem = CheckProjectName(name);
    EXPECT_TRUE(problem) << name;
    return problem ? problem->ToString() : std::string("(accepted)");
  };
  EXPECT_EQ(why(""), "the name is empty");
  EXPECT_EQ(why("2fast"), "'2fast' must start with a letter or '_' (it names a C library and a CMake target)");
  EXPECT_EQ(why("my-app"),
            "'my-app' may hold only letters, digits and '_', not '-' (it names a C library and a CMake target)");
  EXPECT_EQ(why("../evil"), "'../evil' must start with a letter or '_' (it names a C library and a CMake target)");
  EXPECT_EQ(why("a/b"), "'a/b' may hold only letters, digits and '_', not '/' (it names a C library and a CMake target)");
  EXPECT_EQ(why(std::string(65, 'a')), "'" + std::string(65, 'a') + "' is 65 characters long; at most 64");
  EXPECT_EQ(why("test"), "'test' is a target name CMake reserves; choose another");
}

TEST(NewCommandTest, WritesACProjectWithTheNameAndTheHintFilledIn) {
  NewOptions options;
  options.name = "flock";
  options.dir = TempDir("c").string();
  options.package_dir = "/opt/syrof build/lib/cmake/SyROF";

  const Outcome outcome = New(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  const fs::path dir = options.dir;
  for (const char* file : {"app.c", "CMakeLists.txt", "scenario.yaml", "README.md", ".gitignore"}) {
    EXPECT_TRUE(fs::is_regular_file(dir / file)) << file;
  }
  EXPECT_FALSE(fs::exists(dir / "app.cpp"));
  const std::string cmake = ReadFile(dir / "CMakeLists.txt");
  EXPECT_NE(cmake.find("project(flock LANGUAGES C)"), std::string::npos) << cmake;
  EXPECT_NE(cmake.find("find_package(SyROF 0.1 REQUIRED HINTS \"/opt/syrof build/lib/cmake/SyROF\")"),
            std::string::npos)
      << cmake;
  EXPECT_NE(cmake.find("The hint is where `syrof new` found SyROF"), std::string::npos) << cmake;
  EXPECT_NE(cmake.find("syrof_add_app(flock app.c)"), std::string::npos) << cmake;
  EXPECT_NE(ReadFile(dir / "scenario.yaml").find("library: build/libflock.so"), std::string::npos);
  // The scenario shows the app's parameter, which the app reads.
  EXPECT_NE(ReadFile(dir / "scenario.yaml").find("params: { radius_m: 1.0 }"), std::string::npos);
  EXPECT_NE(ReadFile(dir / "app.c").find("syrofAppParameter(\"radius_m\", &radius_m)"), std::string::npos);
  EXPECT_NE(ReadFile(dir / "app.c").find("SYROF_APP_DEFINE(\"flock\""), std::string::npos);
  for (const char* file : {"app.c", "CMakeLists.txt", "scenario.yaml", "README.md"}) {
    EXPECT_EQ(ReadFile(dir / file).find("{{"), std::string::npos) << file << " keeps a placeholder";
  }
  EXPECT_NE(outcome.out.find("cmake -S . -B build && cmake --build build"), std::string::npos) << outcome.out;
}

TEST(NewCommandTest, WritesACppProject) {
  NewOptions options;
  options.name = "flock";
  options.lang = "cpp";
  options.dir = TempDir("cpp").string();
  options.package_dir = "";

  const Outcome outcome = New(options);

  ASSERT_EQ(outcome.status, 0) << outcome.err;
  const std::string cmake = ReadFile(fs::path(options.dir) / "CMakeLists.txt");
  EXPECT_NE(cmake.find("project(flock LANGUAGES CXX)"), std::string::npos) << cmake;
  EXPECT_NE(cmake.find("find_package(SyROF 0.1 REQUIRED)"), std::string::npos) << cmake;  // no hint known
  EXPECT_EQ(cmake.find("hint is"), std::string::npos) << "no comment about a hint it lacks:\n" << cmake;
  EXPECT_NE(cmake.find("syrof_add_app(flock app.cpp)"), std::string::npos) << cmake;
  EXPECT_TRUE(fs::is_regular_file(fs::path(options.dir) / "app.cpp"));
  EXPECT_NE(outcome.out.find("-DSyROF_DIR="), std::string::npos) << outcome.out;
}

TEST(NewCommandTest, AFolderThatIsNotEmptyIsLeftAlone) {
  const fs::path dir = TempDir("taken");
  fs::create_directories(dir);
  std::ofstream(dir / "notes.txt") << "mine\n";
  NewOptions options;
  options.name = "flock";
  options.dir = dir.string();

  const Outcome outcome = New(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("exists and is not empty; nothing was written"), std::string::npos) << outcome.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(NewCommandTest, AnEmptyFolderIsUsed) {
  const fs::path dir = TempDir("empty");
  fs::create_directories(dir);
  NewOptions options;
  options.name = "flock";
  options.dir = dir.string();

  EXPECT_EQ(New(options).status, 0);
  EXPECT_TRUE(fs::is_regular_file(dir / "app.c"));
}

TEST(NewCommandTest, ABadNameWritesNothing) {
  const fs::path dir = TempDir("bad_name");
  NewOptions options;
  options.name = "my-app";
  options.dir = dir.string();

  const Outcome outcome = New(options);

  EXPECT_EQ(outcome.status, 2);
  EXPECT_NE(outcome.err.find("syrof new: bad app name: 'my-app'"), std::string::npos) << outcome.err;
  EXPECT_FALSE(fs::exists(dir));
}

TEST(SyROFPackageDir, FindsABuildTreeOrAnInstallation) {
  const fs::path root = TempDir("package_dir");
  fs::create_directories(root / "build" / "bin");
  std::ofstream(root / "build" / "SyROFConfig.cmake") << "\n";
  fs::create_directories(root / "usr" / "bin");
  fs::create_directories(root / "usr" / "lib" / "cmake" / "SyROF");
  std::ofstream(root / "usr" / "lib" / "cmake" / "SyROF" / "SyROFConfig.cmake") << "\n";
  fs::create_directories(root / "elsewhere" / "bin");

  EXPECT_EQ(SyROFPackageDir(root / "build" / "bin" / "syrof"), (root / "build").string());
  EXPECT_EQ(SyROFPackageDir(root / "usr" / "bin" / "syrof"), (root / "usr" / "lib" / "cmake" / "SyROF").string());
  EXPECT_EQ(SyROFPackageDir(root / "elsewhere" / "bin" / "syrof"), "");
}

}  // namespace
}  // namespace syrof::cli
