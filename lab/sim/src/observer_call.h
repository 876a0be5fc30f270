// What a robot's step tells the lab (runtime::RobotObserver's calls and its
// RecordingApp's app states), as data. The engine (simulation.cpp) handles a
// call at once, or, while a batch of robot steps runs on --threads, after
// the batch (robot_chunks.h), robot by robot in the order of a one-thread
// run. Internal to lab/sim.
//
// A call carries what its handling reads of the robot at the moment of the
// call (its epoch and that epoch's mode), since the robot's step has gone on
// by the time a kept call is handled; its pointers point into the robot and
// stay unchanged until the robot's next round step, after the batch.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <variant>

#include "syrof/app/call_status.h"
#include "syrof/app/command_check.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/sync/ldmap.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"

namespace syrof::lab::sim {

struct ObserverCall {
  struct EpochStart {
    const sync::LDMap* ldmap;
    std::shared_ptr<const replay::EpochMap> map;  // with a replay: ldmap as the replay stores it; else null
  };
  struct Membership {
    const wire::MemberSet* removed;
    const wire::MemberSet* joined;
  };
  struct BecameJoiner {};
  // call_epoch: the epoch of the app call at fault, which may differ from
  // the robot's epoch at the report.
  struct AppFault {
    app::Callback callback;
    uint16_t call_epoch;
    app::CallStatus status;
  };
  struct InvalidCommand {
    uint16_t call_epoch;
    app::CommandCheck check;
  };
  struct PayloadRefused {
    uint16_t call_epoch;
    size_t length;  // bytes
  };
  struct SafetyIntervention {
    int64_t local_ns;  // the robot's local time of the intervention
    uint16_t other;    // the robot avoided, or motion::kWallObstacle
    bool precaution;   // a precaution's start (RobotObserver::OnSafetyPrecaution)
  };
  // An app call returned (agreement, lab/metrics/agreement.h): what it left
  // in the app's map, read at the call, since the map changes within the step.
  struct AppState {
    bool new_round;  // the call was new_round (else end_of_round)
    bool cooperative;
    uint16_t map_epoch;
    uint64_t fingerprint;  // MapFingerprint of the app's map
    uint8_t state;
  };
  using What = std::variant<EpochStart, Membership, BecameJoiner, AppFault, InvalidCommand, PayloadRefused,
                            SafetyIntervention, AppState>;

  uint16_t robot;
  uint16_t epoch;   // the robot's epoch at the call (its events' stamp)
  wire::Mode mode;  // that epoch's mode at the call
  What what;
};

// Handles calls, one at a time, on the engine's thread.
class ObserverCallHandler {
 public:
  virtual void Handle(const ObserverCall& call) = 0;

 protected:
  ~ObserverCallHandler() = default;
};

}  // namespace syrof::lab::sim
