#include "syrof/app/c_abi_app.h"

#include <span>
#include <string_view>

#include "syrof/base/check.h"

namespace syrof::app {
namespace {

// The platform of the robot whose C callback is running; see c_abi_app.h.
Platform* current_platform = nullptr;

// Makes `platform` current for one callback; restores the previous one, so
// a callback that (oddly) runs another robot's callback stays consistent.
class CurrentPlatform {
 public:
  explicit CurrentPlatform(Platform* platform) : previous_(current_platform) { current_platform = platform; }
  ~CurrentPlatform() { current_platform = previous_; }
  CurrentPlatform(const CurrentPlatform&) = delete;
  CurrentPlatform& operator=(const CurrentPlatform&) = delete;

 private:
  Platform* previous_;
};

}  // namespace

const char* ToString(DescriptorError error) {
  switch (error) {
    case DescriptorError::kOk: return "Ok";
    case DescriptorError::kNull: return "Null";
    case DescriptorError::kAbiVersionMismatch: return "AbiVersionMismatch";
    case DescriptorError::kMissingCallback: return "MissingCallback";
  }
  return "?";
}

DescriptorError Validate(const syrof_app_descriptor* descriptor) {
  if (descriptor == nullptr) return DescriptorError::kNull;
  if (descriptor->abi_version != SYROF_APP_ABI_VERSION) return DescriptorError::kAbiVersionMismatch;
  if (descriptor->init == nullptr || descriptor->new_round == nullptr || descriptor->end_of_round == nullptr) {
    return DescriptorError::kMissingCallback;
  }
  return DescriptorError::kOk;
}

CAbiApp::CAbiApp(const syrof_app_descriptor& descriptor) : descriptor_(descriptor) {
  SYROF_CHECK(Validate(&descriptor) == DescriptorError::kOk);
}

const char* CAbiApp::name() const { return descriptor_.name != nullptr ? descriptor_.name : "c_app"; }

CallStatus CAbiApp::Init(const syrof_app_info& info, Platform& platform, uint8_t& global_state) {
  platform_ = &platform;
  const CurrentPlatform current(platform_);
  global_state = descriptor_.init(&info);
  return CallStatus::Ok();
}

CallStatus CAbiApp::NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                             uint32_t clock_ms) {
  const CurrentPlatform current(platform_);
  global_state = descriptor_.new_round(&command, &ldmap, global_state, clock_ms);
  return CallStatus::Ok();
}

CallStatus CAbiApp::EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) {
  const CurrentPlatform current(platform_);
  global_state = descriptor_.end_of_round(&ldmap, global_state, clock_ms);
  return CallStatus::Ok();
}

}  // namespace syrof::app

extern "C" int sendMessageData(const uint8_t* payload, size_t length) {
  using syrof::app::current_platform;
  if (current_platform == nullptr) return SYROF_APP_NOT_RUNNING;
  if (payload == nullptr && length != 0) return SYROF_APP_NULL_ARGUMENT;
  // The platform refuses a payload over SYROF_APP_MAX_PAYLOAD_BYTES itself,
  // so that the robot counts and reports it.
  return current_platform->SendMessageData(std::span<const uint8_t>(payload, length));
}

extern "C" syrof_queries_workspace* syrofQueriesWorkspace(void) {
  using syrof::app::current_platform;
  return current_platform != nullptr ? current_platform->queries_workspace() : nullptr;
}

namespace {

// syrofAppParameter's and syrofAppInput's checks: SYROF_APP_OK with `length`
// set, or the status to return. At most one byte past the longest name is
// read: a name without a NUL within that bound cannot be one the scenario
// gave. (A loop, not strnlen: that is POSIX, not in every MCU C library.)
int CheckNamedRead(const char* name, const double* value, syrof_app_status missing, size_t& length) {
  if (syrof::app::current_platform == nullptr) return SYROF_APP_NOT_RUNNING;
  if (name == nullptr || value == nullptr) return SYROF_APP_NULL_ARGUMENT;
  length = 0;
  while (length <= SYROF_APP_MAX_PARAMETER_NAME_LENGTH && name[length] != '\0') ++length;
  return length > SYROF_APP_MAX_PARAMETER_NAME_LENGTH ? missing : SYROF_APP_OK;
}

}  // namespace

extern "C" int syrofAppParameter(const char* name, double* value) {
  size_t length = 0;
  const int checked = CheckNamedRead(name, value, SYROF_APP_NO_SUCH_PARAMETER, length);
  if (checked != SYROF_APP_OK) return checked;
  return syrof::app::current_platform->AppParameter(std::string_view(name, length), *value);
}

extern "C" int syrofAppInput(const char* name, double* value) {
  size_t length = 0;
  const int checked = CheckNamedRead(name, value, SYROF_APP_NO_SUCH_INPUT, length);
  if (checked != SYROF_APP_OK) return checked;
  return syrof::app::current_platform->AppInput(std::string_view(name, length), *value);
}
