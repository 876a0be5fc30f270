#include "syrof/lab/sim/simulation.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <new>
#include <span>
#include <string>

#include "syrof/base/check.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/apps/builtin_goals.h"
#include "syrof/lab/metrics/agreement.h"
#include "lab_robot.h"
#include "worker_pool.h"
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
// Below this many steps a batch runs on the calling thread: 16 robot steps
// are a few microseconds, about what waking a sleeping worker takes. A
// reasoned guess, not tuned: on the shared machine of docs/lab.md
// ("Threads") no batch size gave a reliable gain to tune against.
constexpr size_t kMinParallelSteps = 16;
constexpr int64_t kNoBoundary = std::numeric_limits<int64_t>::min();
// --threads: the robots are cut into this many chunks per worker, which
// the workers take as they go (a worker first its own chunks, then what is
// left of the others'), so a core that runs slower, or is shared, takes
// fewer: a fixed half per worker left the faster one waiting for the other
// (docs/lab.md, "Threads"). A chunk has at least kMinChunkRobots robots.
constexpr size_t kChunksPerWorker = 4;
constexpr size_t kMinChunkRobots = 8;
constexpr int kNoChunk = -1;

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
                               private os::SimBatchRunner {
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

  // What a robot's step tells the lab (the observer calls above and
  // OnAppState), as data: handled at once, or, during a parallel batch,
  // kept per robot and handled when the batch ends, robot by robot in the
  // order the steps would have run one at a time. It carries what the
  // handling reads of the robot at the moment of the call (its epoch and
  // mode), since the robot's step has gone on by then; ldmap, removed and
  // joined point into the robot, unchanged until its next round step.
  struct ObserverCall {
    enum class Kind : uint8_t {
      kEpochStart,
      kMembership,
      kBecameJoiner,
      kAppFault,
      kInvalidCommand,
      kPayloadRefused,
      kSafetyIntervention,
      kAppState,
    };
    Kind kind;
    uint16_t robot;
    uint16_t epoch;   // the robot's epoch at the call (its events' stamp)
    wire::Mode mode;  // that epoch's mode at the call
    int64_t local_ns = 0;
    const sync::LDMap* ldmap = nullptr;
    std::shared_ptr<const replay::EpochMap> map;  // kEpochStart with a replay: ldmap as the replay stores it
    const wire::MemberSet* removed = nullptr;
    const wire::MemberSet* joined = nullptr;
    uint16_t other = 0;       // kSafetyIntervention
    uint16_t call_epoch = 0;  // the app call's epoch (kAppFault, kInvalidCommand, kPayloadRefused)
    app::Callback callback = app::Callback::kInit;
    app::CallStatus status;
    app::CommandCheck check{};
    size_t length = 0;
    // kAppState
    bool new_round = false;
    bool cooperative = false;
    uint16_t map_epoch = 0;
    uint64_t fingerprint = 0;
    uint8_t state = 0;
  };
  ObserverCall CallOf(ObserverCall::Kind kind, uint16_t robot) const;
  // `ldmap` as the replay stores it, made in the robot's step (so on its
  // worker); the same object as the last map its worker made when equal,
  // which spares the replay writer checking, hashing and comparing it again
  // (a COOPERATIVE epoch's map of 1000 members, 1000 times, on one thread).
  std::shared_ptr<const replay::EpochMap> ReplayMapOf(uint16_t robot, const sync::LDMap& ldmap);
  void Report(const ObserverCall& call);
  void Handle(const ObserverCall& call);

  Scenario scenario_;
  SimulationOptions options_;
  int64_t radio_round_ns_;
  int64_t physics_step_ns_;
  int64_t end_ns_;
  os::SimScheduler scheduler_;
  os::SimPort world_port_;
  QueriesWorkspace workspace_;
  std::vector<std::unique_ptr<QueriesWorkspace>> chunk_workspaces_;  // --threads: chunks 1.. (below)
  // The scenario's app params as syrofAppParameter answers them (names view
  // scenario_.app.params' keys, which never change during the run).
  std::vector<app::Parameter> app_params_;
  // Each robot's private inputs (syrofAppInput), by id; names view
  // scenario_.inputs' keys.
  std::vector<std::vector<app::Parameter>> app_inputs_;
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

  // --threads: the pool (destroyed before the robots), each robot's chunk
  // by port (contiguous blocks of robots, each the radio's receiver block of
  // the same robots; kNoChunk for the world's port), and the observer calls
  // kept during a parallel batch, per robot. Chunk c > 0 lends its robots'
  // apps chunk_workspaces_[c - 1], chunk 0 workspace_: a chunk runs on one
  // thread at a time, whichever takes it.
  std::unique_ptr<WorkerPool> pool_;
  std::vector<int> chunk_of_port_;
  std::vector<uint16_t> robot_of_port_;
  std::vector<std::vector<ObserverCall>> kept_calls_;
  std::vector<std::shared_ptr<const replay::EpochMap>> last_replay_maps_;  // ReplayMapOf's, per chunk
  std::vector<size_t> chunk_starts_;      // chunk c's robots: chunk_starts_[c] .. chunk_starts_[c + 1]
  std::vector<os::SimPort*> robot_ports_;  // in robot order
  // Which chunks are left in the job running now: worker w's own chunks
  // are queues_[w].next .. queues_[w].end, taken from the front by it and
  // then by the others once theirs are done.
  struct alignas(64) ChunkQueue {
    std::atomic<uint32_t> next{0};
    uint32_t begin = 0;
    uint32_t end = 0;
  };
  std::unique_ptr<ChunkQueue[]> queues_;
  int workers_ = 1;
  // Runs run(chunk) for every chunk once, on the pool's workers.
  template <typename Run>
  void ForEachChunk(Run run);
  // RunBatch: the batch's steps of chunk c are batch_[chunk_steps_[i]] for
  // i in chunk_step_begin_[c] .. chunk_step_begin_[c + 1], in batch order.
  std::vector<uint32_t> chunk_steps_;
  std::vector<uint32_t> chunk_step_begin_;
  std::span<const os::SimStep> batch_;
  bool parallel_ = false;  // a parallel batch is running
  // os::SimBatchRunner
  void RunBatch(std::span<const os::SimStep> steps) override;

  // AppStateSink (public: the robots' RecordingApps report here)
  void OnAppState(uint16_t robot, bool new_round, const syrof_ldmap& ldmap, uint8_t state) override;

 private:
  int64_t RoundOf(int64_t now_ns) const { return now_ns / radio_round_ns_; }
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
};

Simulation::Impl::Impl(const Scenario& scenario, const SimulationOptions& options)
    : scenario_(scenario),
      options_(options),
      radio_round_ns_(Nanoseconds(scenario.timing.radio_round_s)),
      physics_step_ns_(Nanoseconds(scenario.timing.physics_step_s)),
      end_ns_(Nanoseconds(scenario.timing.duration_s)),
      scheduler_(scenario.robots.size() * kTasksPerRobot + kWorldTasks),
      world_port_(scheduler_, "world"),
      world_(scenario.arena, Bodies(scenario)),
      radio_(scenario.channel, static_cast<uint16_t>(scenario.robots.size()), ChannelSeed(scenario.seed)),
      recorder_(scenario_, CollectorConfigFor(scenario_)),
      player_(scenario_, world_, recorder_.collector()),
      fault_task_([this](int64_t now_ns) { StepFaults(now_ns); }),
      physics_task_([this](int64_t now_ns) { StepPhysics(now_ns); }),
      hardware_task_([this](int64_t now_ns) { StepHardware(now_ns); }),
      radio_task_([this](int64_t now_ns) { StepRadio(now_ns); }),
      recorder_task_([this](int64_t now_ns) { StepRecorder(now_ns); }),
      partition_active_(scenario.channel.partitions.size(), 0) {
  recorder_.MeasureAgreement();  // the robots' observers report every app return
  for (const auto& [name, value] : scenario_.app.params) app_params_.push_back(app::Parameter{name, value});
  radio_.SetRadioFaults(scenario_.faults);
  robots_.reserve(scenario_.robots.size());
  app_inputs_.reserve(scenario_.robots.size());
  // Threads step robots of one batch side by side. With clocks the radio
  // hands a beacon to its receivers inside the sender's round step
  // (radio_network.h), so robots' steps are not independent, and drifting
  // clocks rarely release two robots at one instant anyway: serial.
  const size_t robot_count = scenario_.robots.size();
  SYROF_CHECK(options_.threads >= 1 && options_.threads <= kMaxThreads);
  const int workers = scenario_.clocks.enabled || robot_count < 2
                          ? 1
                          : static_cast<int>(std::min<size_t>(static_cast<size_t>(options_.threads), robot_count));
  const size_t chunks =
      workers == 1 ? 1
                   : std::max<size_t>(static_cast<size_t>(workers),
                                      std::min(static_cast<size_t>(workers) * kChunksPerWorker, robot_count / kMinChunkRobots));
  const auto chunk_of_robot = [&](size_t robot) { return static_cast<int>(robot * chunks / robot_count); };
  for (size_t chunk = 1; chunk < chunks; ++chunk) chunk_workspaces_.push_back(std::make_unique<QueriesWorkspace>());
  last_replay_maps_.resize(chunks);
  for (const scenario::RobotSpec& spec : scenario_.robots) {
    runtime::RobotConfig config = RobotConfigFor(scenario_, spec);
    const int chunk = chunk_of_robot(spec.id);
    config.queries_workspace = chunk == 0 ? workspace_.handle() : chunk_workspaces_[chunk - 1]->handle();
    config.app_params = app_params_;
    app_inputs_.push_back(InputsOf(scenario_, spec.id));
    config.app_inputs = app_inputs_.back();
    if (options_.configure_robot) options_.configure_robot(config);
    std::unique_ptr<app::App> app =
        options_.app_factory ? options_.app_factory(spec.id)
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
  phase_boundaries_.reserve(robots_.size());

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
  for (auto& robot : robots_) {
    robot->robot().set_observer(this);  // before Attach: init may fault
    robot->Attach();
  }

  // A runtime-supplied app (the grader's or --app's library) is the run's
  // app in the replay and the goal, not the scenario's `app:`.
  recorder_.NameApp(options_.app_source);
  for (replay::RoundSink* sink : options_.sinks) recorder_.AddSink(sink);
  if (options_.replay != nullptr) recorder_.OpenReplay(*options_.replay);
  frames_.resize(robots_.size());
  robot_rounds_.resize(robots_.size());
  round_boundaries_.resize(robots_.size());

  SYROF_CHECK(world_port_.Start() == os::PortError::kOk);
  player_.StartPresentRobots(*this);
  if (workers > 1) {
    uint32_t ports = world_port_.index() + 1;
    for (const auto& robot : robots_) ports = std::max(ports, robot->port().index() + 1);
    chunk_of_port_.assign(ports, kNoChunk);
    robot_of_port_.assign(ports, 0);
    for (const auto& robot : robots_) {
      chunk_of_port_[robot->port().index()] = chunk_of_robot(robot->id());
      robot_of_port_[robot->port().index()] = robot->id();
    }
    kept_calls_.resize(robot_count);
    std::vector<uint16_t> block_starts;
    for (size_t robot = 0; robot < robot_count; ++robot) {
      if (robot == 0 || chunk_of_robot(robot) != chunk_of_robot(robot - 1)) {
        block_starts.push_back(static_cast<uint16_t>(robot));
      }
    }
    SYROF_CHECK(block_starts.size() == chunks);
    radio_.SplitReceivers(block_starts);  // the radio's block c: chunk c's robots
    chunk_starts_.assign(block_starts.begin(), block_starts.end());
    chunk_starts_.push_back(robot_count);
    for (const auto& robot : robots_) robot_ports_.push_back(&robot->port());
    chunk_steps_.resize(robot_count);
    chunk_step_begin_.resize(chunks + 1);
    workers_ = workers;
    queues_ = std::make_unique<ChunkQueue[]>(static_cast<size_t>(workers));
    for (int worker = 0; worker < workers; ++worker) {
      queues_[worker].begin = static_cast<uint32_t>(chunks * static_cast<size_t>(worker) / static_cast<size_t>(workers));
      queues_[worker].end = static_cast<uint32_t>(chunks * static_cast<size_t>(worker + 1) / static_cast<size_t>(workers));
    }
    pool_ = std::make_unique<WorkerPool>(workers);
    scheduler_.set_batch_runner(this);
  }
}

template <typename Run>
void Simulation::Impl::ForEachChunk(Run run) {
  for (int worker = 0; worker < workers_; ++worker) {
    queues_[worker].next.store(queues_[worker].begin, std::memory_order_relaxed);
  }
  auto job = [this, &run](int worker) {
    for (int k = 0; k < workers_; ++k) {
      ChunkQueue& queue = queues_[(worker + k) % workers_];
      for (uint32_t chunk; (chunk = queue.next.fetch_add(1, std::memory_order_relaxed)) < queue.end;) run(chunk);
    }
  };
  pool_->Run(job);
}

// A batch holds one task per robot, due at one instant with one priority
// (os::SimScheduler); each robot's step touches its own robot, port, broker
// and radio slot, and tells the lab what happened through the observer
// calls, which are kept and handled afterwards in the serial order. The
// world's tasks have priorities of their own (registry/tasks.h), so they
// never share a batch with a robot's; a batch that holds one anyway runs
// serially.
void Simulation::Impl::RunBatch(std::span<const os::SimStep> steps) {
  bool robots_only = steps.size() >= kMinParallelSteps;
  for (size_t i = 0; robots_only && i < steps.size(); ++i) {
    robots_only = chunk_of_port_[steps[i].port_index] != kNoChunk;
  }
  if (!robots_only) {
    for (const os::SimStep& step : steps) step.task->Step(step.now_ns);
    return;
  }
  // The steps by chunk (a counting sort that keeps the batch's order).
  const size_t chunks = chunk_starts_.size() - 1;
  std::fill(chunk_step_begin_.begin(), chunk_step_begin_.end(), 0u);
  for (const os::SimStep& step : steps) ++chunk_step_begin_[static_cast<size_t>(chunk_of_port_[step.port_index]) + 1];
  for (size_t chunk = 0; chunk < chunks; ++chunk) chunk_step_begin_[chunk + 1] += chunk_step_begin_[chunk];
  for (uint32_t i = 0; i < steps.size(); ++i) {
    uint32_t& end = chunk_step_begin_[static_cast<size_t>(chunk_of_port_[steps[i].port_index])];
    chunk_steps_[end++] = i;
  }
  for (size_t chunk = chunks; chunk > 0; --chunk) chunk_step_begin_[chunk] = chunk_step_begin_[chunk - 1];
  chunk_step_begin_[0] = 0;
  parallel_ = true;
  batch_ = steps;
  ForEachChunk([this](size_t chunk) {
    for (uint32_t i = chunk_step_begin_[chunk]; i < chunk_step_begin_[chunk + 1]; ++i) {
      const os::SimStep& step = batch_[chunk_steps_[i]];
      step.task->Step(step.now_ns);
    }
  });
  parallel_ = false;
  for (const os::SimStep& step : steps) {
    std::vector<ObserverCall>& calls = kept_calls_[robot_of_port_[step.port_index]];
    for (const ObserverCall& call : calls) Handle(call);
    calls.clear();
  }
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
  if (pool_ == nullptr || robots_.size() < kMinParallelSteps) {
    for (auto& robot : robots_) {
      if (robot->port().running()) robot->StepHardware(now_ns);
    }
    return;
  }
  // Worker w samples its own robots' sensors, which publish to their own
  // brokers (the notifications wait, os::SimScheduler::BeginSideBySide);
  // the drive commands they took reach the bodies here, after.
  scheduler_.BeginSideBySide(robot_ports_);
  ForEachChunk([this](size_t chunk) {
    for (size_t robot = chunk_starts_[chunk]; robot < chunk_starts_[chunk + 1]; ++robot) {
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
  if (pool_ == nullptr) {
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
  ForEachChunk([this](size_t chunk) { radio_.EncodeBlock(chunk); });
  radio_.EndEncoding();
  ForEachChunk([this](size_t chunk) { radio_.DeliverToBlock(chunk, *this); });
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
  if (pool_ == nullptr || robots_.size() < kMinParallelSteps) {
    for (size_t i = 0; i < robots_.size(); ++i) observe(i);
  } else {
    ForEachChunk([this, &observe](size_t chunk) {
      for (size_t i = chunk_starts_[chunk]; i < chunk_starts_[chunk + 1]; ++i) observe(i);
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

Simulation::Impl::ObserverCall Simulation::Impl::CallOf(ObserverCall::Kind kind, uint16_t robot) const {
  ObserverCall call{};
  call.kind = kind;
  call.robot = robot;
  const sync::SyncState& state = robots_[robot]->robot().sync_state();
  call.epoch = state.epoch;
  call.mode = state.epoch_mode;
  return call;
}

void Simulation::Impl::Report(const ObserverCall& call) {
  if (parallel_) {
    kept_calls_[call.robot].push_back(call);  // this robot's own list: only its worker writes it
    return;
  }
  Handle(call);
}

void Simulation::Impl::OnEpochStart(uint16_t robot, int64_t /*local_ns*/, const sync::LDMap& ldmap) {
  ObserverCall call = CallOf(ObserverCall::Kind::kEpochStart, robot);
  call.ldmap = &ldmap;
  if (recorder_.replaying()) call.map = ReplayMapOf(robot, ldmap);
  Report(call);
}

std::shared_ptr<const replay::EpochMap> Simulation::Impl::ReplayMapOf(uint16_t robot, const sync::LDMap& ldmap) {
  const int chunk = pool_ == nullptr ? 0 : chunk_of_port_[robots_[robot]->port().index()];
  std::shared_ptr<const replay::EpochMap>& last = last_replay_maps_[static_cast<size_t>(chunk)];
  if (last == nullptr || !MatchesEpochMap(*last, ldmap)) last = ToEpochMap(ldmap);
  return last;
}

void Simulation::Impl::OnMembership(uint16_t robot, int64_t /*local_ns*/, const wire::MemberSet& removed,
                                    const wire::MemberSet& joined) {
  ObserverCall call = CallOf(ObserverCall::Kind::kMembership, robot);
  call.removed = &removed;
  call.joined = &joined;
  Report(call);
}

void Simulation::Impl::OnBecameJoiner(uint16_t robot, int64_t /*local_ns*/) {
  Report(CallOf(ObserverCall::Kind::kBecameJoiner, robot));
}

void Simulation::Impl::OnAppState(uint16_t robot, bool new_round, const syrof_ldmap& ldmap, uint8_t state) {
  ObserverCall call = CallOf(ObserverCall::Kind::kAppState, robot);
  call.new_round = new_round;
  call.map_epoch = ldmap.epoch;
  call.cooperative = ldmap.mode == SYROF_MODE_COOPERATIVE;
  call.fingerprint = MapFingerprint(ldmap);  // the app's map changes within the step: read it now
  call.state = state;
  Report(call);
}

void Simulation::Impl::OnAppFault(uint16_t robot, int64_t local_ns, app::Callback callback, uint16_t epoch,
                                  const app::CallStatus& status) {
  ObserverCall call = CallOf(ObserverCall::Kind::kAppFault, robot);
  call.local_ns = local_ns;
  call.callback = callback;
  call.call_epoch = epoch;
  call.status = status;
  Report(call);
}

void Simulation::Impl::OnInvalidCommand(uint16_t robot, int64_t local_ns, uint16_t epoch,
                                        const app::CommandCheck& check) {
  ObserverCall call = CallOf(ObserverCall::Kind::kInvalidCommand, robot);
  call.local_ns = local_ns;
  call.call_epoch = epoch;
  call.check = check;
  Report(call);
}

void Simulation::Impl::OnPayloadRefused(uint16_t robot, int64_t local_ns, uint16_t epoch, size_t length) {
  ObserverCall call = CallOf(ObserverCall::Kind::kPayloadRefused, robot);
  call.local_ns = local_ns;
  call.call_epoch = epoch;
  call.length = length;
  Report(call);
}

void Simulation::Impl::OnSafetyIntervention(uint16_t robot, int64_t local_ns, uint16_t other) {
  ObserverCall call = CallOf(ObserverCall::Kind::kSafetyIntervention, robot);
  call.local_ns = local_ns;
  call.other = other;
  Report(call);
}

// A robot whose app faulted is stopped as a crashed robot is (its software
// stops, its body stays, the others' failure detectors remove it) and the
// run goes on. Reported from inside the robot's own step (or from Attach,
// for init), which the robot ends without another app call.
void Simulation::Impl::Handle(const ObserverCall& call) {
  const uint16_t robot = call.robot;
  const int64_t now_ns = TrueNow();
  LabRobot& lab_robot = *robots_[robot];
  switch (call.kind) {
    case ObserverCall::Kind::kEpochStart: {
      const sync::LDMap& ldmap = *call.ldmap;
      recorder_.OnEpochStart(robot, RoundOf(now_ns), now_ns, ldmap);
      AddEvent(replay::EventKind::kEpochStart, now_ns, robot, replay::kNoRobot, ldmap.epoch, ldmap.mode);
      if (call.map != nullptr) round_maps_.push_back(replay::RobotMap{robot, call.map});
      break;
    }
    case ObserverCall::Kind::kMembership:
      recorder_.collector().OnMembership(robot, RoundOf(now_ns), *call.removed, *call.joined);
      for (const uint16_t member : *call.removed) {
        AddEvent(replay::EventKind::kMemberRemoved, now_ns, robot, member, call.epoch, call.mode);
      }
      for (const uint16_t member : *call.joined) {
        AddEvent(replay::EventKind::kMemberJoined, now_ns, robot, member, call.epoch, call.mode);
      }
      break;
    case ObserverCall::Kind::kBecameJoiner:
      AddEvent(replay::EventKind::kBecameJoiner, now_ns, robot, replay::kNoRobot, call.epoch, call.mode);
      break;
    case ObserverCall::Kind::kAppState: {
      using Call = metrics::AgreementTracker::Call;
      recorder_.OnAppState(robot, RoundOf(now_ns), call.new_round ? Call::kNewRound : Call::kEndOfRound,
                           call.map_epoch, call.cooperative, call.fingerprint, call.state);
      break;
    }
    case ObserverCall::Kind::kAppFault:
      recorder_.collector().OnAppFault(metrics::AppFault{robot, app::ToString(call.callback), call.call_epoch, now_ns,
                                              app::ToString(call.status.verdict()), call.status.detail()});
      AddEvent(replay::EventKind::kAppFault, now_ns, robot, replay::kNoRobot, call.call_epoch, call.mode);
      player_.AppFaulted(robot, now_ns, *this);
      break;
    case ObserverCall::Kind::kInvalidCommand: {
      std::array<char, 64> what{};
      recorder_.collector().OnInvalidCommand(robot, call.call_epoch,
                                             app::Describe(call.check, what.data(), what.size()));
      if (lab_robot.invalid_command_recorded) break;
      lab_robot.invalid_command_recorded = true;
      AddEvent(replay::EventKind::kInvalidCommand, now_ns, robot, replay::kNoRobot, call.call_epoch, call.mode);
      break;
    }
    case ObserverCall::Kind::kPayloadRefused:
      recorder_.collector().OnPayloadRefused(robot, call.call_epoch, std::to_string(call.length) + " bytes");
      if (lab_robot.payload_refusal_recorded) break;
      lab_robot.payload_refusal_recorded = true;
      AddEvent(replay::EventKind::kPayloadRefused, now_ns, robot, replay::kNoRobot, call.call_epoch, call.mode);
      break;
    case ObserverCall::Kind::kSafetyIntervention: {
      const int64_t time_ns = lab_robot.port().TrueFromLocal(call.local_ns);
      const bool wall = call.other == motion::kWallObstacle;
      recorder_.collector().OnSafetyIntervention(time_ns, robot,
                                                 wall ? std::nullopt : std::optional<uint16_t>(call.other));
      AddEvent(replay::EventKind::kSafetyIntervention, time_ns, robot, wall ? replay::kNoRobot : call.other,
               call.epoch, call.mode);
      break;
    }
  }
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
  facts.app_sandbox = options_.app_sandbox;
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
