#include "syrof/process/tmpfs_holder.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/prctl.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "syrof/process/confine.h"

namespace syrof::process {
namespace {

// The holder's steps, as it reports the one refused (0: none).
constexpr const char* kSteps[] = {"its holder ended", "namespaces refused", "uid map refused",
                                  "mounts not made private", "tmpfs mount refused"};
constexpr int kStepCount = static_cast<int>(sizeof kSteps / sizeof kSteps[0]);

std::string Failed(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

}  // namespace

TmpfsHolder::TmpfsHolder(const std::filesystem::path& folder, uint64_t size_bytes, uint64_t inodes)
    : size_bytes_(size_bytes) {
  int hold[2];
  int report[2];
  if (pipe2(hold, O_CLOEXEC) != 0) {
    problem_ = Failed("cannot make a pipe");
    return;
  }
  if (pipe2(report, O_CLOEXEC) != 0) {
    problem_ = Failed("cannot make a pipe");
    close(hold[0]);
    close(hold[1]);
    return;
  }
  const bool root = geteuid() == 0;
  const CallerIdMaps id_maps = CallerIdMaps::OfCaller();
  const std::string options = "size=" + std::to_string(size_bytes) + ",nr_inodes=" + std::to_string(inodes) +
                              ",mode=0700";
  const std::string target = folder.string();
  const pid_t pid = fork();
  if (pid == 0) {
    // Async-signal-safe from here (the caller may have threads).
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    CloseAllBut(hold[0], report[1]);
    int failed_step = 0;
    if (root) {
      if (unshare(CLONE_NEWNS) != 0) failed_step = 1;
    } else if (unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0) {
      failed_step = 1;
    } else if (!MapCallerIds(id_maps)) {
      failed_step = 2;
    }
    if (failed_step == 0 && mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) failed_step = 3;
    if (failed_step == 0 && mount("syrof-tmpfs", target.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, options.c_str()) != 0) {
      failed_step = 4;
    }
    const int outcome[2] = {failed_step, failed_step == 0 ? 0 : errno};
    (void)!write(report[1], outcome, sizeof outcome);
    if (failed_step != 0) _exit(1);
    // Held until the other end closes (read returns 0).
    char byte;
    while (read(hold[0], &byte, 1) != 0 && errno == EINTR) {
    }
    _exit(0);
  }
  close(hold[0]);
  close(report[1]);
  hold_ = hold[1];
  if (pid < 0) {
    problem_ = Failed("cannot start its holder");
    close(report[0]);
    return;
  }
  holder_ = pid;
  int outcome[2] = {-1, 0};
  ssize_t got;
  do {
    got = read(report[0], outcome, sizeof outcome);
  } while (got < 0 && errno == EINTR);
  close(report[0]);
  if (got != static_cast<ssize_t>(sizeof outcome) || outcome[0] != 0) {
    const bool told = got == static_cast<ssize_t>(sizeof outcome) && outcome[0] > 0 && outcome[0] < kStepCount;
    const int step = told ? outcome[0] : 0;
    problem_ = std::string(kSteps[step]) + (step != 0 ? std::string(": ") + std::strerror(outcome[1]) : "");
    return;
  }
  const std::string proc = "/proc/" + std::to_string(pid);
  mount_ns_ = open((proc + "/ns/mnt").c_str(), O_RDONLY | O_CLOEXEC);
  if (!root) user_ns_ = open((proc + "/ns/user").c_str(), O_RDONLY | O_CLOEXEC);
  view_ = std::filesystem::path(proc + "/root") / folder.relative_path();
  if (mount_ns_ < 0 || (!root && user_ns_ < 0)) {
    problem_ = Failed("cannot open its namespaces");
    return;
  }
  ok_ = true;
}

TmpfsHolder::~TmpfsHolder() {
  if (mount_ns_ >= 0) close(mount_ns_);
  if (user_ns_ >= 0) close(user_ns_);
  if (hold_ >= 0) close(hold_);  // the holder ends, and the tmpfs with it
  if (holder_ > 0) {
    int status = 0;
    while (waitpid(holder_, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

bool TmpfsHolder::Full(uint64_t margin_bytes) const {
  struct statvfs status {};
  if (statvfs(view_.c_str(), &status) != 0) return false;
  return uint64_t{status.f_bavail} * status.f_frsize < margin_bytes || status.f_favail == 0;
}

}  // namespace syrof::process
