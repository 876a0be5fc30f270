// The steps that confine a process, each written once: closing inherited
// descriptors, resource limits, leaving root for uid 65534, and a user
// namespace that maps the caller's own ids. A process applies them to
// itself: a sandboxed child between fork and exec (Spawn with a Sandbox,
// spawn.h), or syrof-app-host hardening itself before it loads a library
// (docs/app_host.md). Every function here makes system calls only and
// allocates nothing: async-signal-safe, fit for a child of a process that
// has threads.
#pragma once

#include <sys/resource.h>
#include <sys/types.h>

namespace syrof::process {

/// The uid and gid untrusted code runs as when SyROF is started by root
/// (nobody, nogroup).
inline constexpr uid_t kNobodyUid = 65534;
inline constexpr gid_t kNobodyGid = 65534;

/// Closes every descriptor from `first` up. True through close_range
/// (Linux 5.9); false when that is missing and they were closed one by one
/// up to the hard descriptor limit (at most 1 << 20).
bool CloseDescriptorsFrom(int first);

/// Closes every descriptor from 3 up but `keep_a` and `keep_b` (the same
/// number twice keeps one).
void CloseAllBut(int keep_a, int keep_b);

/// Sets the soft and the hard limit of `resource` to `value`. Lowering a
/// limit never needs privilege; false when the kernel refuses.
bool SetLimit(int resource, rlim_t value);

/// Leaves root for kNobodyUid/kNobodyGid: no supplementary groups, then the
/// gid, then the uid; checks that neither the real nor the effective uid is
/// 0 afterwards, and arms the parent-death SIGKILL again (a change of
/// credentials clears it). Returns 0, or the errno of the step refused
/// (EPERM when root remained).
int DropToNobody();

/// The caller's own uid and gid as the one-line maps of a new user
/// namespace ("UID UID 1\n"): the one mapping an unprivileged process may
/// write, so files made inside are owned as outside. Made before fork
/// (formatting is not async-signal-safe), written by MapCallerIds after.
struct CallerIdMaps {
  char uid_map[32] = {};
  char gid_map[32] = {};
  /// The maps of the calling process's effective uid and gid.
  static CallerIdMaps OfCaller();
};

/// In a user namespace just made by unshare: "deny" to setgroups, then the
/// uid and gid maps. False (errno set) when a map is refused.
bool MapCallerIds(const CallerIdMaps& maps);

}  // namespace syrof::process
