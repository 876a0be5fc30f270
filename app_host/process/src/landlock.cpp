// Landlock through its system calls (include/syrof/process/landlock.h).
#include "syrof/process/landlock.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace syrof::process {
namespace {

// The kernel's uapi (linux/landlock.h), ABI 1 to 7, under our own names:
// Debian 12's header defines ABI 1-2 and an attribute struct without the
// net and scope fields. Each bit's ABI is in its comment.
constexpr uint64_t kFsExecute = 1ull << 0;      // 1
constexpr uint64_t kFsWriteFile = 1ull << 1;    // 1
constexpr uint64_t kFsReadFile = 1ull << 2;     // 1
constexpr uint64_t kFsReadDir = 1ull << 3;      // 1
constexpr uint64_t kFsRemoveDir = 1ull << 4;    // 1
constexpr uint64_t kFsRemoveFile = 1ull << 5;   // 1
constexpr uint64_t kFsMakeChar = 1ull << 6;     // 1
constexpr uint64_t kFsMakeDir = 1ull << 7;      // 1
constexpr uint64_t kFsMakeReg = 1ull << 8;      // 1
constexpr uint64_t kFsMakeSock = 1ull << 9;     // 1
constexpr uint64_t kFsMakeFifo = 1ull << 10;    // 1
constexpr uint64_t kFsMakeBlock = 1ull << 11;   // 1
constexpr uint64_t kFsMakeSym = 1ull << 12;     // 1
constexpr uint64_t kFsRefer = 1ull << 13;       // 2
constexpr uint64_t kFsTruncate = 1ull << 14;    // 3
constexpr uint64_t kFsIoctlDev = 1ull << 15;    // 5
constexpr uint64_t kNetBindTcp = 1ull << 0;     // 4
constexpr uint64_t kNetConnectTcp = 1ull << 1;  // 4
constexpr uint64_t kScopeAbstractUnixSocket = 1ull << 0;  // 6
constexpr uint64_t kScopeSignal = 1ull << 1;              // 6

constexpr uint32_t kCreateRulesetVersion = 1u << 0;
constexpr int kRulePathBeneath = 1;

struct RulesetAttr {
  uint64_t handled_access_fs;
  uint64_t handled_access_net;  // ABI 4
  uint64_t scoped;              // ABI 6
};

struct __attribute__((packed)) PathBeneathAttr {
  uint64_t allowed_access;
  int32_t parent_fd;
};

// The file system rights the kernel of `abi` knows.
uint64_t HandledFs(int abi) {
  uint64_t rights = kFsExecute | kFsWriteFile | kFsReadFile | kFsReadDir | kFsRemoveDir | kFsRemoveFile |
                    kFsMakeChar | kFsMakeDir | kFsMakeReg | kFsMakeSock | kFsMakeFifo | kFsMakeBlock |
                    kFsMakeSym;
  if (abi >= 2) rights |= kFsRefer;
  if (abi >= 3) rights |= kFsTruncate;
  if (abi >= 5) rights |= kFsIoctlDev;
  return rights;
}

// The rights that apply to a file itself (a rule on a file may hold no other).
constexpr uint64_t kFileRights = kFsExecute | kFsWriteFile | kFsReadFile | kFsTruncate | kFsIoctlDev;

}  // namespace

int LandlockAbi() {
  // Tests of what happens on a kernel without Landlock set this; it can only
  // take a layer away, never add one.
  if (const char* pretend = std::getenv("SYROF_PRETEND_NO_LANDLOCK"); pretend != nullptr && pretend[0] == '1') {
    errno = ENOSYS;
    return 0;
  }
  const long abi = syscall(SYS_landlock_create_ruleset, nullptr, 0, kCreateRulesetVersion);
  return abi < 0 ? 0 : static_cast<int>(abi);
}

FileRuleset::~FileRuleset() { Close(); }

void FileRuleset::Close() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

bool FileRuleset::Create() {
  abi_ = LandlockAbi();
  if (abi_ <= 0) {
    error_ = std::string("Landlock is not available on this kernel (") + std::strerror(errno) + ")";
    return false;
  }
  handled_fs_ = HandledFs(abi_);
  RulesetAttr attr{};
  attr.handled_access_fs = handled_fs_;
  size_t size = sizeof(attr.handled_access_fs);
  if (abi_ >= 4) {
    attr.handled_access_net = kNetBindTcp | kNetConnectTcp;
    size = offsetof(RulesetAttr, scoped);
  }
  if (abi_ >= 6) {
    attr.scoped = kScopeAbstractUnixSocket | kScopeSignal;
    size = sizeof(attr);
  }
  fd_ = static_cast<int>(syscall(SYS_landlock_create_ruleset, &attr, size, 0u));
  if (fd_ < 0) {
    error_ = std::string("cannot create a Landlock ruleset: ") + std::strerror(errno);
    return false;
  }
  return true;
}

bool FileRuleset::Allow(const std::string& path, Access access) { return AddRule(path, access, false); }

bool FileRuleset::AllowPlainFile(const std::string& path, Access access) { return AddRule(path, access, true); }

bool FileRuleset::AddRule(const std::string& path, Access access, bool plain_file_only) {
  if (fd_ < 0) return false;
  const int target = open(path.c_str(), O_PATH | O_CLOEXEC | (plain_file_only ? O_NOFOLLOW : 0));
  if (target < 0) {
    if (errno == ENOENT || errno == ENOTDIR) return true;
    error_ = "cannot open " + path + " for a Landlock rule: " + std::strerror(errno);
    return false;
  }
  struct stat status {};
  const bool stated = fstat(target, &status) == 0;
  if (plain_file_only && (!stated || !S_ISREG(status.st_mode) || status.st_nlink != 1)) {
    close(target);  // a symbolic link (O_PATH|O_NOFOLLOW opens the link itself), a folder, a device, a hard link
    return true;
  }
  const bool is_file = stated && !S_ISDIR(status.st_mode);
  uint64_t rights = kFsReadFile | kFsReadDir;
  if (access == Access::kReadExecute) rights |= kFsExecute;
  if (access == Access::kReadWrite) rights = handled_fs_;
  rights &= handled_fs_;
  if (is_file) rights &= kFileRights;
  PathBeneathAttr beneath{rights, target};
  const long added = syscall(SYS_landlock_add_rule, fd_, kRulePathBeneath, &beneath, 0u);
  const int saved = errno;
  close(target);
  if (added != 0) {
    error_ = "Landlock refused a rule for " + path + ": " + std::strerror(saved);
    return false;
  }
  return true;
}

int FileRuleset::RestrictSelf() const noexcept {
  if (fd_ < 0) return EBADF;
  if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) return errno;
  if (syscall(SYS_landlock_restrict_self, fd_, 0u) != 0) return errno;
  return 0;
}

}  // namespace syrof::process
