// What an app callback reports besides its results: ok, or a fault with a
// verdict and a short reason. Built-in apps and C apps in-process only fail
// when they say so; the app host (a student's library in a sandboxed child
// process) also reports what the sandbox saw: a signal, a timeout, a
// forbidden system call...
//
// A CallStatus is plain data (no allocation): the reason is a fixed-size,
// NUL-terminated text, truncated to fit.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace syrof::app {

/// Why an app call failed. kOk for a call that did not.
enum class Verdict : uint8_t {
  kOk = 0,
  kAppError,          ///< an in-process app reported a failure itself (detail says what)
  kCrashed,           ///< the app's process died on a signal (detail names it)
  kTimeout,           ///< over the CPU-time budget or the wall cap of a call
  kExited,            ///< the app's process exited during a call
  kMemory,            ///< over the app's memory limit
  kForbiddenSyscall,  ///< a system call the sandbox refuses (detail names it)
  kOutputLimit,       ///< wrote more output than allowed
  kBadAbi,            ///< a malformed reply, or a library built against another ABI
  kLoadFailed,        ///< the library could not be loaded
};

/// The last Verdict, for tables and range checks.
inline constexpr Verdict kLastVerdict = Verdict::kLoadFailed;

/// "ok", "app_error", "crashed", "timeout", "exited", "memory",
/// "forbidden_syscall", "output_limit", "bad_abi", "load_failed" (the names
/// metrics.json uses); "?" for a value outside the enum.
const char* ToString(Verdict verdict);

/// Which callback a call was.
enum class Callback : uint8_t { kInit = 0, kNewRound, kEndOfRound };

/// "init", "new_round", "end_of_round"; "?" for a value outside the enum.
const char* ToString(Callback callback);

/// The outcome of one app call.
class [[nodiscard]] CallStatus {
 public:
  /// Bytes of the reason, its terminating NUL included.
  static constexpr size_t kDetailBytes = 48;

  /// A call that succeeded.
  static CallStatus Ok() { return CallStatus(); }
  /// A call that failed with `verdict` (not kOk) because of `detail` (may be
  /// null; truncated to kDetailBytes - 1 bytes).
  static CallStatus Fault(Verdict verdict, const char* detail);

  CallStatus() = default;

  bool ok() const { return verdict_ == Verdict::kOk; }
  Verdict verdict() const { return verdict_; }
  /// The reason, NUL-terminated; empty for an ok status.
  const char* detail() const { return detail_.data(); }

 private:
  Verdict verdict_ = Verdict::kOk;
  std::array<char, kDetailBytes> detail_{};
};

}  // namespace syrof::app
