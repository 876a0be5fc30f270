// The app interface the robot runtime calls: the C ABI of syrof/app.h seen
// from C++. The runtime holds one App per robot and never knows which kind
// it is:
//   - apps built into the tree (lab/apps) derive from App directly;
//   - CAbiApp (c_abi_app.h) wraps a syrof_app_descriptor, for C apps linked
//     in-process;
//   - the grader's app host will be a third App that forwards each call to a
//     student's library in a sandboxed child process.
// Every callback reports a CallStatus (call_status.h): ok, or a fault with a
// verdict and a reason. The runtime stops a robot whose app faulted as if it
// had crashed, and reports the fault (docs/apps.md, "When an app fails").
// The structs are the ABI's own (syrof_ldmap, syrof_car_command,
// syrof_app_info), so every implementation sees exactly the same bytes.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "syrof/app.h"
#include "syrof/app/call_status.h"

namespace syrof::app {

/// One number the scenario gives the app by name (syrofAppParameter). The
/// name is a view: whoever builds a table of these keeps the names alive.
struct Parameter {
  std::string_view name;
  double value = 0;
};

/// Looks `name` up in `params`: SYROF_APP_OK and `value` set, or `missing`
/// (SYROF_APP_NO_SUCH_PARAMETER, or SYROF_APP_NO_SUCH_INPUT for a robot's
/// private inputs, which are the same kind of table) with `value`
/// unchanged. Linear: a table holds at most SYROF_APP_MAX_PARAMETERS.
syrof_app_status FindParameter(std::span<const Parameter> params, std::string_view name, double& value,
                               syrof_app_status missing = SYROF_APP_NO_SUCH_PARAMETER);

/// What the platform offers an app besides its callbacks. One per robot.
class Platform {
 public:
  /// Sets the payload of the robot's next snapshot (sendMessageData).
  /// Returns SYROF_APP_PAYLOAD_TOO_LONG, changing nothing, for more than
  /// SYROF_APP_MAX_PAYLOAD_BYTES bytes.
  virtual syrof_app_status SendMessageData(std::span<const uint8_t> payload) = 0;

  /// Scratch memory for the queries; shared by the apps of one thread, valid
  /// while the platform lives.
  virtual syrof_queries_workspace* queries_workspace() = 0;

  /// The scenario's parameter `name` (syrofAppParameter, which has already
  /// checked the arguments and bounded the name's length): SYROF_APP_OK and
  /// `value`, or SYROF_APP_NO_SUCH_PARAMETER leaving `value` alone. The
  /// default is a platform that gives no parameters.
  virtual syrof_app_status AppParameter(std::string_view name, double& value);

  /// This robot's private input `name` (syrofAppInput, arguments checked as
  /// for AppParameter): SYROF_APP_OK and `value`, or SYROF_APP_NO_SUCH_INPUT
  /// leaving `value` alone. The default is a platform that gives no inputs.
  virtual syrof_app_status AppInput(std::string_view name, double& value);

 protected:
  ~Platform() = default;
};

/// One robot's app instance. Callbacks run one at a time, in this order:
/// Init once, then per epoch NewRound and (if the maneuver completes)
/// EndOfRound. The `ldmap` is valid only during the call. Each callback
/// returns its status; on a fault its outputs (`command`, `global_state`)
/// are ignored and the runtime makes no further call.
class App {
 public:
  virtual ~App() = default;

  /// A short name for logs ("circle").
  virtual const char* name() const = 0;

  /// Called once when the robot starts. `platform` outlives the app. Sets
  /// `global_state` to the initial global state.
  virtual CallStatus Init(const syrof_app_info& info, Platform& platform, uint8_t& global_state) = 0;

  /// Called at the start of every epoch; `command` arrives as STOP and the
  /// app sets the maneuver. `global_state` holds the current global state
  /// and receives the new one.
  virtual CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                              uint32_t clock_ms) = 0;

  /// Called when the maneuver ends, with the map the epoch started with.
  /// `global_state` holds the current global state and receives the new one.
  virtual CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) = 0;
};

/// The member with `id` in `ldmap`, or nullptr (binary search: members are
/// in increasing id order).
const syrof_member_state* FindMember(const syrof_ldmap& ldmap, uint16_t id);

}  // namespace syrof::app
