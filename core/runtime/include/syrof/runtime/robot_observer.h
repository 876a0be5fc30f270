// Hooks for whoever watches a robot: the lab's metrics and replay, a log, a
// test.
//
// The robot calls its observer (set with Robot::set_observer) from its round
// task, after the synchronizer's step of that round, in this order:
// OnEpochStart (if an epoch started), OnMembership (if members were removed
// or joined), OnBecameJoiner (if the robot lost its group). The app hooks
// (OnAppFault, OnInvalidCommand, OnPayloadRefused) come from the same task
// as the app call they report (Attach for init). OnSafetyIntervention comes
// from the round task, before the synchronizer's step, for the interventions
// the motion task started since the previous round.
#pragma once

#include <cstddef>
#include <cstdint>

#include "syrof/app/call_status.h"
#include "syrof/app/command_check.h"
#include "syrof/sync/ldmap.h"
#include "syrof/wire/member_set.h"

namespace syrof::runtime {

/// Hooks for whoever watches the robot (the lab's metrics and replay, logs).
///
/// Contract:
///   - Who calls: the robot's round task, in the port's task context, after
///     the round's synchronizer step; never from ReceiveBytes' producer
///     thread or an interrupt. Calls for one robot never overlap.
///   - `robot` is the robot's id (sync.self_id); `now_ns` is the port's clock
///     at the round task's activation.
///   - Ownership: the arguments belong to the robot and are valid only during
///     the call; copy what you keep. The robot does not own its observer,
///     which must outlive it (or be unset first).
///   - Bounds: hooks run inside the round task, so they must return in
///     bounded time, must not block, and must not call back into the robot
///     except its const accessors.
class RobotObserver {
 public:
  /// An epoch started with `ldmap` (what newRound received). Also called
  /// when the activation schedule leaves the robot out of the epoch (SSYNC:
  /// no newRound then; sync::IsActive on `ldmap` tells which).
  virtual void OnEpochStart(uint16_t robot, int64_t now_ns, const sync::LDMap& ldmap) = 0;
  /// The failure detector removed, or the membership added, these robots.
  virtual void OnMembership(uint16_t robot, int64_t now_ns, const wire::MemberSet& removed,
                            const wire::MemberSet& joined) = 0;
  /// The robot lost its group and is joining again.
  virtual void OnBecameJoiner(uint16_t robot, int64_t now_ns) = 0;
  /// The app's `callback` failed with `status` during `epoch` (0 for init).
  /// From now on the robot is stopped as if it had crashed: no app call, no
  /// synchronizer step, no beacon (so the others' failure detectors remove
  /// it), drive command STOP. Nothing more is reported for it.
  virtual void OnAppFault(uint16_t robot, int64_t now_ns, app::Callback callback, uint16_t epoch,
                          const app::CallStatus& status) = 0;
  /// newRound of `epoch` returned a command that `check` refuses; the robot
  /// holds still (STOP) for that maneuver.
  virtual void OnInvalidCommand(uint16_t robot, int64_t now_ns, uint16_t epoch, const app::CommandCheck& check) = 0;
  /// sendMessageData refused `length` bytes (more than
  /// SYROF_APP_MAX_PAYLOAD_BYTES) in a callback of `epoch`; the previous
  /// payload stays.
  virtual void OnPayloadRefused(uint16_t robot, int64_t now_ns, uint16_t epoch, size_t length) = 0;
  /// The safety filter began to limit the robot's drive command at
  /// `time_ns` (in the motion task; reported by the round task's next step,
  /// so `time_ns` may be up to a round before `now`), against robot `other`
  /// or motion::kWallObstacle. One call per intervention start, not per step.
  virtual void OnSafetyIntervention(uint16_t robot, int64_t time_ns, uint16_t other) {
    (void)robot;
    (void)time_ns;
    (void)other;
  }
  /// The same for a precaution: the filter began to limit a command that
  /// kept the rule the app is held to, only for its wider cover of the
  /// robot's own error (motion::SafetyConfig::charged_sigmas). Not charged.
  virtual void OnSafetyPrecaution(uint16_t robot, int64_t time_ns, uint16_t other) {
    (void)robot;
    (void)time_ns;
    (void)other;
  }

 protected:
  ~RobotObserver() = default;
};

}  // namespace syrof::runtime
