// A student's app library, run in a sandboxed child process per robot.
//
// The lab (and later the DDS robots and the grader) never load a student's
// shared library into their own process. Each robot gets its own
// `syrof-app-host` process, started with exec, that hardens itself (die with
// the parent, every other descriptor closed, rlimits, an unprivileged uid
// when started as root, namespaces where the kernel allows, no_new_privs, a
// two-stage seccomp allow-list) and only then loads the library. The robot
// talks to it through HostedApp, an app::App whose every callback writes one
// request frame and waits for one reply frame, under a CPU-time budget and a
// wall cap. Whatever the library does (crash, loop, exit, allocate without
// bound, flood its output, call what the sandbox forbids) ends as a
// CallStatus fault with its verdict; the robot then stops like a crashed one
// and the rest of the swarm goes on (docs/apps.md, "When an app fails").
//
// Each robot's stdout and stderr go to its own log file, capped: the first
// `log_keep_bytes` are kept, the rest counted; past `output_limit_bytes` the
// robot is stopped with the verdict output_limit.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/lab/base/error.h"

namespace syrof::app_host {

/// What a robot's app host may use. Defaults are the design's.
struct HostLimits {
  uint32_t cpu_budget_ms = 100;         ///< user CPU time per callback (the host's own, read by the parent; system time is left to the wall cap)
  uint32_t wall_cap_ms = 2000;          ///< wall time per callback, whatever the CPU did
  uint32_t load_wall_cap_ms = 5000;     ///< wall time to start the host and load the library
  uint64_t address_space_bytes = 256ull << 20;  ///< RLIMIT_AS of the host
  uint64_t log_keep_bytes = 64ull << 10;        ///< output kept in the robot's log
  uint64_t output_limit_bytes = 16ull << 20;    ///< output past this stops the robot (output_limit)

  /// The limits for a scenario's (or command line's) budgets over these
  /// defaults: an unset wall cap is raised to 4x the CPU budget when that is
  /// more, so a larger budget is not cut short by the default wall cap.
  static HostLimits ForBudgets(std::optional<uint32_t> cpu_budget_ms, std::optional<uint32_t> wall_cap_ms) {
    HostLimits limits;
    if (cpu_budget_ms) limits.cpu_budget_ms = *cpu_budget_ms;
    limits.wall_cap_ms = wall_cap_ms ? *wall_cap_ms : std::max(limits.wall_cap_ms, 4 * limits.cpu_budget_ms);
    return limits;
  }
};

/// How to start the hosts of one run.
struct HostOptions {
  std::string library_path;  ///< the student's library (absolute, or relative to the working directory)
  std::string host_binary;   ///< path to syrof-app-host; empty: FindHostBinary()
  std::string log_directory; ///< where <id>.log goes (created if missing); empty: output discarded
  HostLimits limits;
  /// What the app's syrofAppParameter answers (the scenario's app.params),
  /// sent to each host with the init request. At most
  /// SYROF_APP_MAX_PARAMETERS, names 1 .. SYROF_APP_MAX_PARAMETER_NAME_LENGTH
  /// bytes without a NUL (the scenario checks); otherwise Init reports a
  /// bad_abi fault.
  std::map<std::string, double> params;
  /// What each robot's syrofAppInput answers (the scenario's `inputs`), by
  /// robot id: each host gets only its own robot's, with the init request.
  /// At most SYROF_APP_MAX_INPUTS a robot, names as for params.
  std::map<uint16_t, std::map<std::string, double>> inputs;
};

/// Where syrof-app-host is: beside the running executable (a build tree's
/// bin/), or in the installed libexec folder. Empty if neither has it.
std::string FindHostBinary();

/// The outcome of checking a library before a run.
struct LibraryCheck {
  std::string app_name;  ///< the descriptor's name, when ok
  /// When not ok: what is wrong, where the file (missing, no
  /// syrof_app_entry, ABI version N where the platform has M, failed to
  /// load: dlerror's text).
  std::optional<lab::Error> error;
  bool ok() const { return !error.has_value(); }
};

/// Starts one sandboxed host for `options.library_path`, loads the library,
/// checks its entry symbol and ABI version, and stops it. The run refuses a
/// library that fails this (exit 2) before any robot starts.
LibraryCheck CheckLibrary(const HostOptions& options);

/// What the sandbox could and could not do on this machine (for example
/// "user namespaces unavailable: ..."), one line each; empty when every
/// layer of the hardening applied. Filled by CheckLibrary's host.
std::vector<std::string> SandboxNotes();

/// Robot `robot_id`'s app: a host process spawned now (posix_spawn + exec),
/// which hardens itself and loads the library while the caller goes on, so
/// a swarm's hosts load side by side; the first callback (or name()) waits
/// for it to be ready. Its callbacks go to that process, which is killed
/// and reaped when the app is destroyed. A host that fails to start gives
/// an app whose Init reports the fault (load_failed, bad_abi, crashed, ...).
/// Spawn from a thread that outlives the app: the host's parent-death
/// signal follows the spawning thread. docs/app_host.md has the details.
std::unique_ptr<app::App> MakeHostedApp(const HostOptions& options, uint16_t robot_id);

/// A library loaded once for many runs: the fork server (docs/app_host.md
/// "The fork server"). One held host loads the library, hardened as a
/// run's host is up to its callbacks' filter, and never runs a callback;
/// each app made from it is a fresh copy of that host made right after the
/// load (a fork), which then installs the callbacks' filter. A copy starts
/// as a fresh host would, so a run gives the same results, byte for byte.
/// When the library does not load in the held host, or its constructors
/// left what copies would share (an open file, a shared mapping, a pending
/// signal), every app is a fresh host instead; a held host that ends is
/// started again. Make it from a thread that outlives every app made from
/// it (the copies' parent-death signal follows that thread); destroying it
/// (the last shared_ptr) ends the held host.
class LoadedLibrary;
std::shared_ptr<LoadedLibrary> LoadOnce(const HostOptions& options);

/// Whether `loaded` still makes copies (`holding`), why not (each app then
/// a fresh host: the library did not load in the held host, its
/// constructors left an open file, a shared mapping or a pending signal,
/// or a held host started again loaded differently), and how many held
/// hosts it started (more than 1: one ended and was started again).
struct LoadedLibraryState {
  bool holding = false;
  std::string fresh_reason;
  int starts = 0;
};
LoadedLibraryState StateOf(const LoadedLibrary& loaded);

/// Robot `robot_id`'s app as MakeHostedApp makes it, its host a copy of
/// `loaded`'s held host (`options` as given to LoadOnce, but for
/// log_directory and the inputs, which are the robot's).
std::unique_ptr<app::App> MakeHostedApp(const HostOptions& options, uint16_t robot_id,
                                        const std::shared_ptr<LoadedLibrary>& loaded);

}  // namespace syrof::app_host
