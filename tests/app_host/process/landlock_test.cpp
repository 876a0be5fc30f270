// FileRuleset (app_host/process/src/landlock.cpp): a child restricted by a
// ruleset reads, writes and signals only what its rules allow.
#include "syrof/process/landlock.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <string>

namespace syrof::process {
namespace {

namespace fs = std::filesystem;

fs::path Fresh(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("landlock_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Runs `probe` in a child restricted by `rules`; its exit code (0-255), or
// 255 when the restriction failed.
template <typename Probe>
int InChild(const FileRuleset& rules, Probe probe) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (rules.RestrictSelf() != 0) _exit(255);
    _exit(probe());
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 254;
}

int OpenErrno(const fs::path& path, int flags) {
  const int fd = open(path.c_str(), flags | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  close(fd);
  return 0;
}

class FileRulesetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (LandlockAbi() == 0) GTEST_SKIP() << "no Landlock on this kernel";
    allowed_ = Fresh("allowed");
    readable_ = Fresh("readable");
    outside_ = Fresh("outside");
    for (const fs::path& dir : {allowed_, readable_, outside_}) std::ofstream(dir / "file.txt") << "text\n";
    ASSERT_TRUE(rules_.Create()) << rules_.error();
    ASSERT_TRUE(rules_.Allow(allowed_.string(), FileRuleset::Access::kReadWrite)) << rules_.error();
    ASSERT_TRUE(rules_.Allow(readable_.string(), FileRuleset::Access::kRead)) << rules_.error();
  }
  FileRuleset rules_;
  fs::path allowed_, readable_, outside_;
};

TEST_F(FileRulesetTest, ReadsAndWritesOnlyWhereARuleAllows) {
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(allowed_ / "file.txt", O_RDONLY); }), 0);
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(allowed_ / "new.txt", O_WRONLY | O_CREAT); }), 0);
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(readable_ / "file.txt", O_RDONLY); }), 0);
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(readable_ / "file.txt", O_WRONLY); }), EACCES);
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(readable_ / "new.txt", O_WRONLY | O_CREAT); }), EACCES);
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(outside_ / "file.txt", O_RDONLY); }), EACCES);
  EXPECT_EQ(InChild(rules_, [&] { return unlink((outside_ / "file.txt").c_str()) == 0 ? 0 : errno; }), EACCES);
  EXPECT_TRUE(fs::exists(outside_ / "file.txt"));
  EXPECT_TRUE(fs::exists(allowed_ / "new.txt"));
}

TEST_F(FileRulesetTest, AMissingPathIsSkippedAndAFileTakesOnlyFileRights) {
  EXPECT_TRUE(rules_.Allow((outside_ / "no such folder").string(), FileRuleset::Access::kRead));
  EXPECT_TRUE(rules_.Allow((outside_ / "file.txt").string(), FileRuleset::Access::kReadWrite)) << rules_.error();
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(outside_ / "file.txt", O_RDWR); }), 0);
  EXPECT_EQ(InChild(rules_, [&] { return OpenErrno(outside_ / "other.txt", O_WRONLY | O_CREAT); }), EACCES);
}

TEST_F(FileRulesetTest, SignalsStayInsideTheSandbox) {
  if (rules_.abi() < 6) GTEST_SKIP() << "signal scoping needs Landlock ABI 6";
  const pid_t bystander = fork();
  if (bystander == 0) {
    pause();
    _exit(0);
  }
  EXPECT_EQ(InChild(rules_, [&] { return kill(bystander, SIGKILL) == 0 ? 0 : errno; }), EPERM);
  EXPECT_EQ(InChild(rules_, [] { return kill(getpid(), 0) == 0 ? 0 : errno; }), 0);
  kill(bystander, SIGKILL);
  int status = 0;
  waitpid(bystander, &status, 0);
}

}  // namespace
}  // namespace syrof::process
