// TmpfsHolder: a folder bounded in size that only a child entering the
// holder's namespaces sees (the grader's bound on what a build writes).
#include "syrof/process/tmpfs_holder.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>
#include <vector>

#include "syrof/process/fd.h"
#include "syrof/process/spawn.h"

namespace syrof::process {
namespace {

namespace fs = std::filesystem;

fs::path FreshFolder() {
  const fs::path folder = fs::temp_directory_path() / ("syrof_tmpfs_holder_" + std::to_string(getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

// Bytes written to `path` until the first refusal, and that refusal's errno.
std::pair<size_t, int> WriteUntilRefused(const fs::path& path, size_t wanted) {
  Fd file(open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (!file.valid()) return {0, errno};
  const std::vector<char> block(64 << 10, 'x');
  size_t written = 0;
  while (written < wanted) {
    const ssize_t put = write(file.get(), block.data(), block.size());
    if (put < 0) return {written, errno};
    written += static_cast<size_t>(put);
  }
  return {written, 0};
}

TEST(TmpfsHolderTest, TheFolderIsBoundedSeenOnlyInsideAndGoneWithTheHolder) {
  const fs::path folder = FreshFolder();
  fs::path view;
  {
    const TmpfsHolder holder(folder, 1 << 20, 64);
    if (!holder.ok()) GTEST_SKIP() << "this kernel refuses: " << holder.problem();
    view = holder.view();
    EXPECT_TRUE(view.string().starts_with("/proc/")) << view;
    EXPECT_EQ(holder.size_bytes(), 1u << 20);
    EXPECT_FALSE(holder.Full(64 << 10));

    // 4 MiB asked, the bound's 1 MiB taken: ENOSPC, and the folder is full.
    const auto [written, refusal] = WriteUntilRefused(view / "big", 4 << 20);
    EXPECT_EQ(refusal, ENOSPC);
    EXPECT_LE(written, size_t{1} << 20);
    EXPECT_GE(written, size_t{1} << 19);
    EXPECT_TRUE(holder.Full(64 << 10));
    // The caller's own view of the folder: the mount is not there.
    EXPECT_FALSE(fs::exists(folder / "big"));

    // A child entering the holder's namespaces sees the file at the folder.
    fs::permissions(view, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                              fs::perms::others_read | fs::perms::others_exec);
    fs::permissions(view / "big", fs::perms::owner_read | fs::perms::owner_write | fs::perms::others_read);
    int ends[2];
    ASSERT_EQ(pipe2(ends, O_CLOEXEC), 0);
    Fd read_end(ends[0]);
    Fd write_end(ends[1]);
    Command command;
    command.argv = {"/bin/sh", "-c", "wc -c < " + (folder / "big").string()};
    command.environment = {"PATH=/usr/bin:/bin"};
    command.descriptors = {{1, write_end.get()}, {2, write_end.get()}};
    Sandbox sandbox;
    sandbox.drop_to_nobody = geteuid() == 0;
    sandbox.enter_user_namespace = holder.user_ns();
    sandbox.enter_mount_namespace = holder.mount_ns();
    Child child = Spawn(command, sandbox);
    write_end.Reset();
    ASSERT_TRUE(child.started());
    std::string output;
    char buffer[256];
    for (ssize_t got; (got = read(read_end.get(), buffer, sizeof buffer)) != 0;) {
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) break;
      output.append(buffer, static_cast<size_t>(got));
    }
    EXPECT_EQ(child.Reap().code, 0) << output;
    EXPECT_EQ(output, std::to_string(written) + "\n");
  }
  // The holder is gone, and the tmpfs with it.
  EXPECT_FALSE(fs::exists(view));
  EXPECT_TRUE(fs::is_empty(folder));
  fs::remove_all(folder);
}

TEST(TmpfsHolderTest, AFolderThatIsNotThereIsNamedAsTheStepRefused) {
  const TmpfsHolder holder("/nonexistent/syrof/folder", 1 << 20, 64);
  EXPECT_FALSE(holder.ok());
  EXPECT_EQ(holder.problem(), "tmpfs mount refused: No such file or directory");
}

}  // namespace
}  // namespace syrof::process
