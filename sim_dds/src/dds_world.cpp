#include "syrof/sim_dds/dds_world.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <memory>
#include <thread>

#include "syrof/app/call_status.h"
#include "syrof/base/split_mix64.h"
#include "syrof/motion/safety_filter.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/apps/builtin_goals.h"
#include "syrof/lab/goals/goals.h"
#include "syrof/lab/metrics/agreement.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/round_recorder.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/world_player.h"
#include "syrof/lab/world/world.h"
#include "syrof/os/posix_port.h"
#include "syrof/registry/tasks.h"
#include "syrof/process/fd.h"
#include "syrof/process/spawn.h"
#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/report_codec.h"
#include "syrof/sim_dds/robot_process.h"
#include "syrof/sim_dds/topics.h"
#include "take_samples.h"

namespace syrof::sim_dds {
namespace {

namespace scenario = lab::scenario;
namespace replay = lab::replay;
using lab::sim::CheckStressOptions;
using lab::sim::CpuQuotaGroup;
using lab::sim::kStallWorld;
using lab::sim::PlanStalls;
using lab::sim::Stall;

int64_t Nanoseconds(double seconds) { return std::llround(seconds * 1e9); }
int64_t MonotonicNow() { return os::PosixPort::MonotonicNowNs(); }

// Sends one robot's simulated readings as its DDS sensor samples.
class DdsSensorSink final : public lab::sensors::ReadingSink {
 public:
  DdsSensorSink(uint16_t robot, uint64_t run_id, dds_entity_t imu, dds_entity_t flow, dds_entity_t uwb)
      : robot_(robot), run_id_(run_id), imu_(imu), flow_(flow), uwb_(uwb) {}
  void OnImu(const estimation::ImuReading& r) override {
    syrof_msg_dds__Imu_ s{};
    s.robot = robot_;
    s.run_id = run_id_;
    s.world_time_ns = r.timestamp_ns;
    std::memcpy(s.accel_g, r.accel_g, sizeof s.accel_g);
    std::memcpy(s.gyro_dps, r.gyro_dps, sizeof s.gyro_dps);
    (void)dds_write(imu_, &s);
  }
  void OnFlow(const estimation::FlowReading& r) override {
    syrof_msg_dds__Flow_ s{};
    s.robot = robot_;
    s.run_id = run_id_;
    s.world_time_ns = r.timestamp_ns;
    s.interval_ns = r.interval_ns;
    s.delta_x_px = r.delta_x_px;
    s.delta_y_px = r.delta_y_px;
    (void)dds_write(flow_, &s);
  }
  void OnUwb(const estimation::UwbReading& r) override {
    syrof_msg_dds__Uwb_ s{};
    s.robot = robot_;
    s.run_id = run_id_;
    s.world_time_ns = r.timestamp_ns;
    std::memcpy(s.range_m, r.range_m, sizeof s.range_m);
    s.valid_mask = r.valid_mask;
    s.sweep = r.sweep;
    (void)dds_write(uwb_, &s);
  }

 private:
  uint16_t robot_;
  uint64_t run_id_;
  dds_entity_t imu_, flow_, uwb_;
};

// A report placed on the run's grid.
struct Received {
  uint16_t robot = 0;
  int64_t time_ns = 0;  // run time (since the grid's origin)
  ReportBody body;
};

struct RobotSlot {
  process::Child process;    // not started: a joiner not yet switched on
  RoundReport last;          // the newest round observation
  bool has_last = false;
  double cpu_seconds = 0;
  std::optional<int> exit;   // the exit code, or minus the signal that ended it
  dds_entity_t imu = 0, flow = 0, uwb = 0, drive = 0;
  std::unique_ptr<lab::sensors::SensorBank> bank;
  std::unique_ptr<DdsSensorSink> sink;
};

// What the world saw at a round boundary (the recorder runs later, once
// the round's reports are in).
struct BoundaryTruth {
  int64_t time_ns = 0;  // run time of the physics step that took it
  std::vector<lab::world::BodyState> bodies;
  std::vector<replay::Presence> presence;
  std::vector<replay::Event> events;  // the simulator's own (faults, contacts) in the round
};

// What the DDS world does to a robot process for the world player: a join
// spawns it (robots present at start are spawned before discovery), a crash
// is SIGKILL, a pause SIGSTOP and its end SIGCONT.
class ProcessRuntime final : public lab::sim::RobotRuntime {
 public:
  ProcessRuntime(std::vector<RobotSlot>& robots, std::function<bool(uint16_t)> spawn)
      : robots_(robots), spawn_(std::move(spawn)) {}

  bool StartRobot(uint16_t id, int64_t /*world_ns*/, bool resume) override {
    RobotSlot& r = robots_[id];
    if (resume) {
      r.process.Signal(SIGCONT);
      return true;
    }
    return r.process.started() || spawn_(id);
  }

  void StopRobot(uint16_t id, int64_t /*world_ns*/, lab::sim::StopReason reason) override {
    process::Child& robot = robots_[id].process;
    if (reason == lab::sim::StopReason::kCrash) robot.Kill();
    if (reason == lab::sim::StopReason::kPause) robot.Signal(SIGSTOP);
  }

  // The robot's newest report says its epoch and mode.
  lab::sim::EventStamp Stamp(uint16_t id) const override {
    const RobotSlot& r = robots_[id];
    if (!r.has_last) return {};
    return lab::sim::EventStamp{r.last.epoch, static_cast<wire::Mode>(r.last.epoch_mode)};
  }

 private:
  std::vector<RobotSlot>& robots_;
  std::function<bool(uint16_t)> spawn_;
};

// Reports of round r are recorded once the grid is this far past r.
constexpr int64_t kRecordLagRounds = 10;

// One round's reports, read: what they fed the collector and the robots'
// slots is done; the rest waits for the round's recorder.
struct RoundReports {
  std::vector<replay::Event> events;
  std::vector<replay::RobotMap> maps;
  std::vector<int64_t> activations;
  std::vector<int64_t> phase_boundaries;
  wire::MemberSet senders;
  std::vector<std::pair<uint16_t, wire::MemberSet>> heard;  // each reporting robot's in-round deliveries

  void AddEvent(replay::EventKind kind, int64_t time_ns, uint16_t robot, uint16_t epoch, uint8_t mode,
                uint16_t other = replay::kNoRobot) {
    replay::Event e{};
    e.kind = kind;
    e.robot = robot;
    e.other = other;
    e.epoch = epoch;
    e.mode = mode;
    e.time_ns = time_ns;
    events.push_back(e);
  }
};

// The run's state and its phases, in the order RunSwarm calls them:
// CreateEntities, OpenReplay, SpawnPresentRobots, AwaitDiscovery, Start,
// Run (one Step per physics step, the recorder ten rounds behind),
// DrainReports, StopRobots, WriteMetrics. A phase that fails says why in
// the result and returns false. Every exit path ends every robot (the
// destructor).
class DdsWorld {
 public:
  DdsWorld(const SwarmOptions& options, std::ostream& log, const scenario::Scenario& scenario,
           std::string robot_binary, uint64_t run_id, std::unique_ptr<Participant> participant,
           SwarmResult& result);
  ~DdsWorld() { EndAll(); }
  DdsWorld(const DdsWorld&) = delete;
  DdsWorld& operator=(const DdsWorld&) = delete;

  bool CreateEntities();
  void OpenReplay();
  bool SpawnPresentRobots();
  bool AwaitDiscovery();
  bool Start();
  void Run();
  void DrainReports();
  void StopRobots();
  void WriteMetrics();

 private:
  bool Fail(int code, std::string why);

  // ---- Processes
  bool Spawn(uint16_t id);  // false: spawn_error_ says why
  void Reap(RobotSlot& r, bool block);
  void EndAll();
  void TakeStatus();

  // ---- Stress (stress.h)
  bool StartStress();
  void ApplyStalls();
  void EndStress();

  // ---- The run
  void Step();
  void TakeDrives();
  void KeepBoundaryTruths();
  int64_t RoundAt(int64_t monotonic_ns) const;
  void FollowRobots();
  void TakeReports();

  // ---- The recorder
  void Record(int64_t round);
  RoundReports ReadReports(int64_t round);
  void ReadReport(int64_t round, const Received& r, RoundReports& read);
  void CountDeliveries(int64_t round, const RoundReports& read);
  void BuildFrames(const BoundaryTruth* truth, int64_t round_time_ns);

  // ---- Metrics
  lab::metrics::DdsMetrics DdsFacts() const;

  const SwarmOptions& options_;
  std::ostream& log_;
  SwarmResult& result_;
  const scenario::Scenario& scenario_;
  const uint16_t swarm_size_;
  const int64_t radio_round_ns_;
  const int64_t physics_step_ns_;
  const int64_t duration_ns_;
  const std::string robot_binary_;
  const uint64_t run_id_;
  const std::unique_ptr<Participant> participant_;

  dds_entity_t control_ = 0, report_reader_ = 0, status_reader_ = 0;
  std::vector<RobotSlot> robots_;
  lab::world::World world_;
  // The metrics, the goal checks and the replay, as every runtime records them.
  lab::sim::RoundRecorder recorder_;
  std::ofstream replay_file_;

  // ---- Processes
  RobotProcessOptions robot_options_;
  // Above 0: robot processes start at SCHED_FIFO with this priority (--realtime where allowed).
  int robot_fifo_priority_ = 0;
  std::string spawn_error_;  // why the last Spawn failed

  // ---- Discovery: every present robot attached
  std::vector<uint8_t> attached_;
  std::vector<syrof_msg_dds__Status_> last_status_;

  // ---- The run
  int64_t start_monotonic_ns_ = 0;
  syrof_msg_dds__Control_ control_sample_{};
  // The robots' lifecycle, the faults and the join wait: the lab's rules.
  ProcessRuntime runtime_;
  lab::sim::WorldPlayer player_;

  std::map<int64_t, std::vector<Received>> reports_by_round_;
  std::map<int64_t, BoundaryTruth> truths_;
  std::vector<int64_t> skews_ns_;
  std::vector<lab::metrics::RobotRound> robot_rounds_;
  std::vector<replay::RobotFrame> frames_;
  std::map<int64_t, wire::MemberSet> round_senders_;  // robots that reported (broadcast) in a round
  int64_t reports_rejected_ = 0, reports_late_ = 0, reports_foreign_ = 0, drives_foreign_ = 0;
  int64_t next_recorded_ = 1;
  double expected_deliveries_ = 0;
  double in_round_deliveries_ = 0;

  // The robots' rounds on the world's clock. On one grid (no alignment)
  // round r starts at start + r * alpha. Aligning robots move their
  // boundaries together and number their own rounds, so the world follows
  // them: the origin is the median over running robots of (when a robot's
  // round report went out) - round * alpha, from each robot's newest report.
  int64_t round_origin_ = 0;
  std::vector<std::optional<int64_t>> robot_origins_;

  // ---- Stress: the plan, the robots stopped now (until when, run time;
  // -1: not stopped by the stress), the process that stops the world, and
  // the robots' CPU quota.
  std::vector<Stall> stalls_;
  size_t next_stall_ = 0;
  std::vector<int64_t> stalled_until_;
  process::Child world_staller_;
  std::atomic<int>* staller_stop_ = nullptr;  // shared with the staller (an anonymous shared page)
  std::unique_ptr<CpuQuotaGroup> quota_;

  int64_t step_ns_ = 0;
  int64_t next_truth_ = 1;  // the next round whose boundary truth is taken
  double wall_seconds_ = 0;
  int64_t last_round_ = 0;
};

DdsWorld::DdsWorld(const SwarmOptions& options, std::ostream& log, const scenario::Scenario& scenario,
                   std::string robot_binary, uint64_t run_id, std::unique_ptr<Participant> participant,
                   SwarmResult& result)
    : options_(options),
      log_(log),
      result_(result),
      scenario_(scenario),
      swarm_size_(static_cast<uint16_t>(scenario.robots.size())),
      radio_round_ns_(Nanoseconds(scenario.timing.radio_round_s)),
      physics_step_ns_(Nanoseconds(scenario.timing.physics_step_s)),
      duration_ns_(Nanoseconds(scenario.timing.duration_s)),
      robot_binary_(std::move(robot_binary)),
      run_id_(run_id),
      participant_(std::move(participant)),
      robots_(swarm_size_),
      world_(scenario.arena, lab::sim::Bodies(scenario), scenario.seed),
      recorder_(scenario, lab::sim::CollectorConfigFor(scenario)),
      attached_(swarm_size_, 0),
      last_status_(swarm_size_),
      runtime_(robots_,
               [this](uint16_t id) {
                 if (Spawn(id)) return true;
                 log_ << "syrof swarm: " << spawn_error_ << "\n";  // the player counts it crashed
                 return false;
               }),
      player_(scenario, world_, recorder_.collector()),
      robot_rounds_(swarm_size_),
      frames_(swarm_size_),
      robot_origins_(swarm_size_),
      stalled_until_(swarm_size_, -1) {
  recorder_.MeasureAgreement();  // the robots report every app return (kAppState)
  robot_options_.scenario_path = options.scenario_path;
  robot_options_.overrides = options.overrides;
  robot_options_.run_id = run_id;
  robot_options_.domain_id = participant_->domain_id();
  robot_options_.interface = options.interface;
  robot_options_.log_directory = (std::filesystem::path(options.out_dir) / "robots").string();
  robot_options_.parent_pid = getpid();
  robot_options_.realtime = options.realtime;
  // The robot's main thread is its hardware: it passes the world's readings
  // to the sensor drivers and the drive back (WorldLink), so it starts at
  // the drivers' priority, and a joiner's start-up is not starved either.
  if (options.realtime && CanUseFifoScheduling()) {
    robot_fifo_priority_ = sched_get_priority_min(SCHED_FIFO) + registry::kSensorTaskPriority;
  }
  robot_options_.align_rounds = options.align_rounds;
  robot_options_.realtime_start = options.realtime_start;
  robot_options_.stress = options.stress;  // the late samples are the robots' to play (RadioOptionsFor, WorldLink)
}

bool DdsWorld::Fail(int code, std::string why) {
  result_.exit_code = code;
  result_.error = lab::Error{.where = "", .message = std::move(why)};
  return false;
}

bool Assign(const EntityOrError& e, dds_entity_t& out) {
  if (!e.ok()) return false;
  out = e.entity;
  return true;
}

bool DdsWorld::CreateEntities() {
  const Participant& participant = *participant_;
  bool entities_ok = Assign(CreateWriter(participant, TopicKind::kControl), control_) &&
                     Assign(CreateReader(participant, TopicKind::kReport), report_reader_) &&
                     Assign(CreateReader(participant, TopicKind::kStatus), status_reader_);
  for (uint16_t id = 0; id < swarm_size_ && entities_ok; ++id) {
    RobotSlot& r = robots_[id];
    entities_ok = Assign(CreateWriter(participant, TopicKind::kImu, id), r.imu) &&
                  Assign(CreateWriter(participant, TopicKind::kFlow, id), r.flow) &&
                  Assign(CreateWriter(participant, TopicKind::kUwb, id), r.uwb) &&
                  Assign(CreateReader(participant, TopicKind::kDrive, id), r.drive);
    r.bank = std::make_unique<lab::sensors::SensorBank>(lab::sim::SensorConfigFor(scenario_, scenario_.robots[id]),
                                                        lab::sim::SensorSeed(scenario_.seed, id));
    r.sink = std::make_unique<DdsSensorSink>(id, run_id_, r.imu, r.flow, r.uwb);
  }
  if (!entities_ok) {
    return Fail(1, "the world's DDS readers and writers could not be created (domain " +
                       std::to_string(participant.domain_id()) + ")");
  }
  return true;
}

void DdsWorld::OpenReplay() {
  for (lab::replay::RoundSink* sink : options_.sinks) recorder_.AddSink(sink);
  if (!options_.replay) return;
  replay_file_.open(std::filesystem::path(options_.out_dir) / "replay", std::ios::binary);
  recorder_.OpenReplay(replay_file_);
}

// ---- Processes --------------------------------------------------------------

// Robot `id`'s process: the world's environment, standard output and error;
// a process group of its own; SIGKILL when the world ends, even killed
// outright; its network namespace when SwarmOptions::robot_networks names one.
bool DdsWorld::Spawn(uint16_t id) {
  robot_options_.robot = id;
  robot_options_.clock_offset_us =
      id < options_.robot_clock_offsets_us.size() ? options_.robot_clock_offsets_us[id] : 0;
  const SwarmOptions::RobotNetwork* network =
      id < options_.robot_networks.size() ? &options_.robot_networks[id] : nullptr;
  robot_options_.interface =
      network != nullptr && !network->interface.empty() ? network->interface : options_.interface;
  process::Fd netns;
  if (network != nullptr && !network->netns_path.empty()) {
    netns.Reset(open(network->netns_path.c_str(), O_RDONLY | O_CLOEXEC));
    if (!netns.valid()) {
      spawn_error_ = "robot " + std::to_string(id) + ": cannot open its network namespace " + network->netns_path +
                     ": " + std::strerror(errno);
      return false;
    }
  }
  process::Command command;
  command.argv = RobotArguments(robot_options_);
  command.argv.insert(command.argv.begin(), robot_binary_);
  command.inherit_environment = true;
  command.descriptors = {{1, 1}, {2, 2}};
  command.own_process_group = true;
  command.die_with_parent = true;
  command.network_namespace = netns.get();
  command.fifo_priority = robot_fifo_priority_;
  RobotSlot& r = robots_[id];
  r.process = process::Spawn(command);
  if (!r.process.started()) {
    spawn_error_ = "robot " + std::to_string(id) + ": cannot start " + robot_binary_ + ": " +
                   std::strerror(r.process.start_error());
    return false;
  }
  result_.robot_pids.push_back(r.process.pid());
  if (quota_ && !quota_->Add(r.process.pid())) {
    log_ << "syrof swarm: robot " << id << " could not join " << quota_->path() << "\n";
  }
  return true;
}

void DdsWorld::Reap(RobotSlot& r, bool block) {
  if (!r.process.started() || r.process.reaped()) return;
  const std::optional<process::ExitStatus> status =
      block ? r.process.Reap() : r.process.Wait(std::chrono::milliseconds(0));
  if (!status) return;
  if (status->exited()) r.exit = status->code;
  if (status->signaled()) r.exit = -status->signal;
  r.cpu_seconds = status->cpu_seconds;
}

// Every exit path ends every robot: SIGKILL to each running robot's
// process group, then reap.
void DdsWorld::EndAll() {
  EndStress();
  for (RobotSlot& r : robots_) {
    if (!r.process.reaped()) r.process.KillGroup();
  }
  for (RobotSlot& r : robots_) Reap(r, true);
}

bool DdsWorld::SpawnPresentRobots() {
  if (options_.stress.on() && options_.stress.cpu_quota_permille > 0) {
    quota_ = std::make_unique<CpuQuotaGroup>(options_.stress.cpu_quota_permille);
    if (!quota_->ok()) return Fail(1, "stress: " + quota_->error());
  }
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    if (scenario_.robots[id].present_at_start && !Spawn(id)) return Fail(1, spawn_error_);
  }
  return true;
}

void DdsWorld::TakeStatus() {
  TakeSamples<syrof_msg_dds__Status_>(status_reader_, [&](const syrof_msg_dds__Status_& s, const dds_sample_info_t&) {
    if (s.run_id != run_id_ || s.robot >= swarm_size_) return;
    last_status_[s.robot] = s;
    if (s.state >= 1) attached_[s.robot] = 1;
  });
}

// ---- Discovery: every present robot attached ----------------------------------

bool DdsWorld::AwaitDiscovery() {
  const int64_t discovery_deadline = MonotonicNow() + Nanoseconds(options_.discovery_timeout_s);
  for (;;) {
    TakeStatus();
    bool all = true;
    for (uint16_t id = 0; id < swarm_size_; ++id) all = all && (!scenario_.robots[id].present_at_start || attached_[id] != 0);
    if (all) return true;
    for (RobotSlot& r : robots_) {
      Reap(r, false);
      if (r.process.reaped()) return Fail(1, "a robot process exited before it attached (see its messages above)");
    }
    if (MonotonicNow() > discovery_deadline) return Fail(1, "robots did not attach within the discovery timeout");
    if (options_.stop != nullptr && options_.stop->load()) {
      result_.stopped_early = true;
      return Fail(0, "");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

// ---- The run ------------------------------------------------------------------

bool DdsWorld::Start() {
  start_monotonic_ns_ = MonotonicNow() + 300'000'000;  // every robot hears it before the first round
  round_origin_ = start_monotonic_ns_;
  control_sample_.run_id = run_id_;
  control_sample_.state = 1;
  control_sample_.start_monotonic_ns = start_monotonic_ns_;
  {
    timespec realtime{};
    clock_gettime(CLOCK_REALTIME, &realtime);
    control_sample_.start_realtime_ns = static_cast<int64_t>(realtime.tv_sec) * 1'000'000'000 + realtime.tv_nsec +
                                        (start_monotonic_ns_ - MonotonicNow());
  }
  control_sample_.radio_round_ns = radio_round_ns_;
  if (dds_write(control_, &control_sample_) < 0) return Fail(1, "the control sample could not be written");
  player_.StartPresentRobots(runtime_);
  return StartStress();
}

// ---- Stress (stress.h) ----------------------------------------------------------

// The plan from the seed; the world's own stalls are played by a child
// process, since a stopped process cannot wake itself.
bool DdsWorld::StartStress() {
  if (!options_.stress.on()) return true;
  if (const std::string why = CheckStressOptions(options_.stress); !why.empty()) return Fail(2, "stress: " + why);
  stalls_ = PlanStalls(options_.stress, duration_ns_, swarm_size_);
  result_.stress_seed = options_.stress.seed;
  std::vector<std::pair<int64_t, int64_t>> world_stalls;  // monotonic start, length
  for (const Stall& stall : stalls_) {
    if (stall.target == kStallWorld) world_stalls.emplace_back(start_monotonic_ns_ + stall.at_ns, stall.duration_ns);
  }
  log_ << "syrof swarm: stress seed " << options_.stress.seed << ": " << stalls_.size() << " SIGSTOP bursts of "
       << options_.stress.min_stall_ms << "-" << options_.stress.max_stall_ms << " ms (" << world_stalls.size()
       << " of the world)";
  if (options_.stress.delayed_fraction > 0) {
    log_ << ", " << options_.stress.delayed_fraction * 100 << " % of beacons and readings "
         << options_.stress.min_delay_ms << "-" << options_.stress.max_delay_ms << " ms late";
  }
  if (quota_) log_ << ", robots' CPU quota " << options_.stress.cpu_quota_permille << " per mille of a core";
  log_ << "\n";
  result_.stalls += static_cast<int64_t>(world_stalls.size());
  if (world_stalls.empty()) return true;
  void* page = mmap(nullptr, sizeof(std::atomic<int>), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (page == MAP_FAILED) return Fail(1, "stress: mmap failed");
  staller_stop_ = new (page) std::atomic<int>(0);
  const pid_t world = getpid();
  world_staller_ = process::ForkHelper([this, world, &world_stalls] {
    // Sleep, stop the world, sleep, resume it. It checks the stop flag at
    // least every 10 ms, and never leaves the world stopped: each SIGSTOP
    // is followed by its SIGCONT.
    const auto sleep_until = [this](int64_t until_ns) {
      for (;;) {
        if (staller_stop_->load() != 0) return false;
        const int64_t now = MonotonicNow();
        if (now >= until_ns) return true;
        const int64_t step = std::min<int64_t>(until_ns - now, 10'000'000);
        timespec t{static_cast<time_t>(step / 1'000'000'000), static_cast<long>(step % 1'000'000'000)};
        (void)nanosleep(&t, nullptr);
      }
    };
    for (const auto& [at, length] : world_stalls) {
      if (!sleep_until(at)) break;
      (void)kill(world, SIGSTOP);
      timespec t{static_cast<time_t>(length / 1'000'000'000), static_cast<long>(length % 1'000'000'000)};
      while (nanosleep(&t, &t) != 0 && errno == EINTR) {
      }
      (void)kill(world, SIGCONT);
    }
    return 0;
  });
  if (!world_staller_.started()) {
    return Fail(1, std::string("stress: cannot start the process that stalls the world: ") +
                       std::strerror(world_staller_.start_error()));
  }
  return true;
}

// Robot stalls due by now on the run's grid: SIGSTOP, and SIGCONT at their
// end unless the scenario has paused, crashed or ended the robot meanwhile.
void DdsWorld::ApplyStalls() {
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    if (stalled_until_[id] < 0 || stalled_until_[id] > step_ns_) continue;
    stalled_until_[id] = -1;
    if (player_.running(id)) robots_[id].process.Signal(SIGCONT);
  }
  while (next_stall_ < stalls_.size() && stalls_[next_stall_].at_ns <= step_ns_) {
    const Stall& stall = stalls_[next_stall_++];
    if (stall.target == kStallWorld || stall.target >= swarm_size_) continue;
    RobotSlot& r = robots_[stall.target];
    if (!player_.running(stall.target) || !r.process.started()) continue;
    if (stalled_until_[stall.target] < 0) {
      r.process.Signal(SIGSTOP);
      ++result_.stalls;
    }
    stalled_until_[stall.target] = std::max(stalled_until_[stall.target], stall.at_ns + stall.duration_ns);
  }
}

// No stall outlives the run: robots resumed, the world's staller told to
// stop and reaped (it finishes the stall it is in, if any).
void DdsWorld::EndStress() {
  next_stall_ = stalls_.size();
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    if (stalled_until_[id] < 0) continue;
    stalled_until_[id] = -1;
    if (player_.lifecycle(id) != lab::sim::Lifecycle::kPaused) robots_[id].process.Signal(SIGCONT);
  }
  if (world_staller_.started() && !world_staller_.reaped()) {
    staller_stop_->store(1);
    (void)world_staller_.Reap();
  }
  if (staller_stop_ != nullptr) {
    (void)munmap(staller_stop_, sizeof(std::atomic<int>));
    staller_stop_ = nullptr;
  }
}

void DdsWorld::Run() {
  int64_t next_progress_ns = 1'000'000'000;
  while (step_ns_ < duration_ns_) {
    if (options_.stop != nullptr && options_.stop->load()) {
      result_.stopped_early = true;
      break;
    }
    step_ns_ += physics_step_ns_;
    // Sleep until this step's instant on the grid.
    const int64_t due = start_monotonic_ns_ + step_ns_;
    const int64_t wait = due - MonotonicNow();
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
    Step();
    ApplyStalls();
    TakeReports();
    if (options_.align_rounds) FollowRobots();
    TakeStatus();
    for (uint16_t id = 0; id < swarm_size_; ++id) {
      if (player_.lifecycle(id) == lab::sim::Lifecycle::kCrashed) Reap(robots_[id], false);
    }
    while (next_recorded_ + kRecordLagRounds <= RoundAt(start_monotonic_ns_ + step_ns_)) Record(next_recorded_++);
    if (options_.progress && step_ns_ >= next_progress_ns) {
      options_.progress(static_cast<double>(step_ns_) * 1e-9);
      next_progress_ns += 1'000'000'000;
    }
  }
  wall_seconds_ = static_cast<double>(MonotonicNow() - start_monotonic_ns_) * 1e-9;
}

// One physics step at step_ns_.
void DdsWorld::Step() {
  // Faults on the radio-round grid, as real ones, with the lab's rules, one
  // physics step ahead of their instant. A fault due at a round boundary
  // acts in the lab before the robots' round tasks at that instant (its
  // priority is higher); here the world and the robots are processes woken
  // at the same instant, so a robot killed or stopped right at the boundary
  // raced its own round task and sometimes sent that round's beacon, and
  // the swarm removed it a round later than in the lab. Half a round at
  // most: more would move a fault to the round before.
  const int64_t lead_ns = 2 * physics_step_ns_ <= radio_round_ns_ ? physics_step_ns_ : 0;
  player_.PlayFaults(step_ns_ + lead_ns, runtime_);
  TakeDrives();
  world_.Step(step_ns_, static_cast<double>(physics_step_ns_) * 1e-9);
  player_.TakeContacts(runtime_);
  // Sensors of running robots.
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    RobotSlot& r = robots_[id];
    if (player_.running(id)) r.bank->Sample(step_ns_, world_.true_state(id), *r.sink);
  }
  KeepBoundaryTruths();
}

// Drive commands to the bodies of running robots.
void DdsWorld::TakeDrives() {
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    RobotSlot& r = robots_[id];
    TakeSamples<syrof_msg_dds__Drive_>(r.drive, [&](const syrof_msg_dds__Drive_& s, const dds_sample_info_t&) {
      if (s.run_id != run_id_) {
        ++drives_foreign_;  // the same robot of another run on this domain
        return;
      }
      if (s.robot != id || !player_.running(id) || s.kind > 1) return;
      motion::DriveCommand command{};
      command.timestamp_ns = s.robot_time_ns;
      command.kind = static_cast<motion::DriveKind>(s.kind);
      command.vx_mps = s.vx_mps;
      command.vy_mps = s.vy_mps;
      command.yaw_rate_radps = s.yaw_rate_radps;
      command.left_mps = s.left_mps;
      command.right_mps = s.right_mps;
      world_.SetDrive(id, command);
    });
  }
}

// A round boundary of the robots: keep the truth for the recorder.
void DdsWorld::KeepBoundaryTruths() {
  while (next_truth_ <= RoundAt(start_monotonic_ns_ + step_ns_)) {
    BoundaryTruth truth;
    truth.time_ns = step_ns_;
    for (uint16_t id = 0; id < swarm_size_; ++id) {
      truth.bodies.push_back(world_.state(id));
      truth.presence.push_back(player_.presence(id));
    }
    truth.events = player_.TakeEvents();
    truths_[next_truth_++] = std::move(truth);
  }
}

int64_t DdsWorld::RoundAt(int64_t monotonic_ns) const {
  const int64_t since = monotonic_ns - round_origin_;
  return since >= 0 ? since / radio_round_ns_ : -((-since + radio_round_ns_ - 1) / radio_round_ns_);
}

void DdsWorld::FollowRobots() {
  std::vector<int64_t> origins;
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    if (player_.running(id) && robot_origins_[id]) origins.push_back(*robot_origins_[id]);
  }
  if (origins.empty()) return;
  std::nth_element(origins.begin(), origins.begin() + static_cast<std::ptrdiff_t>(origins.size() / 2), origins.end());
  round_origin_ = origins[origins.size() / 2];
}

void DdsWorld::TakeReports() {
  TakeSamples<syrof_msg_dds__Report_>(report_reader_, [&](const syrof_msg_dds__Report_& s, const dds_sample_info_t&) {
    if (s.run_id != run_id_) {
      ++reports_foreign_;
      return;
    }
    if (s.robot >= swarm_size_) {
      ++reports_rejected_;
      return;
    }
    DecodedReport decoded = DecodeReport(s.kind, std::span<const uint8_t>(s.body._buffer, s.body._length), swarm_size_);
    if (!decoded.body) {
      ++reports_rejected_;
      log_ << "syrof swarm: robot " << s.robot << "'s report " << s.sequence_number
           << " refused: " << decoded.error->ToString() << "\n";
      return;
    }
    Received received{s.robot, s.robot_time_ns - start_monotonic_ns_, std::move(*decoded.body)};
    const int64_t round = received.body.kind == ReportKind::kRound
                              ? static_cast<int64_t>(received.body.round.round)
                              : RoundAt(s.robot_time_ns + radio_round_ns_ / 2);
    if (options_.align_rounds && received.body.kind == ReportKind::kRound) {
      robot_origins_[s.robot] = received.body.round.activation_ns - round * radio_round_ns_;
    }
    if (round < next_recorded_) {
      ++reports_late_;
      return;
    }
    reports_by_round_[round].push_back(std::move(received));
  });
}

// ---- The recorder ---------------------------------------------------------------

// The recorder of round r: the lab's StepRecorder from reports.
void DdsWorld::Record(int64_t round) {
  const auto truth_it = truths_.find(round);
  const BoundaryTruth* truth = truth_it != truths_.end() ? &truth_it->second : nullptr;
  const int64_t round_time_ns =
      truth != nullptr ? truth->time_ns : round_origin_ - start_monotonic_ns_ + round * radio_round_ns_;
  RoundReports read = ReadReports(round);
  CountDeliveries(round, read);
  if (read.activations.size() >= 2) {
    const auto [low, high] = std::minmax_element(read.activations.begin(), read.activations.end());
    skews_ns_.push_back(*high - *low);
  }
  BuildFrames(truth, round_time_ns);
  std::vector<replay::Event>& events = read.events;
  if (truth != nullptr) events.insert(events.begin(), truth->events.begin(), truth->events.end());
  lab::sim::OrderByTime(events);
  // The running robots' true positions, for the goal checks: at the recorded boundary, or now.
  auto running_poses = [&] {
    return truth != nullptr ? player_.RunningPoses(truth->presence, truth->bodies) : player_.RunningPoses();
  };
  recorder_.RecordRound(lab::sim::RecordedRound{round, round_time_ns, robot_rounds_, read.phase_boundaries, frames_,
                                                events, read.maps, running_poses});
  if (truth != nullptr) truths_.erase(truth_it);
}

// Round r's reports, in robot order, into the collector, the robots' slots
// and the round's events and maps.
RoundReports DdsWorld::ReadReports(int64_t round) {
  std::vector<Received> reports;
  if (auto it = reports_by_round_.find(round); it != reports_by_round_.end()) {
    reports = std::move(it->second);
    reports_by_round_.erase(it);
  }
  std::stable_sort(reports.begin(), reports.end(), [](const Received& a, const Received& b) { return a.robot < b.robot; });
  RoundReports read;
  for (const Received& r : reports) ReadReport(round, r, read);
  return read;
}

void DdsWorld::ReadReport(int64_t round, const Received& r, RoundReports& read) {
  RobotSlot& slot = robots_[r.robot];
  const uint16_t epoch = slot.has_last ? slot.last.epoch : 0;
  const uint8_t mode = slot.has_last ? slot.last.epoch_mode : 1;
  switch (r.body.kind) {
    case ReportKind::kEpochStart:
      recorder_.OnEpochStart(r.robot, round, r.time_ns, r.body.ldmap);
      read.AddEvent(replay::EventKind::kEpochStart, r.time_ns, r.robot, r.body.ldmap.epoch,
                    static_cast<uint8_t>(r.body.ldmap.mode));
      read.maps.push_back(replay::RobotMap{r.robot, lab::sim::ToEpochMap(r.body.ldmap)});
      break;
    case ReportKind::kMembership:
      recorder_.collector().OnMembership(r.robot, round, r.body.removed, r.body.joined);
      for (const uint16_t m : r.body.removed) read.AddEvent(replay::EventKind::kMemberRemoved, r.time_ns, r.robot, epoch, mode, m);
      for (const uint16_t m : r.body.joined) read.AddEvent(replay::EventKind::kMemberJoined, r.time_ns, r.robot, epoch, mode, m);
      break;
    case ReportKind::kBecameJoiner:
      read.AddEvent(replay::EventKind::kBecameJoiner, r.time_ns, r.robot, epoch, mode);
      break;
    case ReportKind::kAppFault:
      recorder_.collector().OnAppFault(lab::metrics::AppFault{
          r.robot, app::ToString(static_cast<app::Callback>(r.body.callback)), r.body.epoch, r.time_ns,
          app::ToString(static_cast<app::Verdict>(r.body.verdict)), r.body.text});
      read.AddEvent(replay::EventKind::kAppFault, r.time_ns, r.robot, r.body.epoch, mode);
      player_.NoteAppFault(r.robot);
      break;
    case ReportKind::kInvalidCommand:
      recorder_.collector().OnInvalidCommand(r.robot, r.body.epoch, r.body.text);
      break;
    case ReportKind::kPayloadRefused:
      recorder_.collector().OnPayloadRefused(r.robot, r.body.epoch, std::to_string(r.body.length) + " bytes");
      break;
    case ReportKind::kSafety:
      recorder_.collector().OnSafetyIntervention(
          r.body.time_ns - start_monotonic_ns_, r.robot,
          r.body.other == motion::kWallObstacle ? std::nullopt : std::optional<uint16_t>(r.body.other));
      read.AddEvent(replay::EventKind::kSafetyIntervention, r.body.time_ns - start_monotonic_ns_, r.robot, epoch, mode,
                    r.body.other == motion::kWallObstacle ? replay::kNoRobot : r.body.other);
      break;
    case ReportKind::kRound:
      slot.last = r.body.round;
      slot.has_last = true;
      read.activations.push_back(r.body.round.activation_ns);
      read.senders.set(r.robot);
      read.heard.emplace_back(r.robot, r.body.round.heard_in_round);
      if (r.body.round.status == 0) read.phase_boundaries.push_back(r.body.round.activation_ns - start_monotonic_ns_);
      break;
    case ReportKind::kAppState: {
      const AppStateReport& a = r.body.app_state;
      using Call = lab::metrics::AgreementTracker::Call;
      recorder_.OnAppState(r.robot, round, a.new_round ? Call::kNewRound : Call::kEndOfRound, a.epoch,
                           a.cooperative, a.map_fingerprint, a.state);
      break;
    }
  }
}

// In-round delivery: each robot that reported this round could have
// heard, within the round before, the beacon of every other robot that
// sent one then; its report says whose it did hear.
void DdsWorld::CountDeliveries(int64_t round, const RoundReports& read) {
  if (auto previous = round_senders_.find(round - 1); previous != round_senders_.end()) {
    for (const auto& [receiver, heard_set] : read.heard) {
      wire::MemberSet expected = previous->second;
      expected.reset(receiver);
      wire::MemberSet delivered = heard_set;
      delivered &= expected;
      expected_deliveries_ += expected.count();
      in_round_deliveries_ += delivered.count();
    }
    round_senders_.erase(previous);
  }
  round_senders_[round] = read.senders;
}

// The round's RobotRound (for the collector) and RobotFrame (for the
// replay) of every robot, from its newest report and the boundary's truth
// (or the world now, when the boundary has none).
void DdsWorld::BuildFrames(const BoundaryTruth* truth, int64_t round_time_ns) {
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    RobotSlot& slot = robots_[id];
    const replay::Presence presence = truth != nullptr ? truth->presence[id] : player_.presence(id);
    const lab::world::BodyState body = truth != nullptr ? truth->bodies[id] : world_.state(id);
    lab::metrics::RobotRound& rr = robot_rounds_[id];
    rr = lab::metrics::RobotRound{};
    rr.id = id;
    rr.running = presence == replay::Presence::kRunning && !player_.app_faulted(id);
    rr.sync_member = slot.has_last && slot.last.status == 0;
    rr.member = rr.running && rr.sync_member;
    rr.paused = presence == replay::Presence::kPaused;
    rr.epoch = slot.last.epoch;
    rr.epoch_mode = static_cast<wire::Mode>(slot.last.epoch_mode);
    rr.phase = static_cast<wire::Phase>(slot.last.phase);
    rr.estimate_valid = rr.running && slot.last.estimate_valid != 0 && round_time_ns >= player_.scored_from_ns(id);
    rr.true_x_m = body.x_m;
    rr.true_y_m = body.y_m;
    rr.est_x_m = slot.last.est_x_m;
    rr.est_y_m = slot.last.est_y_m;
    replay::RobotFrame& f = frames_[id];
    f.id = id;
    f.presence = player_.app_faulted(id) && presence != replay::Presence::kAbsent ? replay::Presence::kCrashed : presence;
    f.status = slot.has_last ? slot.last.status : 1;
    f.phase = slot.last.phase;
    f.mode = slot.last.epoch_mode;
    f.epoch = slot.last.epoch;
    f.true_x_m = static_cast<float>(body.x_m);
    f.true_y_m = static_cast<float>(body.y_m);
    f.true_heading_rad = static_cast<float>(body.heading_rad);
    f.est_x_m = slot.last.est_x_m;
    f.est_y_m = slot.last.est_y_m;
    f.est_heading_rad = slot.last.est_heading_rad;
  }
}

// ---- The end ----------------------------------------------------------------------

// Let the last rounds' reports arrive, then record them.
void DdsWorld::DrainReports() {
  EndStress();
  last_round_ = RoundAt(start_monotonic_ns_ + step_ns_);
  const int64_t drain_until = MonotonicNow() + 300'000'000;
  while (MonotonicNow() < drain_until) {
    TakeReports();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  while (next_recorded_ <= last_round_) Record(next_recorded_++);
  recorder_.FinishReplay(!result_.stopped_early);  // the live page says a stopped run stopped
}

// Stop: Control_ says so, robots exit; SIGKILL whoever has not.
void DdsWorld::StopRobots() {
  control_sample_.state = 2;
  (void)dds_write(control_, &control_sample_);
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    if (player_.lifecycle(id) == lab::sim::Lifecycle::kPaused) robots_[id].process.Signal(SIGCONT);
  }
  const int64_t exit_deadline = MonotonicNow() + 2'000'000'000;
  for (;;) {
    bool all = true;
    for (RobotSlot& r : robots_) {
      Reap(r, false);
      all = all && (!r.process.started() || r.process.reaped());
    }
    if (all || MonotonicNow() > exit_deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EndAll();
}

// ---- Metrics ------------------------------------------------------------------------

void DdsWorld::WriteMetrics() {
  result_.delivery_ratio = expected_deliveries_ > 0 ? in_round_deliveries_ / expected_deliveries_ : 0;
  result_.skew = lab::metrics::SkewOf(skews_ns_);
  for (const RobotSlot& r : robots_) {
    result_.cpu_seconds.push_back(r.cpu_seconds);
    result_.robot_exits.push_back(r.exit);
  }
  const lab::sim::RunEnd end{static_cast<double>(step_ns_) * 1e-9, wall_seconds_, last_round_};
  lab::metrics::Metrics metrics = recorder_.Finish(recorder_.Facts(end, player_, world_));
  metrics.runtime = "dds";
  metrics.dds = DdsFacts();
  result_.metrics_json = lab::metrics::ToJson(metrics);
  result_.metrics = std::move(metrics);
  std::ofstream(std::filesystem::path(options_.out_dir) / "metrics.json") << result_.metrics_json;
}

lab::metrics::DdsMetrics DdsWorld::DdsFacts() const {
  lab::metrics::DdsMetrics dds;
  dds.domain_id = participant_->domain_id();
  dds.delivery_ratio = result_.delivery_ratio;
  dds.round_start_skew = result_.skew;
  dds.cpu_seconds_per_robot = result_.cpu_seconds;
  dds.reports_rejected = reports_rejected_;
  dds.reports_late = reports_late_;
  dds.reports_other_runs = reports_foreign_;
  dds.drives_other_runs = drives_foreign_;
  dds.stopped_early = result_.stopped_early;
  for (const RobotSlot& r : robots_) dds.robot_exits.push_back(r.exit);
  return dds;
}

}  // namespace

std::string DefaultRobotBinary() {
  if (const char* env = std::getenv("SYROF_ROBOT_BINARY"); env != nullptr && *env != '\0') return env;
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return "syrof-robot";
  return (self.parent_path() / "syrof-robot").string();
}

SwarmResult RunSwarm(const SwarmOptions& options, std::ostream& log) {
  SwarmResult result;
  auto fail = [&](int code, std::string why) {
    result.exit_code = code;
    result.error = lab::Error{.where = "", .message = std::move(why)};
    return result;
  };
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(options.scenario_path, options.overrides);
  if (!loaded.ok()) return fail(2, loaded.error->ToString());
  const std::string robot_binary = options.robot_binary.empty() ? DefaultRobotBinary() : options.robot_binary;
  if (access(robot_binary.c_str(), X_OK) != 0) return fail(1, "the robot binary " + robot_binary + " is not executable");
  std::error_code fs_error;
  std::filesystem::create_directories(options.out_dir, fs_error);
  if (fs_error) return fail(1, options.out_dir + ": " + fs_error.message());

  const uint64_t run_id = base::SplitMix64Hash(static_cast<uint64_t>(MonotonicNow()) ^ (static_cast<uint64_t>(getpid()) << 40));
  uint32_t domain = 0;
  if (options.domain_id) {
    domain = *options.domain_id;
  } else {
    const DomainIdOrError id = DomainIdFromEnvironment(run_id);
    if (!id.ok()) return fail(2, id.error->ToString());
    domain = id.domain_id;
  }
  CycloneOptions cyclone;
  cyclone.interface = options.interface;
  // With --realtime the world's loop runs above every robot task (the
  // physics task's place in registry/tasks.h), its network threads with the
  // robots' (robot_process.cpp).
  const int fifo_minimum = sched_get_priority_min(SCHED_FIFO);
  // Without CAP_SYS_NICE the robots say so each and the run goes on at
  // normal priority.
  const bool realtime = options.realtime && CanUseFifoScheduling();
  if (realtime) cyclone.network_fifo_priority = fifo_minimum + registry::kSensorTaskPriority + 1;
  ParticipantOrError made = Participant::Create(domain, cyclone);
  if (!made.ok()) return fail(1, made.error->ToString());

  {
    // A phase that fails has said why in `result`; the world ends every
    // robot as it goes out of scope.
    DdsWorld world(options, log, *loaded.scenario, robot_binary, run_id, std::move(made.participant), result);
    if (world.CreateEntities()) {
      world.OpenReplay();
      if (world.SpawnPresentRobots() && world.AwaitDiscovery() && world.Start()) {
        // This thread only, for the run; anything it forks starts at normal
        // priority (SCHED_RESET_ON_FORK) unless it asks for more, as the
        // robots do (Spawn).
        sched_param fifo{};
        fifo.sched_priority = fifo_minimum + registry::kPhysicsPriority + 1;
        const bool raised = realtime && sched_setscheduler(0, SCHED_FIFO | SCHED_RESET_ON_FORK, &fifo) == 0;
        world.Run();
        if (raised) {
          sched_param normal{};
          (void)sched_setscheduler(0, SCHED_OTHER, &normal);
        }
        world.DrainReports();
        world.StopRobots();
        world.WriteMetrics();
      }
    }
  }
  return result;
}

}  // namespace syrof::sim_dds
