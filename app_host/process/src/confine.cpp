#include "syrof/process/confine.h"

#include <fcntl.h>
#include <grp.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace syrof::process {
namespace {

bool WriteProcFile(const char* path, const char* text) {
  const int fd = open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const size_t length = strlen(text);
  const bool ok = write(fd, text, length) == static_cast<ssize_t>(length);
  const int saved = errno;
  close(fd);
  errno = saved;
  return ok;
}

int DescriptorCeiling() {
  rlimit limit{};
  return getrlimit(RLIMIT_NOFILE, &limit) == 0 && limit.rlim_max < (1u << 20) ? static_cast<int>(limit.rlim_max)
                                                                              : 1 << 20;
}

}  // namespace

bool CloseDescriptorsFrom(int first) {
  if (syscall(SYS_close_range, static_cast<unsigned>(first), ~0u, 0u) == 0) return true;
  const int most = DescriptorCeiling();
  for (int fd = first; fd < most; ++fd) close(fd);
  return false;
}

void CloseAllBut(int keep_a, int keep_b) {
  if (keep_a > keep_b) {
    const int swap = keep_a;
    keep_a = keep_b;
    keep_b = swap;
  }
  for (int fd = 3; fd < keep_a; ++fd) close(fd);
  for (int fd = keep_a + 1; fd < keep_b; ++fd) close(fd);
  CloseDescriptorsFrom(keep_b + 1);
}

bool SetLimit(int resource, rlim_t value) {
  const rlimit limit{value, value};
  return setrlimit(static_cast<__rlimit_resource>(resource), &limit) == 0;
}

int DropToNobody() {
  if (setgroups(0, nullptr) != 0 || setgid(kNobodyGid) != 0 || setuid(kNobodyUid) != 0) return errno;
  if (getuid() == 0 || geteuid() == 0) return EPERM;
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  return 0;
}

CallerIdMaps CallerIdMaps::OfCaller() {
  CallerIdMaps maps;
  snprintf(maps.uid_map, sizeof maps.uid_map, "%u %u 1\n", static_cast<unsigned>(geteuid()),
           static_cast<unsigned>(geteuid()));
  snprintf(maps.gid_map, sizeof maps.gid_map, "%u %u 1\n", static_cast<unsigned>(getegid()),
           static_cast<unsigned>(getegid()));
  return maps;
}

bool MapCallerIds(const CallerIdMaps& maps) {
  WriteProcFile("/proc/self/setgroups", "deny");
  return WriteProcFile("/proc/self/uid_map", maps.uid_map) && WriteProcFile("/proc/self/gid_map", maps.gid_map);
}

}  // namespace syrof::process
