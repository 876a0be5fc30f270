#include "syrof/lab/sim/simulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <new>
#include <span>
#include <string>
#include <variant>

#include "syrof/base/check.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/apps/builtin_goals.h"
#include "syrof/lab/metrics/agreement.h"
#include "lab_robot.h"
#include "observer_call.h"
#include "robot_chunks.h"
#include "syrof/lab/sim/world_player.h"
#include "syrof/lab/sim/observation.h"
#include "syrof/lab/sim/radio_network.h"
#include "syrof/lab/sim/recording_app.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/round_recorder.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/world/world.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/queries/queries.h"
#include "syrof/registry/tasks.h"
#include "units.h"

namespace syrof::lab::sim {
namespace {

using scenario::Scenario;

using registry::kFaultPriority;
using registry::kPhysicsPriority;
using registry::kRecorderPriority;
constexpr int kTasksPerRobot = 4;  // state, Kalman, round, motion
constexpr int kWorldTasks = 5;     // faults, physics, hardware, radio, recorder
constexpr int64_t kNoBoundary = std::numeric_limits<int64_t>::min();

}  // namespace

// A periodic task that calls a member function of the simulation. Outside
// the anonymous namespace: Simulation::Impl holds some, and a member's type
// from an anonymous namespace is refused (-Wsubobject-linkage) when this
// file is part of lab/sim's unity unit.
class CallbackTask final : public os::Task {
 public:
  explicit CallbackTask(std::function<void(int64_t)> step) : step_(std::move(step)) {}
  void Step(int64_t now_ns) override { step_(now_ns); }

 private:
  std::function<void(int64_t)> step_;
};

// ---- The simulation -------------------------------------------------------

class Simulation::Impl final : public runtime::RobotObserver,
                               private RobotRuntime,
                               private BeaconReceivers,
                               public AppStateSink,
                               private ObserverCallHandler {
 public:
  Impl(const Scenario& scenario, const SimulationOptions& options);

  void RunUntil(double end_s);
  RunReport Finish(double wall_seconds);
  double now_s() const { return static_cast<double>(scheduler_.now_ns()) * 1e-9; }

  // runtime::RobotObserver
  void OnEpochStart(uint16_t robot, int64_t now_ns, const sync::LDMap& ldmap) override;
  void OnMembership(uint16_t robot, int64_t now_ns, const wire::MemberSet& removed,
                    const wire::MemberSet& joined) override;
  void OnBecameJoiner(uint16_t robot, int64_t now_ns) override;
  void OnAppFault(uint16_t robot, int64_t now_ns, app::Callback callback, uint16_t epoch,
                  const app::CallStatus& status) override;
  void OnInvalidCommand(uint16_t robot, int64_t now_ns, uint16_t epoch, const app::CommandCheck& check) override;
  void OnPayloadRefused(uint16_t robot, int64_t now_ns, uint16_t epoch, size_t length) override;
  void OnSafetyIntervention(uint16_t robot, int64_t time_ns, uint16_t other) override;
  void OnSafetyPrecaution(uint16_t robot, int64_t time_ns, uint16_t other) override;

  // AppStateSink (public: the robots' RecordingApps report here)
  void OnAppState(uint16_t robot, bool new_round, const syrof_ldmap& ldmap, uint8_t state) override;

  Scenario scenario_;
  SimulationOptions options_;
  int64_t radio_round_ns_;
  int64_t physics_step_ns_;
  int64_t end_ns_;
  os::SimScheduler scheduler_;
  os::SimPort world_port_;
  // --threads: how the robots are cut into chunks (robot_chunks.h), fixed
  // before the robots are made: chunk c lends its robots' apps
  // workspaces_[c] (the scratch memory of their matching), since a chunk
  // runs on one thread at a time, whichever takes it.
  ChunkPlan chunk_plan_;
  std::vector<std::unique_ptr<QueriesWorkspace>> workspaces_;
  // The scenario's app params as syrofAppParameter answers them (names view
  // scenario_.app.params' keys, which never change during the run).
  std::vector<app::Parameter> app_params_;
  // Each robot's private inputs (syrofAppInput), by id; names view
  // scenario_.inputs' keys.
  std::vector<std::vector<app::Parameter>> app_inputs_;
  // Every robot's kind by id, the same table for all (RobotConfig::member_kinds).
  std::vector<motion::RobotKind> member_kinds_;
  world::World world_;
  RadioNetwork radio_;
  std::vector<std::unique_ptr<LabRobot>> robots_;
  // The metrics, the goal checks and the replay, round by round
  // (round_recorder.h), and the robots' lifecycle, the faults, the join
  // wait and the world's own events (world_player.h): what every runtime
  // shares.
  RoundRecorder recorder_;
  WorldPlayer player_;

  CallbackTask fault_task_;
  CallbackTask physics_task_;
  CallbackTask hardware_task_;
  CallbackTask radio_task_;
  CallbackTask recorder_task_;
  std::vector<replay::RobotFrame> frames_;
  std::vector<replay::RobotMap> round_maps_;  // the maps robots started an epoch with this round
  std::vector<metrics::RobotRound> robot_rounds_;
  std::vector<uint8_t> partition_active_;
  std::vector<std::shared_ptr<const replay::EpochMap>> last_replay_maps_;  // ReplayMapOf's, per chunk
  // --threads: the workers and the batches (null with one worker);
  // destroyed before the robots, whose steps its workers run.
  std::unique_ptr<RobotChunks> chunks_;

 private:
  // The constructor's steps, in order.
  void MakeRobots();
  void AddWorldTasks();
  void AttachRobots();
  void OpenRecorder();
  void StartWorld();
  void StartThreads();

  int64_t RoundOf(int64_t now_ns) const { return now_ns / radio_round_ns_; }
  // Whether the world's per-robot work runs chunk by chunk on the workers.
  bool SideBySide() const { return chunks_ != nullptr && robots_.size() >= kMinParallelSteps; }
  void StepFaults(int64_t now_ns);
  void StepPhysics(int64_t now_ns);
  void StepHardware(int64_t now_ns);
  void StepRadio(int64_t now_ns);
  void StepRecorder(int64_t now_ns);
  // BeaconReceivers
  bool Listening(uint16_t robot) const override;
  void Receive(uint16_t robot, std::span<const wire::Beacon* const> beacons) override;
  void ReceiveAt(uint16_t robot, const wire::Beacon& beacon, int64_t arrival_ns) override;
  // Observations carry the robots' local times; the lab's records use the
  // scheduler's (true) time, which is the same without clocks.
  int64_t TrueNow() const { return scheduler_.now_ns(); }
  std::vector<int64_t> phase_boundaries_;
  std::vector<int64_t> round_boundaries_;  // per robot, kNoBoundary when it has none this round
  // An event of `robot` (or replay::kNoRobot) stamped with the robot's
  // epoch and that epoch's mode at this moment (docs/replay.md).
  void AddEvent(replay::EventKind kind, int64_t now_ns, uint16_t robot, uint16_t other = replay::kNoRobot);
  void AddEvent(replay::EventKind kind, int64_t now_ns, uint16_t robot, uint16_t other, uint16_t epoch,
                wire::Mode mode);
  // RobotRuntime: the lab switches a robot's port on and off.
  bool StartRobot(uint16_t id, int64_t now_ns, bool resume) override;
  void StopRobot(uint16_t id, int64_t now_ns, StopReason reason) override;
  EventStamp Stamp(uint16_t id) const override;

  // What a robot's step tells the lab (observer_call.h): handled at once,
  // or, during a batch on the workers, kept and handled after it.
  void Report(uint16_t robot, ObserverCall::What what);
  // `ldmap` as the replay stores it, made in the robot's step (so on its
  // worker); the same object as the last map its chunk made when equal,
  // which spares the replay writer checking, hashing and comparing it again
  // (a COOPERATIVE epoch's map of 1000 members, 1000 times, on one thread).
  std::shared_ptr<const replay::EpochMap> ReplayMapOf(uint16_t robot, const sync::LDMap& ldmap);
  // ObserverCallHandler
  void Handle(const ObserverCall& call) override;
  void Handle(const ObserverCall& call, const ObserverCall::EpochStart& epoch_start);
  void Handle(const ObserverCall& call, const ObserverCall::Membership& membership);
  void Handle(const ObserverCall& call, const ObserverCall::BecameJoiner& became_joiner);
  void Handle(const ObserverCall& call, const ObserverCall::AppFault& fault);
  void Handle(const ObserverCall& call, const ObserverCall::InvalidCommand& invalid);
  void Handle(const ObserverCall& call, const ObserverCall::PayloadRefused& refused);
  void Handle(const ObserverCall& call, const ObserverCall::SafetyIntervention& intervention);
  void Handle(const ObserverCall& call, const ObserverCall::AppState& app_state);
};

Simulation::Impl::Impl(const Scenario& scenario, const SimulationOptions& options)
    : scenario_(scenario),
      options_(options),
      radio_round_ns_(Nanoseconds(scenario.timing.radio_round_s)),
      physics_step_ns_(Nanoseconds(scenario.timing.physics_step_s)),
      end_ns_(Nanoseconds(scenario.timing.duration_s)),
      scheduler_(scenario.robots.size() * kTasksPerRobot + kWorldTasks),
      world_port_(scheduler_, "world"),
      chunk_plan_(scenario.robots.size(), options.threads, scenario.clocks.enabled),
      world_(scenario.arena, Bodies(scenario), scenario.seed),
      radio_(scenario.channel, static_cast<uint16_t>(scenario.robots.size()), ChannelSeed(scenario.seed)),
      recorder_(scenario_, CollectorConfigFor(scenario_)),
      player_(scenario_, world_, recorder_.collector()),
      fault_task_([this](int64_t now_ns) { StepFaults(now_ns); }),
      physics_task_([this](int64_t now_ns) { StepPhysics(now_ns); }),
      hardware_task_([this](int64_t now_ns) { StepHardware(now_ns); }),
      radio_task_([this](int64_t now_ns) { StepRadio(now_ns); }),
      recorder_task_([this](int64_t now_ns) { StepRecorder(now_ns); }),
      partition_active_(scenario.channel.partitions.size(), 0),
      last_replay_maps_(chunk_plan_.chunks()) {
  recorder_.MeasureAgreement();  // the robots' observers report every app return
  MakeRobots();
  AddWorldTasks();
  AttachRobots();
  OpenRecorder();
  StartWorld();
  StartThreads();
}

// Each robot's software (its config, app and private inputs) on its own
// port; with clocks, each port's drift and the radio's clocked delivery.
void Simulation::Impl::MakeRobots() {
  for (const auto& [name, value] : scenario_.app.params) app_params_.push_back(app::Parameter{name, value});
  radio_.SetRadioFaults(scenario_.faults);
  robots_.reserve(scenario_.robots.size());
  app_inputs_.reserve(scenario_.robots.size());
  member_kinds_ = MemberKindsOf(scenario_);
  for (size_t chunk = 0; chunk < chunk_plan_.chunks(); ++chunk) workspaces_.push_back(std::make_unique<QueriesWorkspace>());
  for (const scenario::RobotSpec& spec : scenario_.robots) {
    runtime::RobotConfig config = RobotConfigFor(scenario_, spec);
    config.queries_workspace = workspaces_[chunk_plan_.ChunkOf(spec.id)]->handle();
    config.app_params = app_params_;
    app_inputs_.push_back(InputsOf(scenario_, spec.id));
    config.app_inputs = app_inputs_.back();
    config.member_kinds = member_kinds_;
    if (options_.configure_robot) options_.configure_robot(config);
    std::unique_ptr<app::App> app =
        options_.apps.factory ? options_.apps.factory(spec.id)
                             : apps::MakeBuiltinApp(apps::BareAppName(scenario_.app.name), scenario_.app.params);
    SYROF_CHECK(app != nullptr);
    app = std::make_unique<RecordingApp>(std::move(app), spec.id, *this, options_.state_digests);
    robots_.push_back(std::make_unique<LabRobot>(scenario_, spec, scheduler_, world_, config, std::move(app),
                                                 radio_.radio(spec.id)));
    if (scenario_.clocks.enabled) {
      robots_.back()->port().SetDriftPpb(static_cast<int32_t>(std::llround(scenario_.clocks.drift_ppm[spec.id] * 1e3)));
    }
  }
  if (scenario_.clocks.enabled) {
    radio_.UseClocks([this] { return scheduler_.now_ns(); }, *this, radio_round_ns_,
                     Nanoseconds(scenario_.clocks.jitter_ms * 1e-3), JitterSeed(scenario_.seed));
  }
}

// The world's tasks on the world port, their order within an instant set
// by their priorities (registry/tasks.h).
void Simulation::Impl::AddWorldTasks() {
  SYROF_CHECK(world_port_.AddTask(fault_task_, {"lab.faults", os::Trigger::periodic(physics_step_ns_),
                                                kFaultPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(physics_task_, {"lab.physics",
                                                  os::Trigger::periodic(physics_step_ns_, physics_step_ns_),
                                                  kPhysicsPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(hardware_task_, {"lab.hardware",
                                                   os::Trigger::periodic(registry::kImuPeriodNs),
                                                   registry::kSensorTaskPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(radio_task_, {"lab.radio", os::Trigger::periodic(radio_round_ns_, radio_round_ns_),
                                                registry::kRadioDeliveryPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(recorder_task_, {"lab.recorder",
                                                   os::Trigger::periodic(radio_round_ns_, radio_round_ns_),
                                                   kRecorderPriority})
                  .ok());
}

void Simulation::Impl::AttachRobots() {
  for (auto& robot : robots_) {
    robot->robot().set_observer(this);  // before Attach: init may fault
    robot->Attach();
  }
}

// The recorder's name for the app, its sinks and replay, and the per-robot
// rows StepRecorder fills each round.
void Simulation::Impl::OpenRecorder() {
  // A runtime-supplied app (the grader's or --app's library) is the run's
  // app in the replay and the goal, not the scenario's `app:`.
  recorder_.NameApp(options_.apps.source);
  for (replay::RoundSink* sink : options_.sinks) recorder_.AddSink(sink);
  if (options_.replay != nullptr) recorder_.OpenReplay(*options_.replay);
  phase_boundaries_.reserve(robots_.size());
  frames_.resize(robots_.size());
  robot_rounds_.resize(robots_.size());
  round_boundaries_.resize(robots_.size());
}

void Simulation::Impl::StartWorld() {
  SYROF_CHECK(world_port_.Start() == os::PortError::kOk);
  player_.StartPresentRobots(*this);
}

// --threads: the radio's receiver blocks are the chunks (each decides its
// links on its own copy of the channel), and the scheduler hands batches of
// robot steps to the chunks' workers.
void Simulation::Impl::StartThreads() {
  if (chunk_plan_.workers() == 1) return;
  radio_.SplitReceivers(chunk_plan_.FirstRobots());
  std::vector<os::SimPort*> robot_ports;
  for (const auto& robot : robots_) robot_ports.push_back(&robot->port());
  ObserverCallHandler& handler = *this;
  chunks_ = std::make_unique<RobotChunks>(chunk_plan_, std::move(robot_ports), handler);
  scheduler_.set_batch_runner(chunks_.get());
}

bool Simulation::Impl::StartRobot(uint16_t id, int64_t /*now_ns*/, bool /*resume*/) {
  // With clocks, a robot boots its offset later than the lab switches it on.
  const int64_t boot_delay_ns = scenario_.clocks.enabled ? Nanoseconds(scenario_.clocks.offset_ms[id] * 1e-3) : 0;
  SYROF_CHECK(robots_[id]->port().StartAfter(boot_delay_ns) == os::PortError::kOk);
  return true;
}

void Simulation::Impl::StopRobot(uint16_t id, int64_t /*now_ns*/, StopReason /*reason*/) {
  LabRobot& robot = *robots_[id];
  if (robot.port().running()) SYROF_CHECK(robot.port().Stop() == os::PortError::kOk);
  robot.robot().DropReceived();  // what its radio held is lost with it
}

EventStamp Simulation::Impl::Stamp(uint16_t id) const {
  const sync::SyncState& state = robots_[id]->robot().sync_state();
  return EventStamp{state.epoch, state.epoch_mode};
}

void Simulation::Impl::AddEvent(replay::EventKind kind, int64_t now_ns, uint16_t robot, uint16_t other) {
  if (robot >= robots_.size()) {
    AddEvent(kind, now_ns, robot, other, 0, wire::Mode::kCooperative);
    return;
  }
  const sync::SyncState& state = robots_[robot]->robot().sync_state();
  AddEvent(kind, now_ns, robot, other, state.epoch, state.epoch_mode);
}

void Simulation::Impl::AddEvent(replay::EventKind kind, int64_t now_ns, uint16_t robot, uint16_t other,
                                uint16_t epoch, wire::Mode mode) {
  replay::Event event{};
  event.kind = kind;
  event.robot = robot;
  event.other = other;
  event.epoch = epoch;
  event.mode = static_cast<uint8_t>(mode);
  event.time_ns = now_ns;
  player_.AddEvent(event);
}

// Faults take effect on the radio-round grid (fault_schedule.h).
void Simulation::Impl::StepFaults(int64_t now_ns) { player_.PlayFaults(now_ns, *this); }

void Simulation::Impl::StepPhysics(int64_t now_ns) {
  world_.Step(now_ns, static_cast<double>(physics_step_ns_) * 1e-9);
  player_.TakeContacts(*this);
}

void Simulation::Impl::StepHardware(int64_t now_ns) {
  if (!SideBySide()) {
    for (auto& robot : robots_) {
      if (robot->port().running()) robot->StepHardware(now_ns);
    }
    return;
  }
  // Worker w samples its own robots' sensors, which publish to their own
  // brokers (the notifications wait, os::SimScheduler::BeginSideBySide);
  // the drive commands they took reach the bodies here, after.
  scheduler_.BeginSideBySide(chunks_->robot_ports());
  chunks_->ForEachChunk([this](size_t chunk) {
    for (size_t robot = chunk_plan_.begin(chunk); robot < chunk_plan_.end(chunk); ++robot) {
      if (robots_[robot]->port().running()) robots_[robot]->SampleHardware();
    }
  });
  scheduler_.EndSideBySide();
  for (auto& robot : robots_) robot->ApplyDrive();
}

// The beacons broadcast at the end of the previous round travel now
// (radio_network.h), to every running robot.
void Simulation::Impl::StepRadio(int64_t now_ns) {
  if (scenario_.clocks.enabled) return;  // beacons travel when sent (radio_network.h)
  const int64_t round = RoundOf(now_ns) - 1;
  const double sent_at_s = static_cast<double>(round * radio_round_ns_) * 1e-9;
  if (chunks_ == nullptr) {
    radio_.Deliver(round, sent_at_s, *this);
    return;
  }
  // Worker w encodes and decodes its own robots' beacons, then, once all
  // are decoded, hands its own robots their beacons (each receiver's inbox
  // and its block's channel copy are its own).
  radio_.BeginDelivery(round, sent_at_s, *this);
  if (robots_.size() < kMinParallelSteps) {
    for (size_t block = 0; block < radio_.blocks(); ++block) radio_.EncodeBlock(block);
    radio_.EndEncoding();
    for (size_t block = 0; block < radio_.blocks(); ++block) radio_.DeliverToBlock(block, *this);
    return;
  }
  chunks_->ForEachChunk([this](size_t chunk) { radio_.EncodeBlock(chunk); });
  radio_.EndEncoding();
  chunks_->ForEachChunk([this](size_t chunk) { radio_.DeliverToBlock(chunk, *this); });
}

bool Simulation::Impl::Listening(uint16_t robot) const { return robots_[robot]->port().running(); }

void Simulation::Impl::Receive(uint16_t robot, std::span<const wire::Beacon* const> beacons) {
  robots_[robot]->robot().Receive(beacons);
}

void Simulation::Impl::ReceiveAt(uint16_t robot, const wire::Beacon& beacon, int64_t arrival_ns) {
  LabRobot& receiver = *robots_[robot];
  receiver.robot().Receive(beacon, receiver.port().LocalFromTrue(arrival_ns));
}

void Simulation::Impl::StepRecorder(int64_t now_ns) {
  const int64_t round = RoundOf(now_ns);
  const double now = static_cast<double>(now_ns) * 1e-9;
  for (size_t i = 0; i < scenario_.channel.partitions.size(); ++i) {
    const world::PartitionSpec& partition = scenario_.channel.partitions[i];
    const uint8_t active = partition.start_s <= now && now < partition.end_s ? 1 : 0;
    if (active != partition_active_[i]) {
      AddEvent(active != 0 ? replay::EventKind::kPartitionStart : replay::EventKind::kPartitionEnd, now_ns,
               replay::kNoRobot, replay::kNoRobot, 0, wire::Mode::kCooperative);
      player_.events().back().partition = static_cast<uint16_t>(i);
      partition_active_[i] = active;
    }
  }
  // One observation per robot feeds both the metrics and the replay, and
  // each running member's latest round boundary, in true time, the round
  // phases. Each robot's are its own slots: the threads take the chunks.
  const auto observe = [this, now_ns](size_t i) {
    const LabRobot& lab_robot = *robots_[i];
    const runtime::Robot& robot = lab_robot.robot();
    const RobotObservation observation =
        Observe(lab_robot.id(), player_.presence(lab_robot.id()), robot.sync_state(), world_.state(lab_robot.id()),
                robot.estimate(), robot.estimate_valid() && now_ns >= player_.scored_from_ns(lab_robot.id()));
    robot_rounds_[i] = ToRobotRound(observation);
    frames_[i] = ToRobotFrame(observation);
    const bool boundary = player_.running(lab_robot.id()) && robot.counters().rounds > 0 &&
                          robot.sync_state().status == sync::Status::kMember;
    round_boundaries_[i] = boundary ? lab_robot.port().TrueFromLocal(robot.last_round_ns()) : kNoBoundary;
  };
  if (!SideBySide()) {
    for (size_t i = 0; i < robots_.size(); ++i) observe(i);
  } else {
    chunks_->ForEachChunk([this, &observe](size_t chunk) {
      for (size_t i = chunk_plan_.begin(chunk); i < chunk_plan_.end(chunk); ++i) observe(i);
    });
  }
  phase_boundaries_.clear();
  for (const int64_t boundary_ns : round_boundaries_) {
    if (boundary_ns != kNoBoundary) phase_boundaries_.push_back(boundary_ns);
  }
  recorder_.RecordRound(RecordedRound{round, now_ns, robot_rounds_, phase_boundaries_, frames_, player_.events(),
                                      round_maps_, [this] { return player_.RunningPoses(); }});
  player_.events().clear();
  round_maps_.clear();
  if (options_.progress && options_.progress_period_s > 0) {
    const int64_t period_ns = Nanoseconds(options_.progress_period_s);
    if (now_ns % period_ns < radio_round_ns_) options_.progress(now);
  }
}

// ---- What the robots tell the lab ------------------------------------------

void Simulation::Impl::Report(uint16_t robot, ObserverCall::What what) {
  const sync::SyncState& state = robots_[robot]->robot().sync_state();
  ObserverCall call{robot, state.epoch, state.epoch_mode, std::move(what)};
  if (chunks_ != nullptr && chunks_->in_batch()) {
    chunks_->Keep(std::move(call));
    return;
  }
  Handle(call);
}

void Simulation::Impl::OnEpochStart(uint16_t robot, int64_t /*local_ns*/, const sync::LDMap& ldmap) {
  Report(robot, ObserverCall::EpochStart{&ldmap, recorder_.replaying() ? ReplayMapOf(robot, ldmap) : nullptr});
}

std::shared_ptr<const replay::EpochMap> Simulation::Impl::ReplayMapOf(uint16_t robot, const sync::LDMap& ldmap) {
  std::shared_ptr<const replay::EpochMap>& last = last_replay_maps_[chunk_plan_.ChunkOf(robot)];
  if (last == nullptr || !MatchesEpochMap(*last, ldmap)) last = ToEpochMap(ldmap);
  return last;
}

void Simulation::Impl::OnMembership(uint16_t robot, int64_t /*local_ns*/, const wire::MemberSet& removed,
                                    const wire::MemberSet& joined) {
  Report(robot, ObserverCall::Membership{&removed, &joined});
}

void Simulation::Impl::OnBecameJoiner(uint16_t robot, int64_t /*local_ns*/) {
  Report(robot, ObserverCall::BecameJoiner{});
}

void Simulation::Impl::OnAppState(uint16_t robot, bool new_round, const syrof_ldmap& ldmap, uint8_t state) {
  Report(robot, ObserverCall::AppState{new_round, ldmap.mode == SYROF_MODE_COOPERATIVE, ldmap.epoch,
                                       MapFingerprint(ldmap), state});
}

void Simulation::Impl::OnAppFault(uint16_t robot, int64_t /*local_ns*/, app::Callback callback, uint16_t epoch,
                                  const app::CallStatus& status) {
  Report(robot, ObserverCall::AppFault{callback, epoch, status});
}

void Simulation::Impl::OnInvalidCommand(uint16_t robot, int64_t /*local_ns*/, uint16_t epoch,
                                        const app::CommandCheck& check) {
  Report(robot, ObserverCall::InvalidCommand{epoch, check});
}

void Simulation::Impl::OnPayloadRefused(uint16_t robot, int64_t /*local_ns*/, uint16_t epoch, size_t length) {
  Report(robot, ObserverCall::PayloadRefused{epoch, length});
}

void Simulation::Impl::OnSafetyIntervention(uint16_t robot, int64_t local_ns, uint16_t other) {
  Report(robot, ObserverCall::SafetyIntervention{local_ns, other, false});
}

void Simulation::Impl::OnSafetyPrecaution(uint16_t robot, int64_t local_ns, uint16_t other) {
  Report(robot, ObserverCall::SafetyIntervention{local_ns, other, true});
}

void Simulation::Impl::Handle(const ObserverCall& call) {
  std::visit([this, &call](const auto& what) { Handle(call, what); }, call.what);
}

void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::EpochStart& epoch_start) {
  const int64_t now_ns = TrueNow();
  const sync::LDMap& ldmap = *epoch_start.ldmap;
  recorder_.OnEpochStart(call.robot, RoundOf(now_ns), now_ns, ldmap);
  AddEvent(replay::EventKind::kEpochStart, now_ns, call.robot, replay::kNoRobot, ldmap.epoch, ldmap.mode);
  if (epoch_start.map != nullptr) round_maps_.push_back(replay::RobotMap{call.robot, epoch_start.map});
}

void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::Membership& membership) {
  const int64_t now_ns = TrueNow();
  recorder_.collector().OnMembership(call.robot, RoundOf(now_ns), *membership.removed, *membership.joined);
  for (const uint16_t member : *membership.removed) {
    AddEvent(replay::EventKind::kMemberRemoved, now_ns, call.robot, member, call.epoch, call.mode);
  }
  for (const uint16_t member : *membership.joined) {
    AddEvent(replay::EventKind::kMemberJoined, now_ns, call.robot, member, call.epoch, call.mode);
  }
}

void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::BecameJoiner& /*became_joiner*/) {
  AddEvent(replay::EventKind::kBecameJoiner, TrueNow(), call.robot, replay::kNoRobot, call.epoch, call.mode);
}

void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::AppState& app_state) {
  using Call = metrics::AgreementTracker::Call;
  recorder_.OnAppState(call.robot, RoundOf(TrueNow()), app_state.new_round ? Call::kNewRound : Call::kEndOfRound,
                       app_state.map_epoch, app_state.cooperative, app_state.fingerprint, app_state.state);
}

// A robot whose app faulted is stopped as a crashed robot is (its software
// stops, its body stays, the others' failure detectors remove it) and the
// run goes on. Reported from inside the robot's own step (or from Attach,
// for init), which the robot ends without another app call.
void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::AppFault& fault) {
  const int64_t now_ns = TrueNow();
  recorder_.collector().OnAppFault(metrics::AppFault{call.robot, app::ToString(fault.callback), fault.call_epoch,
                                                     now_ns, app::ToString(fault.status.verdict()),
                                                     fault.status.detail()});
  AddEvent(replay::EventKind::kAppFault, now_ns, call.robot, replay::kNoRobot, fault.call_epoch, call.mode);
  player_.AppFaulted(call.robot, now_ns, *this);
}

// The metrics count every invalid command and refused payload; the replay
// records the first of each per robot.
void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::InvalidCommand& invalid) {
  std::array<char, 64> what{};
  recorder_.collector().OnInvalidCommand(call.robot, invalid.call_epoch,
                                         app::Describe(invalid.check, what.data(), what.size()));
  LabRobot& robot = *robots_[call.robot];
  if (robot.invalid_command_recorded) return;
  robot.invalid_command_recorded = true;
  AddEvent(replay::EventKind::kInvalidCommand, TrueNow(), call.robot, replay::kNoRobot, invalid.call_epoch,
           call.mode);
}

void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::PayloadRefused& refused) {
  recorder_.collector().OnPayloadRefused(call.robot, refused.call_epoch, std::to_string(refused.length) + " bytes");
  LabRobot& robot = *robots_[call.robot];
  if (robot.payload_refusal_recorded) return;
  robot.payload_refusal_recorded = true;
  AddEvent(replay::EventKind::kPayloadRefused, TrueNow(), call.robot, replay::kNoRobot, refused.call_epoch,
           call.mode);
}

void Simulation::Impl::Handle(const ObserverCall& call, const ObserverCall::SafetyIntervention& intervention) {
  const int64_t time_ns = robots_[call.robot]->port().TrueFromLocal(intervention.local_ns);
  const bool wall = intervention.other == motion::kWallObstacle;
  const std::optional<uint16_t> other = wall ? std::nullopt : std::optional<uint16_t>(intervention.other);
  if (intervention.precaution) {
    recorder_.collector().OnSafetyPrecaution(call.robot, other);
    return;
  }
  recorder_.collector().OnSafetyIntervention(time_ns, call.robot, other);
  AddEvent(replay::EventKind::kSafetyIntervention, time_ns, call.robot, wall ? replay::kNoRobot : intervention.other,
           call.epoch, call.mode);
}

void Simulation::Impl::RunUntil(double end_s) {
  const int64_t end_ns = std::min(end_ns_, Nanoseconds(end_s));
  if (end_ns > scheduler_.now_ns()) scheduler_.RunUntil(end_ns);
}

RunReport Simulation::Impl::Finish(double wall_seconds) {
  RunUntil(scenario_.timing.duration_s);
  recorder_.FinishReplay();

  const RunEnd end{now_s(), wall_seconds, scheduler_.now_ns() / radio_round_ns_};
  metrics::RunFacts facts = recorder_.Facts(end, player_, world_);
  facts.app_name = robots_.empty() ? std::string() : robots_.front()->app_name();
  facts.app_source = recorder_.app_name();
  facts.app_sandbox = options_.apps.sandbox;
  RunReport report;
  report.metrics = recorder_.Finish(facts);
  report.metrics_json = metrics::ToJson(report.metrics);
  report.replay_error = recorder_.replay_error();
  return report;
}

// ---- Simulation ------------------------------------------------------------

Simulation::Simulation(const Scenario& scenario, const SimulationOptions& options)
    : impl_(std::make_unique<Impl>(scenario, options)) {}
Simulation::~Simulation() = default;
void Simulation::RunUntil(double end_s) { impl_->RunUntil(end_s); }
void Simulation::RunThroughRoundStart(int64_t round) {
  Impl& impl = *impl_;
  const int64_t end_ns = std::min(impl.end_ns_, round * impl.radio_round_ns_);
  if (end_ns >= impl.scheduler_.now_ns()) impl.scheduler_.RunUntil(end_ns);
}
RunReport Simulation::Finish(double wall_seconds) { return impl_->Finish(wall_seconds); }
double Simulation::now_s() const { return impl_->now_s(); }

std::optional<base::StateDigest::Value> Simulation::StateDigest() const {
  const Impl& impl = *impl_;
  SYROF_CHECK(impl.options_.state_digests);  // the apps' call histories are kept only then
  if (impl.scenario_.clocks.enabled) return std::nullopt;
  base::StateDigest digest;
  impl.scheduler_.AddToDigest(digest);
  impl.world_.AddToDigest(digest);
  impl.radio_.AddToDigest(digest);
  for (const std::unique_ptr<LabRobot>& robot : impl.robots_) robot->AddToDigest(digest);
  impl.player_.AddToDigest(digest);
  impl.recorder_.AddToDigest(digest);
  digest.AddRange(std::span<const uint8_t>(impl.partition_active_));
  return digest.value();
}

int64_t Simulation::PropertyBreaks() const { return impl_->recorder_.PropertyBreaks(); }
size_t Simulation::robot_count() const { return impl_->robots_.size(); }
const runtime::Robot& Simulation::robot(uint16_t id) const { return impl_->robots_.at(id)->robot(); }
const scenario::Scenario& Simulation::scenario() const { return impl_->scenario_; }
const world::World& Simulation::world() const { return impl_->world_; }

RunReport Run(const Scenario& scenario, const SimulationOptions& options, double wall_seconds) {
  Simulation simulation(scenario, options);
  return simulation.Finish(wall_seconds);
}

}  // namespace syrof::lab::sim
