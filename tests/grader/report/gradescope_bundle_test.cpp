// The Gradescope bundle: what goes in (the scripts, SyROF's self-contained
// folder with its programs' modes, the assignment without its reference and
// broken folders), the zip's listing,
// modes and timestamps, the same bytes from the same inputs whenever and
// wherever it is written, and the inputs it refuses.
#include "syrof/report/gradescope_bundle.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "zip_test_support.h"

namespace syrof::grader::report {
namespace {

namespace fs = std::filesystem;
using testing::ReadZip;
using testing::ZipEntry;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::string Octal(uint32_t value) {
  std::ostringstream text;
  text << std::oct << value;
  return text.str();
}

void Write(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

// An assignment folder with every kind of thing a real one holds, and a
// stand-in of SyROF's self-contained folder (the files the bundle requires
// of one, and a bundled library).
class BundleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("syrof_bundle_" + std::string(::testing::UnitTest::GetInstance()
                                                                            ->current_test_info()
                                                                            ->name()) +
                                         "_" + std::to_string(getpid()));
    fs::remove_all(root_);
    folder_ = root_ / "gather";
    Write(folder_ / "assignment.yaml", "title: Gather\n");
    Write(folder_ / "README.md", "# Gather\n");
    Write(folder_ / "scenarios/gather_6.yaml", "name: gather_6\n");
    Write(folder_ / "hidden/gather_10_crash.yaml", "name: crash\n");
    Write(folder_ / "starter/app.c", "int x;\n");
    Write(folder_ / "reference/gather.c", "solution\n");
    Write(folder_ / "broken/uses_rand/gather.c", "rand\n");
    Write(folder_ / ".git/config", "[core]\n");
    Write(folder_ / ".hidden_notes", "notes\n");
    syrof_ = root_ / "prefix";
    for (const char* file : {"bin/syrof", "libexec/syrof/syrof-app-host", "lib/libsyrof_app.so.1",
                             "lib/cmake/SyROF/SyROFConfig.cmake", "include/syrof/app.h", "gradescope-prefix.txt"}) {
      Write(syrof_ / file, std::string(file) + "\n");
    }
    fs::permissions(syrof_ / "bin/syrof", fs::perms::owner_all | fs::perms::group_read | fs::perms::others_read);
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path root_;
  fs::path folder_;
  fs::path syrof_;
};

TEST_F(BundleTest, HoldsTheScriptsSyrofAndTheAssignmentButNotItsSolutions) {
  const BundleResult result = GradescopeBundle(folder_.string(), syrof_.string());

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  std::vector<std::string> names;
  for (const BundleFile& file : result.bundle->files) names.push_back(file.name);
  EXPECT_EQ(names, (std::vector<std::string>{"assignment/README.md", "assignment/assignment.yaml",
                                             "assignment/hidden/gather_10_crash.yaml",
                                             "assignment/scenarios/gather_6.yaml", "assignment/starter/app.c",
                                             "deadline_s", "run_autograder", "setup.sh", "syrof/bin/syrof",
                                             "syrof/gradescope-prefix.txt", "syrof/include/syrof/app.h",
                                             "syrof/lib/cmake/SyROF/SyROFConfig.cmake", "syrof/lib/libsyrof_app.so.1",
                                             "syrof/libexec/syrof/syrof-app-host"}));
}

TEST_F(BundleTest, TheZipListsFoldersBeforeTheirFilesWithModesAndOneFixedTime) {
  const BundleResult result = GradescopeBundle(folder_.string(), syrof_.string());
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const fs::path zip = root_ / "autograder.zip";

  ASSERT_EQ(WriteBundleZip(*result.bundle, zip.string()), std::nullopt);

  std::string error;
  const std::vector<ZipEntry> entries = ReadZip(zip.string(), error);
  ASSERT_EQ(error, "");
  std::vector<std::string> listing;
  for (const ZipEntry& entry : entries) {
    listing.push_back(entry.name + " " + Octal(entry.mode));
    EXPECT_EQ(entry.opsys, ZIP_OPSYS_UNIX) << entry.name;
    EXPECT_EQ(entry.dos_time, 0) << entry.name;                         // 00:00:00
    EXPECT_EQ(entry.dos_date, (0 << 9) | (1 << 5) | 1) << entry.name;  // 1980-01-01
  }
  EXPECT_EQ(listing, (std::vector<std::string>{
                         "assignment/ 40755", "assignment/README.md 100644", "assignment/assignment.yaml 100644",
                         "assignment/hidden/ 40755", "assignment/hidden/gather_10_crash.yaml 100644",
                         "assignment/scenarios/ 40755", "assignment/scenarios/gather_6.yaml 100644",
                         "assignment/starter/ 40755", "assignment/starter/app.c 100644", "deadline_s 100644",
                         "run_autograder 100755",
                         "setup.sh 100755", "syrof/ 40755", "syrof/bin/ 40755", "syrof/bin/syrof 100755",
                         "syrof/gradescope-prefix.txt 100644", "syrof/include/ 40755", "syrof/include/syrof/ 40755",
                         "syrof/include/syrof/app.h 100644", "syrof/lib/ 40755", "syrof/lib/cmake/ 40755",
                         "syrof/lib/cmake/SyROF/ 40755", "syrof/lib/cmake/SyROF/SyROFConfig.cmake 100644",
                         "syrof/lib/libsyrof_app.so.1 100644", "syrof/libexec/ 40755", "syrof/libexec/syrof/ 40755",
                         "syrof/libexec/syrof/syrof-app-host 100644"}));
  EXPECT_EQ(entries[9].bytes, std::to_string(kDefaultDeadlineS) + "\n");
  EXPECT_EQ(entries[10].bytes, GradescopeRunScript());
  EXPECT_EQ(entries[11].bytes, GradescopeSetupScript());
  EXPECT_EQ(entries[14].bytes, ReadFile(syrof_ / "bin/syrof"));
  EXPECT_EQ(entries[14].method, ZIP_CM_DEFLATE);
  EXPECT_EQ(entries[2].bytes, "title: Gather\n");
}

TEST_F(BundleTest, TheSameInputsGiveTheSameBytesWhateverTheClockAndTimeZone) {
  const fs::path first = root_ / "first.zip";
  const fs::path second = root_ / "second.zip";
  const char* zone = std::getenv("TZ");
  const std::string saved = zone == nullptr ? "" : zone;

  setenv("TZ", "UTC", 1);
  tzset();
  ASSERT_EQ(WriteBundleZip(*GradescopeBundle(folder_.string(), syrof_.string()).bundle, first.string()), std::nullopt);
  // Newer files, another time zone, a folder listed in another order.
  fs::last_write_time(folder_ / "README.md", fs::file_time_type::clock::now() + std::chrono::hours(30));
  fs::remove(folder_ / "scenarios/gather_6.yaml");
  Write(folder_ / "scenarios/gather_6.yaml", "name: gather_6\n");
  setenv("TZ", "Pacific/Kiritimati", 1);
  tzset();
  ASSERT_EQ(WriteBundleZip(*GradescopeBundle(folder_.string(), syrof_.string()).bundle, second.string()),
            std::nullopt);

  if (saved.empty()) {
    unsetenv("TZ");
  } else {
    setenv("TZ", saved.c_str(), 1);
  }
  tzset();
  EXPECT_EQ(ReadFile(first), ReadFile(second));
  EXPECT_FALSE(ReadFile(first).empty());
}

TEST_F(BundleTest, RefusesAFolderWithoutAnAssignment) {
  const BundleResult result = GradescopeBundle((folder_ / "scenarios").string(), syrof_.string());

  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error->ToString(), (folder_ / "scenarios").string() + " holds no assignment.yaml");
}

TEST_F(BundleTest, RefusesASyrofFolderThatLacksWhatGradingNeeds) {
  fs::remove(syrof_ / "libexec/syrof/syrof-app-host");
  const BundleResult no_host = GradescopeBundle(folder_.string(), syrof_.string());
  const BundleResult nowhere = GradescopeBundle(folder_.string(), (root_ / "nowhere").string());

  ASSERT_FALSE(no_host.ok());
  EXPECT_EQ(no_host.error->ToString(), syrof_.string() +
                                           " is not a self-contained SyROF for Gradescope: it has no "
                                           "libexec/syrof/syrof-app-host (make one with `make gradescope-prefix`)");
  ASSERT_FALSE(nowhere.ok());
  EXPECT_EQ(nowhere.error->ToString(), (root_ / "nowhere").string() +
                                           " is not a self-contained SyROF for Gradescope: it has no bin/syrof (make "
                                           "one with `make gradescope-prefix`)");
}

TEST_F(BundleTest, RefusesASymbolicLinkInTheSyrofFolder) {
  fs::create_symlink("/etc/passwd", syrof_ / "lib/passwd");

  const BundleResult result = GradescopeBundle(folder_.string(), syrof_.string());

  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error->ToString(),
            (syrof_ / "lib/passwd").string() + " is a symbolic link; a bundle holds only regular files and folders");
}

TEST_F(BundleTest, RefusesASymbolicLinkInTheAssignment) {
  fs::create_symlink("/etc/passwd", folder_ / "scenarios/passwd");

  const BundleResult result = GradescopeBundle(folder_.string(), syrof_.string());

  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error->ToString(),
            (folder_ / "scenarios/passwd").string() + " is a symbolic link; a bundle holds only regular files and folders");
}

TEST_F(BundleTest, AZipThatCannotBeWrittenSaysWhere) {
  const BundleResult result = GradescopeBundle(folder_.string(), syrof_.string());
  ASSERT_TRUE(result.ok());

  const std::optional<lab::Error> problem = WriteBundleZip(*result.bundle, "/nonexistent/folder/autograder.zip");

  ASSERT_TRUE(problem);
  // Then libzip's words, which differ between its versions.
  EXPECT_TRUE(problem->ToString().starts_with("cannot write /nonexistent/folder/autograder.zip: ")) << *problem;
  EXPECT_FALSE(fs::exists("/nonexistent/folder/autograder.zip"));
}

TEST(GradescopeScriptsTest, TheScriptsTakeTheirRootFromAutograderRoot) {
  for (const std::string& script : {GradescopeSetupScript(), GradescopeRunScript()}) {
    EXPECT_TRUE(script.starts_with("#!/usr/bin/env bash\n"));
    EXPECT_NE(script.find("root=\"${AUTOGRADER_ROOT:-/autograder}\""), std::string::npos);
  }
  EXPECT_NE(GradescopeRunScript().find("syrof=\"$root/source/syrof/bin/syrof\""), std::string::npos);
  EXPECT_NE(GradescopeRunScript().find(
                "\"$syrof\" grade \"$root/submission\" --assignment \"$root/source/assignment\" --out \"$out\""),
            std::string::npos);
  EXPECT_NE(GradescopeRunScript().find("--deadline-s \"${deadline_s:-480}\" --gradescope-results \"$results/results.json\""),
            std::string::npos);
  // Nothing of SyROF from apt: only the tools a submission's build needs.
  EXPECT_EQ(GradescopeSetupScript().find(".deb"), std::string::npos);
  EXPECT_NE(GradescopeSetupScript().find("apt-get install -y -q --no-install-recommends"), std::string::npos);
}

}  // namespace
}  // namespace syrof::grader::report
