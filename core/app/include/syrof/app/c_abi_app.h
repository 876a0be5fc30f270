// An App over the C ABI: wraps a syrof_app_descriptor (an app written in C
// against syrof/app.h) so the runtime calls it like any built-in app.
//
// The C functions the app calls back (sendMessageData, syrofAppParameter,
// syrofQueriesWorkspace) carry no robot handle, so while a callback runs this adapter makes its
// robot's Platform the current one, and those functions act on it. Outside
// a callback they answer SYROF_APP_NOT_RUNNING (or NULL). In a process that
// hosts one robot (the grader's app host, the firmware) that is all there
// is; in the lab, where many robots share a process and a thread, it keeps
// each call on its own robot.
#pragma once

#include "syrof/app.h"
#include "syrof/app/app.h"

namespace syrof::app {

/// Why a descriptor was refused.
enum class [[nodiscard]] DescriptorError : uint8_t {
  kOk = 0,
  kNull,                ///< no descriptor
  kAbiVersionMismatch,  ///< built against another SYROF_APP_ABI_VERSION
  kMissingCallback,     ///< init, new_round or end_of_round is NULL
};

/// The enumerator's name without the k.
const char* ToString(DescriptorError error);

/// Checks a descriptor before use: the loader's ABI check.
DescriptorError Validate(const syrof_app_descriptor* descriptor);

class CAbiApp final : public App {
 public:
  /// `descriptor` must be valid (Validate) and outlive the app.
  explicit CAbiApp(const syrof_app_descriptor& descriptor);

  const char* name() const override;
  /// A C callback cannot report a failure (the ABI has no channel for it):
  /// every call returns ok. A C app that crashes takes its process with it;
  /// the app host (a child process) is what turns that into a verdict.
  CallStatus Init(const syrof_app_info& info, Platform& platform, uint8_t& global_state) override;
  CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                      uint32_t clock_ms) override;
  CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) override;

 private:
  const syrof_app_descriptor& descriptor_;
  Platform* platform_ = nullptr;
};

}  // namespace syrof::app
