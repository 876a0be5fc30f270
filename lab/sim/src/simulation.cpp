#include "syrof/lab/sim/simulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <new>
#include <span>
#include <string>

#include "syrof/base/check.h"
#include "syrof/base/split_mix64.h"
#include "syrof/estimation/task_config.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/apps/goal.h"
#include "syrof/lab/replay/writer.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sensors/sensor_publishers.h"
#include "syrof/lab/world/channel.h"
#include "syrof/lab/world/world.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/queries/queries.h"
#include "syrof/runtime/task_config.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::lab::sim {
namespace {

using scenario::FaultKind;
using scenario::Scenario;

constexpr uint8_t kFaultPriority = 9;
constexpr uint8_t kPhysicsPriority = 8;
constexpr uint8_t kRecorderPriority = 0;
constexpr int kTasksPerRobot = 4;  // state, Kalman, round, motion
constexpr int kWorldTasks = 5;     // faults, physics, hardware, radio, recorder

// An estimate is scored only this long after its robot started or resumed:
// the filter converges from the known start pose within it.
constexpr int64_t kEstimationWarmupNs = 1'000'000'000;

int64_t Nanoseconds(double seconds) { return std::llround(seconds * 1e9); }

// Seeds derived from the scenario seed, one stream per use, so adding a
// robot does not change another robot's noise.
uint64_t SensorSeed(uint64_t seed, uint16_t robot) {
  return base::SplitMix64Hash(seed ^ base::SplitMix64Hash(0x53454e534f52ULL + robot));
}
uint64_t ChannelSeed(uint64_t seed) { return base::SplitMix64Hash(seed ^ 0x4348414e4e454cULL); }

// The estimator's arena: the one the simulated sensors measure against.
estimation::Arena<float> EstimatorArena(const Scenario& scenario) {
  const estimation::Arena<double>& source = scenario.sensors.arena;
  estimation::Arena<float> arena{};
  arena.width_m = static_cast<float>(source.width_m);
  arena.depth_m = static_cast<float>(source.depth_m);
  arena.tag_height_m = static_cast<float>(source.tag_height_m);
  arena.anchor_count = source.anchor_count;
  for (int i = 0; i < source.anchor_count; ++i) arena.anchors[i] = source.anchors[i].cast<float>();
  return arena;
}

// One queries workspace for every app of the run: the lab runs one robot's
// callback at a time, and a workspace holds nothing between queries.
class QueriesWorkspace {
 public:
  QueriesWorkspace()
      : memory_(static_cast<unsigned char*>(::operator new(syrof_queries_workspace_size(),
                                                            std::align_val_t(syrof_queries_workspace_alignment())))) {
    SYROF_CHECK(syrof_queries_workspace_init(memory_, syrof_queries_workspace_size(), &handle_) ==
                SYROF_QUERIES_OK);
  }
  ~QueriesWorkspace() { ::operator delete(memory_, std::align_val_t(syrof_queries_workspace_alignment())); }
  QueriesWorkspace(const QueriesWorkspace&) = delete;
  QueriesWorkspace& operator=(const QueriesWorkspace&) = delete;
  syrof_queries_workspace* handle() const { return handle_; }

 private:
  unsigned char* memory_;
  syrof_queries_workspace* handle_ = nullptr;
};

// A periodic task that calls a member function of the simulation.
class CallbackTask final : public os::Task {
 public:
  explicit CallbackTask(std::function<void(int64_t)> step) : step_(std::move(step)) {}
  void Step(int64_t now_ns) override { step_(now_ns); }

 private:
  std::function<void(int64_t)> step_;
};

}  // namespace

// ---- One simulated robot: its port, broker, hardware and software ---------

namespace {

// The simulated hardware is lab code, not robot code: one world task steps
// every robot's sensors and actuators (in robot order, at the drivers'
// priority) instead of one task per robot. Its drive subscriptions are read
// by polling, so they name no task: a port ignores notifications to an id
// it does not have (port.h).
constexpr os::TaskId kPolledTask = UINT16_MAX;

// The robot's radio: beacons go to the channel's outbox for the next round.
class LabRadio final : public runtime::Radio {
 public:
  LabRadio(std::vector<wire::Beacon>& outbox, std::vector<uint8_t>& sent, uint16_t id)
      : outbox_(outbox), sent_(sent), id_(id) {}
  void Broadcast(const wire::Beacon& beacon) override {
    outbox_[id_] = beacon;
    sent_[id_] = 1;
  }

 private:
  std::vector<wire::Beacon>& outbox_;
  std::vector<uint8_t>& sent_;
  uint16_t id_;
};

class LabRobot {
 public:
  LabRobot(const Scenario& scenario, const scenario::RobotSpec& spec, os::SimScheduler& scheduler,
           world::World& world, runtime::RobotConfig config, std::unique_ptr<app::App> app, LabRadio radio)
      : spec_(spec),
        world_(world),
        port_(scheduler, "robot"),
        broker_(port_),
        bank_(scenario.sensors, SensorSeed(scenario.seed, spec.id)),
        app_(std::move(app)),
        radio_(radio),
        robot_(config, *app_, radio_) {}

  void Attach() {
    SYROF_CHECK(publishers_.Advertise(broker_) == pubsub::BrokerError::kOk);
    const runtime::RobotSetupError error = robot_.Attach(port_, broker_);
    SYROF_CHECK(error == runtime::RobotSetupError::kOk);
    SYROF_CHECK(drive_.Subscribe(broker_, motion::kDriveTopic, kPolledTask) == pubsub::BrokerError::kOk);
  }

  // The robot's hardware on the lab side of the topics, once per IMU period
  // while the robot runs: the latest drive command to its body, then the
  // sensor readings due, sampled from the body's true state.
  void StepHardware(int64_t now_ns) {
    motion::DriveCommand drive{};
    if (drive_.TakeLatest(drive)) world_.SetDrive(spec_.id, drive);
    bank_.Sample(now_ns, world_.true_state(spec_.id), publishers_);
  }

  uint16_t id() const { return spec_.id; }
  const char* app_name() const { return app_->name(); }
  os::SimPort& port() { return port_; }
  runtime::Robot& robot() { return robot_; }
  const runtime::Robot& robot() const { return robot_; }
  int64_t scored_from_ns = 0;  // estimates before this are not scored (warm-up)
  replay::Presence presence = replay::Presence::kAbsent;
  bool app_faulted = false;              // stopped for good, as if crashed (OnAppFault)
  bool invalid_command_recorded = false;  // the replay records the first of each per robot
  bool payload_refusal_recorded = false;

 private:
  scenario::RobotSpec spec_;
  world::World& world_;
  os::SimPort port_;
  pubsub::StaticBroker<8, 12> broker_;
  sensors::SensorBank bank_;
  sensors::SensorPublishers publishers_;
  pubsub::Subscriber<motion::DriveCommand> drive_;
  std::unique_ptr<app::App> app_;
  LabRadio radio_;
  runtime::Robot robot_;
};

}  // namespace

// ---- The simulation -------------------------------------------------------

class Simulation::Impl final : public runtime::RobotObserver {
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

  Scenario scenario_;
  SimulationOptions options_;
  int64_t radio_round_ns_;
  int64_t physics_step_ns_;
  int64_t end_ns_;
  os::SimScheduler scheduler_;
  os::SimPort world_port_;
  QueriesWorkspace workspace_;
  world::World world_;
  world::Channel channel_;
  std::vector<wire::Beacon> outbox_;
  std::vector<uint8_t> sent_;
  std::vector<wire::Beacon> inflight_;
  std::vector<std::unique_ptr<LabRobot>> robots_;
  metrics::Collector collector_;
  std::unique_ptr<replay::Writer> replay_;

  CallbackTask fault_task_;
  CallbackTask physics_task_;
  CallbackTask hardware_task_;
  CallbackTask radio_task_;
  CallbackTask recorder_task_;
  size_t next_fault_ = 0;
  std::vector<replay::Event> round_events_;
  std::vector<replay::RobotFrame> frames_;
  std::vector<metrics::RobotRound> robot_rounds_;
  std::vector<uint8_t> partition_active_;
  std::array<uint8_t, wire::kMaxBeaconBytes> frame_bytes_{};
  uint64_t beacons_malformed_ = 0;

 private:
  int64_t RoundOf(int64_t now_ns) const { return now_ns / radio_round_ns_; }
  void StepFaults(int64_t now_ns);
  void StepPhysics(int64_t now_ns);
  void StepHardware(int64_t now_ns);
  void StepRadio(int64_t now_ns);
  void StepRecorder(int64_t now_ns);
  void AddEvent(replay::EventKind kind, int64_t now_ns, uint16_t robot, uint16_t other = 0xFFFF,
                uint16_t epoch = 0, uint8_t mode = 0);
  void StartRobot(LabRobot& robot, int64_t now_ns);
  void StopRobot(LabRobot& robot, replay::Presence presence);
};

namespace {

std::vector<world::BodySpec> Bodies(const Scenario& scenario) {
  std::vector<world::BodySpec> bodies;
  for (const scenario::RobotSpec& robot : scenario.robots) {
    world::BodySpec body{};
    body.id = robot.id;
    body.kind = robot.kind;
    body.spec = scenario.kind_spec(robot.kind);
    body.x_m = robot.x_m;
    body.y_m = robot.y_m;
    body.heading_rad = robot.heading_rad;
    body.presence = robot.present_at_start ? world::BodyPresence::kActive : world::BodyPresence::kAbsent;
    bodies.push_back(body);
  }
  return bodies;
}

}  // namespace

Simulation::Impl::Impl(const Scenario& scenario, const SimulationOptions& options)
    : scenario_(scenario),
      options_(options),
      radio_round_ns_(Nanoseconds(scenario.timing.radio_round_s)),
      physics_step_ns_(Nanoseconds(scenario.timing.physics_step_s)),
      end_ns_(Nanoseconds(scenario.timing.duration_s)),
      scheduler_(scenario.robots.size() * kTasksPerRobot + kWorldTasks),
      world_port_(scheduler_, "world"),
      world_(scenario.arena, Bodies(scenario)),
      channel_(scenario.channel, static_cast<uint16_t>(scenario.robots.size()), ChannelSeed(scenario.seed)),
      outbox_(scenario.robots.size()),
      sent_(scenario.robots.size(), 0),
      inflight_(scenario.robots.size()),
      collector_(metrics::CollectorConfig{static_cast<uint16_t>(scenario.robots.size()),
                                          Nanoseconds(scenario.timing.radio_round_s)}),
      fault_task_([this](int64_t now_ns) { StepFaults(now_ns); }),
      physics_task_([this](int64_t now_ns) { StepPhysics(now_ns); }),
      hardware_task_([this](int64_t now_ns) { StepHardware(now_ns); }),
      radio_task_([this](int64_t now_ns) { StepRadio(now_ns); }),
      recorder_task_([this](int64_t now_ns) { StepRecorder(now_ns); }),
      partition_active_(scenario.channel.partitions.size(), 0) {
  const auto swarm_size = static_cast<uint16_t>(scenario_.robots.size());
  wire::MemberSet initial;
  for (const scenario::RobotSpec& spec : scenario_.robots) {
    if (spec.present_at_start) initial.set(spec.id);
  }
  robots_.reserve(swarm_size);
  for (const scenario::RobotSpec& spec : scenario_.robots) {
    runtime::RobotConfig config;
    config.sync = sync::SyncConfig::ForSwarm(swarm_size, spec.id);
    config.sync.vote_rounds = static_cast<uint8_t>(scenario_.timing.vote_rounds);
    config.sync.silence_rounds = static_cast<uint16_t>(scenario_.timing.silence_rounds);
    config.sync.initial_members = initial;
    config.radio_round_ns = radio_round_ns_;
    config.maneuver_rounds =
        static_cast<uint16_t>(std::llround(scenario_.timing.app_round_s / scenario_.timing.radio_round_s));
    config.estimator.arena = EstimatorArena(scenario_);
    config.estimator.range_sigma_m = static_cast<float>(std::max(0.02, scenario_.sensors.uwb.sigma_m));
    config.estimator.flow_sigma_px = static_cast<float>(std::max(0.5, scenario_.sensors.flow.sigma_px));
    config.initial_pose.x_m = static_cast<float>(spec.x_m);
    config.initial_pose.y_m = static_cast<float>(spec.y_m);
    config.initial_pose.heading_rad = static_cast<float>(spec.heading_rad);
    config.initial_pose.position_sigma_m = 0.05f;
    config.initial_pose.heading_sigma_rad = 0.05f;
    config.motion = world::ControllerConfigFor(spec.kind, scenario_.kind_spec(spec.kind));
    config.arena_width_m = static_cast<float>(scenario_.arena.width_m);
    config.arena_height_m = static_cast<float>(scenario_.arena.height_m);
    config.queries_workspace = workspace_.handle();
    std::unique_ptr<app::App> app =
        options_.app_factory ? options_.app_factory(spec.id)
                             : apps::MakeBuiltinApp(apps::BareAppName(scenario_.app.name), scenario_.app.params);
    SYROF_CHECK(app != nullptr);
    robots_.push_back(std::make_unique<LabRobot>(scenario_, spec, scheduler_, world_, config, std::move(app),
                                                 LabRadio(outbox_, sent_, spec.id)));
  }

  SYROF_CHECK(world_port_.AddTask(fault_task_, {"lab.faults", os::Trigger::periodic(physics_step_ns_),
                                                kFaultPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(physics_task_, {"lab.physics",
                                                  os::Trigger::periodic(physics_step_ns_, physics_step_ns_),
                                                  kPhysicsPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(hardware_task_, {"lab.hardware",
                                                   os::Trigger::periodic(estimation::config::kImuPeriodNs),
                                                   estimation::config::kSensorTaskPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(radio_task_, {"lab.radio", os::Trigger::periodic(radio_round_ns_, radio_round_ns_),
                                                runtime::config::kRadioDeliveryPriority})
                  .ok());
  SYROF_CHECK(world_port_.AddTask(recorder_task_, {"lab.recorder",
                                                   os::Trigger::periodic(radio_round_ns_, radio_round_ns_),
                                                   kRecorderPriority})
                  .ok());
  for (auto& robot : robots_) {
    robot->robot().set_observer(this);  // before Attach: init may fault
    robot->Attach();
  }

  if (options_.replay != nullptr) {
    replay::Header header;
    header.seed = scenario_.seed;
    header.radio_round_ns = radio_round_ns_;
    header.arena_width_m = static_cast<float>(scenario_.arena.width_m);
    header.arena_height_m = static_cast<float>(scenario_.arena.height_m);
    header.scenario_name = scenario_.name;
    header.app_name = scenario_.app.name;
    for (const scenario::RobotSpec& spec : scenario_.robots) {
      header.robots.push_back(replay::RobotInfo{spec.id, static_cast<uint8_t>(spec.kind),
                                                static_cast<float>(scenario_.kind_spec(spec.kind).body_radius_m)});
    }
    replay_ = std::make_unique<replay::Writer>(*options_.replay, header);
  }
  frames_.resize(robots_.size());
  robot_rounds_.resize(robots_.size());

  SYROF_CHECK(world_port_.Start() == os::PortError::kOk);
  for (auto& robot : robots_) {
    if (scenario_.robots[robot->id()].present_at_start) StartRobot(*robot, 0);
  }
}

void Simulation::Impl::StartRobot(LabRobot& robot, int64_t now_ns) {
  if (robot.app_faulted) {
    // Its app failed in init: the body arrives and stays an obstacle.
    robot.presence = replay::Presence::kCrashed;
    world_.SetPresence(robot.id(), world::BodyPresence::kStopped);
    return;
  }
  SYROF_CHECK(robot.port().Start() == os::PortError::kOk);
  robot.presence = replay::Presence::kRunning;
  robot.scored_from_ns = now_ns + kEstimationWarmupNs;
  world_.SetPresence(robot.id(), world::BodyPresence::kActive);
}

void Simulation::Impl::StopRobot(LabRobot& robot, replay::Presence presence) {
  if (robot.port().running()) SYROF_CHECK(robot.port().Stop() == os::PortError::kOk);
  robot.presence = robot.app_faulted ? replay::Presence::kCrashed : presence;
  world_.SetPresence(robot.id(), world::BodyPresence::kStopped);
}

void Simulation::Impl::AddEvent(replay::EventKind kind, int64_t now_ns, uint16_t robot, uint16_t other,
                                uint16_t epoch, uint8_t mode) {
  replay::Event event{};
  event.kind = kind;
  event.robot = robot;
  event.other = other;
  event.epoch = epoch;
  event.mode = mode;
  event.time_ns = now_ns;
  round_events_.push_back(event);
}

// Faults take effect on the radio-round grid: a fault at t starts at the
// first round boundary at or after t (docs/scenarios.md), so a robot that
// starts or resumes runs its rounds in step with the others.
void Simulation::Impl::StepFaults(int64_t now_ns) {
  if (now_ns % radio_round_ns_ != 0) return;
  while (next_fault_ < scenario_.faults.size()) {
    const scenario::FaultSpec& fault = scenario_.faults[next_fault_];
    if (Nanoseconds(fault.at_s) > now_ns) break;
    LabRobot& robot = *robots_[fault.robot];
    switch (fault.kind) {
      case FaultKind::kCrash:
        StopRobot(robot, replay::Presence::kCrashed);
        AddEvent(replay::EventKind::kCrash, now_ns, fault.robot);
        break;
      case FaultKind::kPause:
        StopRobot(robot, replay::Presence::kPaused);
        AddEvent(replay::EventKind::kPause, now_ns, fault.robot);
        break;
      case FaultKind::kJoin:
        StartRobot(robot, now_ns);
        AddEvent(replay::EventKind::kJoin, now_ns, fault.robot);
        break;
    }
    ++next_fault_;
  }
  // Resumes, in robot order.
  for (const scenario::FaultSpec& fault : scenario_.faults) {
    if (fault.kind != FaultKind::kPause) continue;
    const int64_t resume_ns = ((Nanoseconds(fault.until_s) + radio_round_ns_ - 1) / radio_round_ns_) * radio_round_ns_;
    LabRobot& robot = *robots_[fault.robot];
    if (resume_ns == now_ns && robot.presence == replay::Presence::kPaused) {
      StartRobot(robot, now_ns);
      AddEvent(replay::EventKind::kResume, now_ns, fault.robot);
    }
  }
}

void Simulation::Impl::StepPhysics(int64_t now_ns) {
  world_.Step(now_ns, static_cast<double>(physics_step_ns_) * 1e-9);
  for (const world::Contact& contact : world_.new_contacts()) {
    collector_.OnCollision(contact.time_ns, contact.a, contact.b);
    AddEvent(replay::EventKind::kCollision, contact.time_ns, contact.a, contact.b);
  }
  for (const world::WallContact& contact : world_.new_wall_contacts()) {
    collector_.OnWallContact(contact.time_ns, contact.robot);
    AddEvent(replay::EventKind::kWallContact, contact.time_ns, contact.robot);
  }
}

void Simulation::Impl::StepHardware(int64_t now_ns) {
  for (auto& robot : robots_) {
    if (robot->port().running()) robot->StepHardware(now_ns);
  }
}

// The beacons broadcast at the end of the previous round travel now: each is
// encoded and decoded once (the wire format is exercised on every beacon),
// then offered to every other running robot through the channel.
void Simulation::Impl::StepRadio(int64_t now_ns) {
  const int64_t round = RoundOf(now_ns) - 1;
  const double sent_at_s = static_cast<double>(round * radio_round_ns_) * 1e-9;
  const auto swarm_size = static_cast<uint16_t>(robots_.size());
  for (uint16_t sender = 0; sender < swarm_size; ++sender) {
    if (sent_[sender] == 0) continue;
    sent_[sender] = 0;
    const auto encoded = wire::Encode(outbox_[sender], swarm_size, frame_bytes_);
    SYROF_CHECK(encoded.ok());
    const auto decoded = wire::Decode(std::span<const uint8_t>(frame_bytes_.data(), encoded.value()), swarm_size);
    if (!decoded.ok()) {
      ++beacons_malformed_;
      continue;
    }
    inflight_[sender] = decoded.value();
    for (uint16_t receiver = 0; receiver < swarm_size; ++receiver) {
      if (receiver == sender || !robots_[receiver]->port().running()) continue;
      if (channel_.Delivers(sender, receiver, round, sent_at_s)) robots_[receiver]->robot().Receive(inflight_[sender]);
    }
  }
}

void Simulation::Impl::StepRecorder(int64_t now_ns) {
  const int64_t round = RoundOf(now_ns);
  const double now = static_cast<double>(now_ns) * 1e-9;
  for (size_t i = 0; i < scenario_.channel.partitions.size(); ++i) {
    const scenario::PartitionSpec& partition = scenario_.channel.partitions[i];
    const uint8_t active = partition.start_s <= now && now < partition.end_s ? 1 : 0;
    if (active != partition_active_[i]) {
      AddEvent(active != 0 ? replay::EventKind::kPartitionStart : replay::EventKind::kPartitionEnd, now_ns,
               static_cast<uint16_t>(i));
      partition_active_[i] = active;
    }
  }
  for (size_t i = 0; i < robots_.size(); ++i) {
    LabRobot& lab_robot = *robots_[i];
    const runtime::Robot& robot = lab_robot.robot();
    const sync::SyncState& state = robot.sync_state();
    const world::BodyState& body = world_.state(lab_robot.id());
    const estimation::StateEstimate& estimate = robot.estimate();
    const bool running = lab_robot.presence == replay::Presence::kRunning;

    metrics::RobotRound& record = robot_rounds_[i];
    record.id = lab_robot.id();
    record.running = running;
    record.member = running && state.status == sync::Status::kMember;
    record.epoch = state.epoch;
    record.epoch_mode = state.epoch_mode;
    record.phase = state.phase;
    record.estimate_valid = running && robot.estimate_valid() && now_ns >= lab_robot.scored_from_ns;
    record.true_x_m = body.x_m;
    record.true_y_m = body.y_m;
    record.est_x_m = estimate.x_m;
    record.est_y_m = estimate.y_m;

    replay::RobotFrame& frame = frames_[i];
    frame.id = lab_robot.id();
    frame.presence = lab_robot.presence;
    frame.status = static_cast<uint8_t>(state.status);
    frame.phase = static_cast<uint8_t>(state.phase);
    frame.mode = static_cast<uint8_t>(state.epoch_mode);
    frame.epoch = state.epoch;
    frame.true_x_m = static_cast<float>(body.x_m);
    frame.true_y_m = static_cast<float>(body.y_m);
    frame.true_heading_rad = static_cast<float>(body.heading_rad);
    frame.est_x_m = estimate.x_m;
    frame.est_y_m = estimate.y_m;
    frame.est_heading_rad = estimate.heading_rad;
  }
  collector_.OnRoundEnd(round, robot_rounds_);
  if (replay_ != nullptr) replay_->WriteRound(static_cast<uint32_t>(round), now_ns, frames_, round_events_);
  round_events_.clear();
  if (options_.progress && options_.progress_period_s > 0) {
    const int64_t period_ns = Nanoseconds(options_.progress_period_s);
    if (now_ns % period_ns < radio_round_ns_) options_.progress(now);
  }
}

void Simulation::Impl::OnEpochStart(uint16_t robot, int64_t now_ns, const sync::LDMap& ldmap) {
  collector_.OnEpochStart(robot, RoundOf(now_ns), ldmap);
  AddEvent(replay::EventKind::kEpochStart, now_ns, robot, 0xFFFF, ldmap.epoch, static_cast<uint8_t>(ldmap.mode));
}

void Simulation::Impl::OnMembership(uint16_t robot, int64_t now_ns, const wire::MemberSet& removed,
                                    const wire::MemberSet& joined) {
  collector_.OnMembership(robot, RoundOf(now_ns), removed, joined);
  const uint16_t epoch = robots_[robot]->robot().sync_state().epoch;
  for (const uint16_t member : removed) AddEvent(replay::EventKind::kMemberRemoved, now_ns, robot, member, epoch);
  for (const uint16_t member : joined) AddEvent(replay::EventKind::kMemberJoined, now_ns, robot, member, epoch);
}

void Simulation::Impl::OnBecameJoiner(uint16_t robot, int64_t now_ns) {
  AddEvent(replay::EventKind::kBecameJoiner, now_ns, robot);
}

// ---- The app's failures ----------------------------------------------------
// A robot whose app faulted is stopped as a crashed robot is (its software
// stops, its body stays, the others' failure detectors remove it) and the
// run goes on. Called from inside the robot's own step (or from Attach, for
// init), which the robot ends without another app call.

void Simulation::Impl::OnAppFault(uint16_t robot, int64_t now_ns, app::Callback callback, uint16_t epoch,
                                  const app::CallStatus& status) {
  collector_.OnAppFault(metrics::AppFault{robot, app::ToString(callback), epoch, now_ns,
                                          app::ToString(status.verdict()), status.detail()});
  LabRobot& lab_robot = *robots_[robot];
  const auto mode = static_cast<uint8_t>(lab_robot.robot().sync_state().epoch_mode);
  AddEvent(replay::EventKind::kAppFault, now_ns, robot, replay::kNoRobot, epoch, mode);
  lab_robot.app_faulted = true;
  if (lab_robot.presence != replay::Presence::kAbsent) StopRobot(lab_robot, replay::Presence::kCrashed);
}

void Simulation::Impl::OnInvalidCommand(uint16_t robot, int64_t now_ns, uint16_t epoch,
                                        const app::CommandCheck& check) {
  std::array<char, 64> what{};
  collector_.OnInvalidCommand(robot, epoch, app::Describe(check, what.data(), what.size()));
  LabRobot& lab_robot = *robots_[robot];
  if (lab_robot.invalid_command_recorded) return;
  lab_robot.invalid_command_recorded = true;
  const auto mode = static_cast<uint8_t>(lab_robot.robot().sync_state().epoch_mode);
  AddEvent(replay::EventKind::kInvalidCommand, now_ns, robot, replay::kNoRobot, epoch, mode);
}

void Simulation::Impl::OnPayloadRefused(uint16_t robot, int64_t now_ns, uint16_t epoch, size_t length) {
  collector_.OnPayloadRefused(robot, epoch, std::to_string(length) + " bytes");
  LabRobot& lab_robot = *robots_[robot];
  if (lab_robot.payload_refusal_recorded) return;
  lab_robot.payload_refusal_recorded = true;
  const auto mode = static_cast<uint8_t>(lab_robot.robot().sync_state().epoch_mode);
  AddEvent(replay::EventKind::kPayloadRefused, now_ns, robot, replay::kNoRobot, epoch, mode);
}

void Simulation::Impl::RunUntil(double end_s) {
  const int64_t end_ns = std::min(end_ns_, Nanoseconds(end_s));
  if (end_ns > scheduler_.now_ns()) scheduler_.RunUntil(end_ns);
}

RunReport Simulation::Impl::Finish(double wall_seconds) {
  RunUntil(scenario_.timing.duration_s);
  if (replay_ != nullptr) replay_->Finish();

  std::vector<apps::GoalPose> poses;
  for (const auto& robot : robots_) {
    const world::BodyState& body = world_.state(robot->id());
    poses.push_back(apps::GoalPose{robot->id(), body.x_m, body.y_m, body.heading_rad,
                                   robot->presence == replay::Presence::kRunning});
  }
  const apps::GoalReport goal =
      apps::EvaluateGoal(apps::BareAppName(scenario_.app.name), scenario_.app.params,
                         apps::ArenaSize{scenario_.arena.width_m, scenario_.arena.height_m},
                         scenario_.omni.body_radius_m, poses);

  metrics::RunFacts facts;
  facts.seed = scenario_.seed;
  facts.robots = static_cast<uint16_t>(robots_.size());
  facts.sim_seconds = static_cast<double>(scheduler_.now_ns()) * 1e-9;
  facts.wall_seconds = wall_seconds;
  facts.radio_rounds = static_cast<int64_t>(scheduler_.now_ns() / radio_round_ns_);
  facts.min_separation_m = world_.min_separation_m();
  facts.scenario = scenario_.name;
  facts.app_name = robots_.empty() ? std::string() : robots_.front()->app_name();
  facts.app_source = options_.app_source.empty() ? scenario_.app.name : options_.app_source;
  facts.goal = metrics::GoalResult{scenario_.app.name, goal.reached, goal.error_m, goal.detail};
  RunReport report;
  report.metrics = collector_.Finish(facts);
  report.metrics_json = metrics::ToJson(report.metrics);
  return report;
}

// ---- Simulation ------------------------------------------------------------

Simulation::Simulation(const Scenario& scenario, const SimulationOptions& options)
    : impl_(std::make_unique<Impl>(scenario, options)) {}
Simulation::~Simulation() = default;
void Simulation::RunUntil(double end_s) { impl_->RunUntil(end_s); }
RunReport Simulation::Finish(double wall_seconds) { return impl_->Finish(wall_seconds); }
double Simulation::now_s() const { return impl_->now_s(); }
size_t Simulation::robot_count() const { return impl_->robots_.size(); }
const runtime::Robot& Simulation::robot(uint16_t id) const { return impl_->robots_.at(id)->robot(); }
const scenario::Scenario& Simulation::scenario() const { return impl_->scenario_; }

RunReport Run(const Scenario& scenario, const SimulationOptions& options, double wall_seconds) {
  Simulation simulation(scenario, options);
  return simulation.Finish(wall_seconds);
}

}  // namespace syrof::lab::sim
