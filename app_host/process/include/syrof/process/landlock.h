// Landlock, the kernel's file-access sandbox for unprivileged processes
// (docs/app_host.md and docs/grading.md, "Threat model"), through its three
// system calls. Debian 12's headers define only ABI 1-2; this file defines
// what later ABIs add and asks the kernel which one it has.
//
// A FileRuleset names what a process may still reach: every file access
// the kernel's ABI knows is handled (denied unless a rule allows it), TCP
// bind and connect are denied (ABI 4), and signals and abstract UNIX
// sockets are scoped to the process's own domain (ABI 6): a sandboxed
// process cannot signal or connect to anything outside its sandbox, even
// under the same uid.
//
//   FileRuleset rules;
//   if (!rules.Create()) ...                 // rules.error() says why
//   rules.Allow("/usr", Access::kReadExecute);
//   rules.Allow(copy_dir, Access::kReadWrite);
//   ... fork ...
//   child: if (rules.RestrictSelf() != 0) _exit(...);   // async-signal-safe
//
// The ruleset is built in the parent (paths, allocation) and applied in a
// child between fork and exec with two system calls.
#pragma once

#include <string>

namespace syrof::process {

/// The Landlock ABI version of the running kernel: 0 when it has none (too
/// old, or Landlock not enabled at boot), or when SYROF_PRETEND_NO_LANDLOCK=1
/// (tests of the refusal).
int LandlockAbi();

class FileRuleset {
 public:
  enum class Access {
    kRead,         ///< read files and list folders
    kReadExecute,  ///< also execute files
    kReadWrite,    ///< everything beneath: create, write, remove, execute
  };

  FileRuleset() = default;
  ~FileRuleset();
  FileRuleset(const FileRuleset&) = delete;
  FileRuleset& operator=(const FileRuleset&) = delete;

  /// Creates the ruleset for the kernel's ABI. False (and error()) when
  /// Landlock is missing or refused.
  bool Create();

  /// Allows `access` beneath `path` (a folder) or on `path` (a file: only
  /// the file rights apply). A path that does not exist is skipped and
  /// returns true (a missing /lib32 is no error); false and error() when
  /// the kernel refuses the rule.
  bool Allow(const std::string& path, Access access);

  /// Allows `access` on the file `path` alone when it is a regular file with
  /// one link, opened without following a symbolic link (so no link can
  /// name a file elsewhere); anything else is left out and returns true.
  /// False and error() when the kernel refuses the rule.
  bool AllowPlainFile(const std::string& path, Access access);

  /// Applies the ruleset to the calling thread and everything it starts
  /// (no_new_privs first, as Landlock requires). Returns 0 or an errno.
  /// Only system calls: safe between fork and exec.
  int RestrictSelf() const noexcept;

  /// Closes the ruleset's descriptor (a restricted process keeps its rules).
  void Close();

  bool created() const { return fd_ >= 0; }
  int abi() const { return abi_; }
  const std::string& error() const { return error_; }

 private:
  bool AddRule(const std::string& path, Access access, bool plain_file_only);

  int fd_ = -1;
  int abi_ = 0;
  unsigned long long handled_fs_ = 0;
  std::string error_;
};

}  // namespace syrof::process
