// The world's side of a run that every runtime shares (docs/architecture.md,
// "One world, three runtimes"): the robots' lifecycle, the scenario's faults
// on world time, the join wait, and the simulator's own replay events
// (faults, contacts) with the metrics they feed. The lab engine, the DDS
// world of `syrof swarm` and the emulated firmware swarm's host each play
// their world through one WorldPlayer and implement RobotRuntime, the few
// things only they can do to a robot (switch it on, stop it, continue it),
// so a scenario's faults mean the same thing in all three.
//
// The rules, one place for all runtimes:
//   - a fault takes effect on the radio-round grid (FaultSchedule);
//   - join: an absent robot is switched on; with safety on and its start
//     disc occupied it waits (JOIN_WAIT, metrics' safety.join_waits) and is
//     switched on at the first step that finds the disc clear;
//   - crash: for good, whatever the robot was doing (a waiting joiner never
//     starts); a robot already crashed stays so and the fault is dropped;
//   - pause: only a running robot; resume: only a paused one (a robot that
//     crashed during its pause stays crashed);
//   - a robot whose app faulted is stopped as if crashed, and one that was
//     never switched on arrives crashed: its body is an obstacle.
// Each change that happens gives one replay event, stamped with the robot's
// epoch and mode (RobotRuntime::Stamp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "syrof/lab/apps/builtin_goals.h"
#include "syrof/lab/goals/goals.h"
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/fault_schedule.h"
#include "syrof/lab/world/world.h"
#include "syrof/wire/beacon.h"
#include "syrof/base/state_digest.h"

namespace syrof::lab::sim {

/// Where a robot is in its life, the same in every runtime.
enum class Lifecycle : uint8_t {
  kAbsent,         ///< not switched on yet (a later `join`)
  kWaitingToJoin,  ///< its join is due, its start disc is occupied
  kRunning,
  kPaused,
  kCrashed,        ///< for good: a crash fault, or its app faulted
};

const char* ToString(Lifecycle lifecycle);

/// The replay's presence of a robot in `lifecycle` (a waiting joiner is absent).
replay::Presence ToPresence(Lifecycle lifecycle);

/// Why a runtime is told to stop a robot.
enum class StopReason : uint8_t {
  kCrash,     ///< a crash fault: for good
  kPause,     ///< a pause fault: it will be resumed
  kAppFault,  ///< its app faulted: for good, the robot has stopped its app itself
};

/// A robot event's stamp: the robot's epoch and that epoch's mode now.
struct EventStamp {
  uint16_t epoch = 0;
  wire::Mode mode = wire::Mode::kCooperative;
};

/// What only a runtime can do to its robots: the lab's ports, the DDS robot
/// processes, the firmware's qemu instances.
class RobotRuntime {
 public:
  virtual ~RobotRuntime() = default;
  /// Switches robot `id` on at world time `world_ns`: its first start
  /// (`resume` false) or the end of a pause. False when it cannot run (its
  /// process did not start): the player counts it crashed.
  virtual bool StartRobot(uint16_t id, int64_t world_ns, bool resume) = 0;
  /// Stops robot `id` at `world_ns`; it was running or paused.
  virtual void StopRobot(uint16_t id, int64_t world_ns, StopReason reason) = 0;
  /// The stamp of robot `id`'s events now (zero where the runtime does not know).
  virtual EventStamp Stamp(uint16_t /*id*/) const { return {}; }
};

class WorldPlayer {
 public:
  /// `world` holds the scenario's bodies (Bodies(scenario)) and `collector`
  /// the run's metrics; `scenario`, `world` and `collector` outlive the
  /// player. Every robot starts absent.
  WorldPlayer(const scenario::Scenario& scenario, world::World& world, metrics::Collector& collector);

  /// Switches on the robots present at start, at world time 0, in id order
  /// (no events: the replay's first frame shows them).
  void StartPresentRobots(RobotRuntime& runtime);

  /// Plays what is due at world time `now_ns` (non-decreasing; every physics
  /// step, the grid's points included): waiting joiners whose start disc is
  /// clear now, in the order they became due, then the faults due now.
  void PlayFaults(int64_t now_ns, RobotRuntime& runtime);

  /// After World::Step: the new contacts to the metrics and the replay
  /// (each event stamped as its first robot's).
  void TakeContacts(const RobotRuntime& runtime);

  /// Robot `id`'s app faulted at `now_ns`: it stops for good (as the lab has
  /// always done; a waiting or absent robot arrives crashed).
  void AppFaulted(uint16_t id, int64_t now_ns, RobotRuntime& runtime);

  /// Robot `id`'s app faulted, and the robot stopped it itself (a DDS robot
  /// process): noted for the goal, nothing else changes.
  void NoteAppFault(uint16_t id) { robots_[id].app_faulted = true; }

  /// The true positions of the robots running now with a working app, for
  /// the scenario's goal checks (lab/goals).
  std::vector<goals::RobotPose> RunningPoses() const;
  /// The same at an instant captured earlier (the DDS world's boundary
  /// truth): `presence` and `bodies` per robot as they were then; an app
  /// fault noted since counts too. Both hold robot_count() entries.
  std::vector<goals::RobotPose> RunningPoses(std::span<const replay::Presence> presence,
                                             std::span<const world::BodyState> bodies) const;
  /// Every robot's true pose now, `present` for those running with a
  /// working app, for the built-in app's goal (apps::EvaluateGoal).
  std::vector<apps::GoalPose> FinalPoses() const;

  Lifecycle lifecycle(uint16_t id) const { return robots_[id].lifecycle; }
  replay::Presence presence(uint16_t id) const { return ToPresence(robots_[id].lifecycle); }
  bool running(uint16_t id) const { return robots_[id].lifecycle == Lifecycle::kRunning; }
  bool app_faulted(uint16_t id) const { return robots_[id].app_faulted; }
  /// Estimates of robot `id` before this world time are not scored (it
  /// started or resumed within kEstimationWarmupNs).
  int64_t scored_from_ns(uint16_t id) const { return robots_[id].scored_from_ns; }
  uint16_t robot_count() const { return static_cast<uint16_t>(robots_.size()); }

  /// A replay event of the round in progress. The player's own (faults,
  /// contacts) go here too, in the order they happen.
  void AddEvent(const replay::Event& event) { events_.push_back(event); }
  /// The events since the last call, in the order they were added; the
  /// player's list is left empty.
  std::vector<replay::Event> TakeEvents();
  /// The events of the round in progress (the lab writes them with the round).
  std::vector<replay::Event>& events() { return events_; }

  /// Each robot's lifecycle and the joiners waiting into `digest`
  /// (base/state_digest.h); the faults to come are the scenario's.
  void AddToDigest(base::StateDigest& digest) const {
    for (const Robot& robot : robots_) {  // field by field: Robot has padding
      digest.AddValue(robot.lifecycle);
      digest.AddValue(robot.app_faulted);
      digest.AddValue(robot.scored_from_ns);
    }
    digest.AddRange(std::span<const uint16_t>(waiting_));
  }

 private:
  // RunningPoses' rule, over robot ids: `presence_of(id)`, `body_of(id)`.
  template <typename PresenceOf, typename BodyOf>
  std::vector<goals::RobotPose> RunningPosesOf(PresenceOf presence_of, BodyOf body_of) const;

  struct Robot {
    Lifecycle lifecycle = Lifecycle::kAbsent;
    bool app_faulted = false;
    int64_t scored_from_ns = 0;
  };

  void Event(replay::EventKind kind, int64_t now_ns, uint16_t id, const RobotRuntime& runtime,
             uint16_t other = replay::kNoRobot);
  // Switches `id` on now (a join whose disc is clear, or a resume).
  void Start(uint16_t id, int64_t now_ns, bool resume, RobotRuntime& runtime);
  void Stop(uint16_t id, int64_t now_ns, StopReason reason, Lifecycle after, RobotRuntime& runtime);
  void Join(uint16_t id, int64_t now_ns, RobotRuntime& runtime);
  bool StartDiscClear(uint16_t id) const;

  const scenario::Scenario& scenario_;
  world::World& world_;
  metrics::Collector& collector_;
  FaultSchedule faults_;
  std::vector<Robot> robots_;
  std::vector<uint16_t> waiting_;  // joiners whose disc was occupied, in the order they became due
  std::vector<replay::Event> events_;
};

}  // namespace syrof::lab::sim
