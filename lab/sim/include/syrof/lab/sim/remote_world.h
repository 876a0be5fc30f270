// The world loop of a runtime whose robots run outside the lab's engine
// (docs/architecture.md, "One world, three runtimes"): the DDS world of
// `syrof swarm` and the emulated firmware swarm (syrof-firmware-swarm). It
// owns what such a runtime has around its robots, the same whatever carries
// their messages:
//   - the World (bodies), the WorldPlayer (lifecycle, faults, the join
//     wait) and the RoundRecorder (metrics, goal, replay);
//   - each robot's SensorBank, sampled at every instant;
//   - each round boundary's truth (bodies, presence, the world's events),
//     kept until the round's reports are complete;
//   - each robot's newest round report, its events' stamp;
//   - the round-start skew, one sample a round: the spread of the robots'
//     round boundaries as the adapter marks them (a DDS robot's round task
//     activation, an emulated robot's beacon reaching the host).
// The runtime around it (its adapter) supplies only what depends on its
// transport: how robots are started and stopped (RobotRuntime), how
// readings go out and drives come back (RemoteLinks), and its robots'
// reports read into one RemoteRound per radio round.
//
// One instant (StepInstant), in the order core/registry/tasks.h declares
// for the world's tasks: faults (9), the drives that came back, physics
// (8, World::Step and the contacts), the sensor drivers' readings (6); then
// the boundary's truth when the robots' round changed. The robots' own tasks
// (5 to 1) run in their processes; the recorder (0) runs once a round's
// reports are in (RecordRound), which for remote robots is some rounds
// after the round's end.
//
// Where the two runtimes differ in what they can know, RemoteRules names it
// (which drives the world takes, whether boundary truths are kept, whether
// reports carry a heading), and RemoteRobotState::reporting says whether a
// robot's reports still arrive.
//
// Usage, per run:
//   RemoteWorld loop(scenario, CollectorConfigFor(scenario), rules);
//   loop.player().StartPresentRobots(runtime);
//   every physics step: loop.StepInstant({now, fault_at, round_now}, runtime, links);
//   per report: loop.NoteRound(robot, state) when it reports its round;
//   once round r's reports are in: loop.RecordRound(r, time_if_no_truth, read);
//   at the end: loop.recorder().FinishReplay(); loop.Finish(end).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/round_recorder.h"
#include "syrof/lab/sim/world_player.h"
#include "syrof/lab/world/world.h"
#include "syrof/motion/drive.h"

namespace syrof::lab::sensors {
class ReadingSink;
class SensorBank;
}  // namespace syrof::lab::sensors

namespace syrof::lab::sim {

/// What a robot's newest round report said of it (DDS: its kRound report).
/// The defaults are a robot that has not reported: not a member, WAIT,
/// AUTONOMOUS, epoch 0.
struct RemoteRobotState {
  bool reported = false;      ///< any round report yet
  uint8_t status = 1;         ///< sync::Status (0: member)
  uint8_t phase = 1;          ///< wire::Phase
  uint8_t epoch_mode = 1;     ///< wire::Mode
  bool estimate_valid = false;
  uint16_t epoch = 0;
  double est_x_m = 0;  ///< double: the firmware's console lines carry more than a float holds
  double est_y_m = 0;
  float est_heading_rad = 0;
  /// Its reports still arrive. A robot the player runs whose reports stopped
  /// (the firmware swarm: its newest console report older than three rounds
  /// on the robots' clock, or none yet) is recorded as not running and
  /// shown absent. The DDS world leaves it true.
  bool reporting = true;
};

/// The rules a runtime's rounds are recorded by, where the runtimes differ.
/// The defaults are the DDS world's.
struct RemoteRules {
  /// Which robots' drives the world takes (RemoteLinks::TakeDrives).
  enum class Drives : uint8_t {
    /// Running robots' only: a drive a robot sent before it stopped is dropped (DDS).
    kRunningRobots,
    /// Every robot's: the firmware's sensor links carry a drive to the world
    /// as it arrives, whatever the robot's lifecycle; a stopped body does
    /// not move, and keeps the drive for when it runs again.
    kEveryRobot,
  };
  Drives drives = Drives::kRunningRobots;
  /// Each round boundary's truth is kept until the round's reports are in
  /// (DDS: they arrive some rounds after the round's end). false (the
  /// firmware swarm, which records a round as it ends on the world's time):
  /// none is kept; a round is the world when RecordRound is called, with
  /// the world's events up to then, and every event of the round is stamped
  /// no later than the round's time.
  bool boundary_truths = true;
  /// The reports carry the estimated heading. false (the firmware's console
  /// lines carry none): a frame shows the true heading as the estimate.
  bool reports_heading = true;
};

/// One radio round's reports, read by the adapter: the common round report.
struct RemoteRound {
  std::vector<replay::Event> events;    ///< the robots' events of the round, any order (sorted by time)
  std::vector<replay::RobotMap> maps;   ///< the maps robots started epochs with in the round
  /// Each robot's round boundary, as the adapter marks it (DDS: the
  /// reporting robot's round task activation; the firmware swarm: its
  /// beacon of the round reaching the host), any one clock: the
  /// round-start skew's sample is their spread (two or more).
  std::vector<int64_t> activations_ns;
  std::vector<int64_t> phase_boundaries_ns;  ///< each reporting member's round boundary, run time
};

/// How readings go out to the robots and drives come back: the transport's part.
class RemoteLinks {
 public:
  virtual ~RemoteLinks() = default;
  /// The drives that came back since the last call, each to `apply(robot, command)`.
  virtual void TakeDrives(const std::function<void(uint16_t, const motion::DriveCommand&)>& apply) = 0;
  /// Where robot `id`'s readings go; nullptr: nowhere now (its link is
  /// closed), and the robot is not sampled at this instant.
  virtual sensors::ReadingSink* Readings(uint16_t id) = 0;
};

class RemoteWorld {
 public:
  /// `scenario` outlives the loop; `config` is the collector's
  /// (CollectorConfigFor(scenario)). Every robot starts absent.
  RemoteWorld(const scenario::Scenario& scenario, const metrics::CollectorConfig& config, RemoteRules rules = {});
  ~RemoteWorld();
  RemoteWorld(const RemoteWorld&) = delete;
  RemoteWorld& operator=(const RemoteWorld&) = delete;

  world::World& world() { return world_; }
  const world::World& world() const { return world_; }
  WorldPlayer& player() { return player_; }
  const WorldPlayer& player() const { return player_; }
  RoundRecorder& recorder() { return recorder_; }

  /// One physics step's instant.
  struct Instant {
    int64_t now_ns = 0;    ///< run time of the step (world time); increases by the physics step
    int64_t faults_ns = 0;  ///< the faults due by this time are played (now_ns, or a step ahead)
    double step_s = 0;      ///< the physics step's length
    int64_t round = 0;      ///< the robots' round at now_ns: boundaries up to it get their truth
  };
  /// Steps `instant`: the faults due (through `runtime`), the drives
  /// `links` took (RemoteRules::drives), World::Step and the contacts,
  /// the running robots' readings of the instant to `links` (a robot whose
  /// Readings is nullptr skipped), then, with RemoteRules::boundary_truths,
  /// the truth of every round boundary up to `instant.round` not yet kept
  /// (with the world's events since the boundary before).
  void StepInstant(const Instant& instant, RobotRuntime& runtime, RemoteLinks& links);

  /// Robot `id` reported its round: its newest state, for its frames, its
  /// metrics entry and its events' stamp.
  void NoteRound(uint16_t id, const RemoteRobotState& state) { robots_[id] = state; }
  const RemoteRobotState& robot(uint16_t id) const { return robots_[id]; }
  /// Robot `id`'s events' stamp: its newest report's epoch and mode (zero
  /// before any), as RobotRuntime::Stamp gives it.
  EventStamp Stamp(uint16_t id) const;

  /// Records round `round` from `read`: the boundary's truth kept for it
  /// (or the world now when none was, at `time_ns_without_truth`; without
  /// RemoteRules::boundary_truths, always so, with the world's events up to
  /// now, every event stamped no later than that time), every
  /// robot's RobotRound and RobotFrame from its newest report, the events
  /// (the world's first, then `read`'s, by time), the maps, the running
  /// poses; and a round-start skew sample from `read.activations_ns`.
  void RecordRound(int64_t round, int64_t time_ns_without_truth, RemoteRound& read);

  /// Round-start skew over the rounds recorded: one sample a round, the
  /// spread (latest minus earliest) of its `activations_ns`.
  metrics::SkewStats skew() const { return metrics::SkewOf(skews_ns_); }

  /// The run's metrics (RoundRecorder::Facts and Finish) at `end`, with
  /// the round-start skew (metrics.json `round_start_skew_us`).
  metrics::Metrics Finish(const RunEnd& end);
  /// The same from `facts` the adapter amended (RoundRecorder::Facts).
  metrics::Metrics Finish(const metrics::RunFacts& facts);

 private:
  // What the world saw at a round boundary; recorded once the round's
  // reports are in.
  struct BoundaryTruth {
    int64_t time_ns = 0;  // run time of the physics step that took it
    std::vector<world::BodyState> bodies;
    std::vector<replay::Presence> presence;
    std::vector<replay::Event> events;  // the world's own (faults, contacts) since the boundary before
  };

  void KeepBoundaryTruths(int64_t now_ns, int64_t round);
  void BuildFrames(const BoundaryTruth* truth, int64_t round_time_ns);

  const uint16_t size_;
  const RemoteRules rules_;
  world::World world_;
  RoundRecorder recorder_;
  WorldPlayer player_;
  std::vector<std::unique_ptr<sensors::SensorBank>> banks_;
  std::vector<RemoteRobotState> robots_;
  std::map<int64_t, BoundaryTruth> truths_;
  int64_t next_truth_ = 1;  // the next round whose boundary truth is taken
  std::vector<int64_t> skews_ns_;
  std::vector<metrics::RobotRound> robot_rounds_;
  std::vector<replay::RobotFrame> frames_;
};

}  // namespace syrof::lab::sim
