#include "syrof/app/call_status.h"

#include "text.h"

namespace syrof::app {

const char* ToString(Verdict verdict) {
  switch (verdict) {
    case Verdict::kOk: return "ok";
    case Verdict::kAppError: return "app_error";
    case Verdict::kCrashed: return "crashed";
    case Verdict::kTimeout: return "timeout";
    case Verdict::kExited: return "exited";
    case Verdict::kMemory: return "memory";
    case Verdict::kForbiddenSyscall: return "forbidden_syscall";
    case Verdict::kOutputLimit: return "output_limit";
    case Verdict::kBadAbi: return "bad_abi";
    case Verdict::kLoadFailed: return "load_failed";
  }
  return "?";
}

const char* ToString(Callback callback) {
  switch (callback) {
    case Callback::kInit: return "init";
    case Callback::kNewRound: return "new_round";
    case Callback::kEndOfRound: return "end_of_round";
  }
  return "?";
}

CallStatus CallStatus::Fault(Verdict verdict, const char* detail) {
  CallStatus status;
  status.verdict_ = verdict;
  detail::TextBuilder(status.detail_.data(), status.detail_.size()).Append(detail);
  return status;
}

}  // namespace syrof::app
