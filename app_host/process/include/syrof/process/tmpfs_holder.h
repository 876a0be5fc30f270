// A folder bounded in size for a sandboxed child: a tmpfs mounted over it in
// a mount namespace of its own, held by a small process for as long as the
// TmpfsHolder lives. As root the holder makes only the mount namespace;
// otherwise a user namespace mapping the caller's own ids as well (which
// may mount a tmpfs). A child started with Sandbox::enter_user_namespace
// and enter_mount_namespace set to the holder's (spawn.h) sees the tmpfs at
// the folder; the caller reaches it through /proc/HOLDER/root (view()).
// When the holder ends (the TmpfsHolder goes), the mount and everything in
// it are gone. Nothing of it reaches the machine's other mounts: the
// namespace's mounts are private. A tmpfs lives in memory (or swap): its
// size is also what it may take of them.
//
//   process::TmpfsHolder work(folder, 512 << 20, 32768);
//   if (!work.ok()) ...                  // work.problem(): the step refused
//   sandbox.enter_user_namespace = work.user_ns();
//   sandbox.enter_mount_namespace = work.mount_ns();
//   ... the child writes below `folder`; the caller reads work.view() ...
//   if (work.Full(64 << 10)) ...         // the child reached the bound
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace syrof::process {

class TmpfsHolder {
 public:
  /// Mounts a tmpfs of `size_bytes` and at most `inodes` files and folders
  /// (a tmpfs inode takes memory its size does not count), mode 0700, over
  /// the existing folder `folder` (absolute) in the holder's namespace.
  TmpfsHolder(const std::filesystem::path& folder, uint64_t size_bytes, uint64_t inodes);
  /// Ends the holder (and the tmpfs) and reaps it.
  ~TmpfsHolder();
  TmpfsHolder(const TmpfsHolder&) = delete;
  TmpfsHolder& operator=(const TmpfsHolder&) = delete;

  bool ok() const { return ok_; }
  /// What was refused when not ok(): "namespaces refused: Operation not
  /// permitted", "tmpfs mount refused: ...", "cannot make a pipe: ...".
  const std::string& problem() const { return problem_; }
  /// The folder as the caller reaches it (/proc/HOLDER/root/FOLDER).
  const std::filesystem::path& view() const { return view_; }
  /// The holder's namespaces, open close-on-exec; -1 for the user
  /// namespace when run as root (none was made).
  int user_ns() const { return user_ns_; }
  int mount_ns() const { return mount_ns_; }
  uint64_t size_bytes() const { return size_bytes_; }
  /// Less than `margin_bytes` left, or no inode left: a writer reached the
  /// bound.
  bool Full(uint64_t margin_bytes) const;

 private:
  uint64_t size_bytes_ = 0;
  bool ok_ = false;
  std::string problem_;
  pid_t holder_ = -1;
  int hold_ = -1;
  int mount_ns_ = -1;
  int user_ns_ = -1;
  std::filesystem::path view_;
};

}  // namespace syrof::process
