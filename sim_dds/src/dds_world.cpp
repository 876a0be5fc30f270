#include "syrof/sim_dds/dds_world.h"

#include <sched.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <thread>

#include "syrof/base/split_mix64.h"
#include "syrof/lab/sim/remote_world.h"
#include "syrof/lab/sim/round_recorder.h"
#include "syrof/os/posix_port.h"
#include "syrof/registry/tasks.h"
#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/report_codec.h"
#include "syrof/sim_dds/topics.h"
#include "dds_links.h"
#include "robot_fleet.h"
#include "round_grid.h"
#include "round_reports.h"
#include "take_samples.h"
#include "world_stress.h"

namespace syrof::sim_dds {
namespace {

namespace scenario = lab::scenario;

int64_t Nanoseconds(double seconds) { return std::llround(seconds * 1e9); }
int64_t MonotonicNow() { return os::PosixPort::MonotonicNowNs(); }

// Reports of round r are recorded once the grid is this far past r.
constexpr int64_t kRecordLagRounds = 10;

// The DDS world: an adapter on the world loop (lab/sim/remote_world.h). The
// loop owns the world, its rules, its sensors and its record; this supplies
// the robot processes (robot_fleet.h), the DDS links (dds_links.h), the
// reports read into each round's common report (round_reports.h), the grid
// the rounds follow (round_grid.h), the control sample and the stress
// (world_stress.h).
//
// The run's phases, in the order RunSwarm calls them: CreateEntities,
// OpenReplay, SpawnPresentRobots, AwaitDiscovery, Start, Run (one instant
// per physics step, the recorder ten rounds behind), DrainReports,
// StopRobots, WriteMetrics. A phase that fails says why in the result and
// returns false. Every exit path ends every robot (the destructor).
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
  bool Fail(const StressFailure& failure) { return Fail(failure.exit_code, failure.error.ToString()); }

  // Ends the stress and every robot; keeps the stress's figures.
  void EndAll();
  void EndStress();
  void TakeStatus();
  int64_t RoundNow() const { return grid_.RoundAt(start_monotonic_ns_ + step_ns_); }
  void TakeReports() { reports_.Take(report_reader_, start_monotonic_ns_, grid_, next_recorded_); }
  void Record(int64_t round);
  lab::metrics::DdsMetrics DdsFacts() const;

  const SwarmOptions& options_;
  std::ostream& log_;
  SwarmResult& result_;
  const scenario::Scenario& scenario_;
  const uint16_t swarm_size_;
  const int64_t radio_round_ns_;
  const int64_t physics_step_ns_;
  const int64_t duration_ns_;
  // Faults on the radio-round grid, as real ones, with the lab's rules, one
  // physics step ahead of their instant. A fault due at a round boundary
  // acts in the lab before the robots' round tasks at that instant (its
  // priority is higher); here the world and the robots are processes woken
  // at the same instant, so a robot killed or stopped right at the boundary
  // raced its own round task and sometimes sent that round's beacon, and the
  // swarm removed it a round later than in the lab. Half a round at most:
  // more would move a fault to the round before.
  const int64_t fault_lead_ns_;
  const uint64_t run_id_;
  const std::unique_ptr<Participant> participant_;

  // The world, its rules, its sensors and its record, as every runtime outside the lab has them.
  lab::sim::RemoteWorld loop_;
  DdsLinks links_;
  RobotFleet fleet_;  // what the loop's WorldPlayer does to the robot processes
  WorldStress stress_;
  RoundReportBook reports_;
  std::ofstream replay_file_;

  dds_entity_t control_ = 0, report_reader_ = 0, status_reader_ = 0;
  syrof_msg_dds__Control_ control_sample_{};
  // ---- Discovery: every present robot attached
  std::vector<uint8_t> attached_;

  // ---- The run
  int64_t start_monotonic_ns_ = 0;
  int64_t next_recorded_ = 1;  // the next round to record
  RoundGrid grid_;
  int64_t step_ns_ = 0;
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
      fault_lead_ns_(2 * physics_step_ns_ <= radio_round_ns_ ? physics_step_ns_ : 0),
      run_id_(run_id),
      participant_(std::move(participant)),
      loop_(scenario, lab::sim::CollectorConfigFor(scenario)),
      links_(swarm_size_, run_id),
      fleet_(options, std::move(robot_binary), run_id, participant_->domain_id(), loop_, log, result.robot_pids),
      stress_(options.stress, swarm_size_),
      reports_(loop_, run_id, options.align_rounds, log),
      attached_(swarm_size_, 0),
      grid_(radio_round_ns_, swarm_size_) {
  loop_.recorder().MeasureAgreement();  // the robots report every app return (kAppState)
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
  const bool entities_ok = Assign(CreateWriter(participant, TopicKind::kControl), control_) &&
                           Assign(CreateReader(participant, TopicKind::kReport), report_reader_) &&
                           Assign(CreateReader(participant, TopicKind::kStatus), status_reader_) &&
                           links_.Create(participant);
  if (!entities_ok) {
    return Fail(1, "the world's DDS readers and writers could not be created (domain " +
                       std::to_string(participant.domain_id()) + ")");
  }
  return true;
}

void DdsWorld::OpenReplay() {
  for (lab::replay::RoundSink* sink : options_.sinks) loop_.recorder().AddSink(sink);
  if (!options_.replay) return;
  replay_file_.open(std::filesystem::path(options_.out_dir) / "replay", std::ios::binary);
  loop_.recorder().OpenReplay(replay_file_);
}

bool DdsWorld::SpawnPresentRobots() {
  if (const std::optional<StressFailure> failure = stress_.OpenQuota()) return Fail(*failure);
  fleet_.JoinQuota(stress_.quota());
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    if (scenario_.robots[id].present_at_start && !fleet_.Spawn(id)) return Fail(1, fleet_.spawn_error());
  }
  return true;
}

void DdsWorld::TakeStatus() {
  TakeSamples<syrof_msg_dds__Status_>(status_reader_, [&](const syrof_msg_dds__Status_& s, const dds_sample_info_t&) {
    if (s.run_id != run_id_ || s.robot >= swarm_size_) return;
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
    for (uint16_t id = 0; id < swarm_size_; ++id) fleet_.Reap(id, false);
    if (fleet_.AnyEnded()) return Fail(1, "a robot process exited before it attached (see its messages above)");
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
  grid_.Start(start_monotonic_ns_);
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
  loop_.player().StartPresentRobots(fleet_);
  // The plan from the seed; the world's own stalls are played by a child
  // process, since a stopped process cannot wake itself.
  if (const std::optional<StressFailure> failure = stress_.Start(duration_ns_, start_monotonic_ns_, log_)) {
    return Fail(*failure);
  }
  return true;
}

void DdsWorld::Run() {
  // Robot stalls: SIGSTOP to a running robot, SIGCONT at their end unless
  // the scenario has paused, crashed or ended the robot meanwhile.
  const auto running = [this](uint16_t id) { return loop_.player().running(id) && fleet_.process(id).started(); };
  const auto signal = [this](uint16_t id, bool stop) { fleet_.process(id).Signal(stop ? SIGSTOP : SIGCONT); };
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
    loop_.StepInstant({step_ns_, step_ns_ + fault_lead_ns_, static_cast<double>(physics_step_ns_) * 1e-9,
                       RoundNow()},
                      fleet_, links_);
    stress_.Play(step_ns_, running, signal);
    TakeReports();
    if (options_.align_rounds) grid_.FollowRobots([this](uint16_t id) { return loop_.player().running(id); });
    TakeStatus();
    for (uint16_t id = 0; id < swarm_size_; ++id) {
      if (loop_.player().lifecycle(id) == lab::sim::Lifecycle::kCrashed) fleet_.Reap(id, false);
    }
    while (next_recorded_ + kRecordLagRounds <= RoundNow()) Record(next_recorded_++);
    if (options_.progress && step_ns_ >= next_progress_ns) {
      options_.progress(static_cast<double>(step_ns_) * 1e-9);
      next_progress_ns += 1'000'000'000;
    }
  }
  wall_seconds_ = static_cast<double>(MonotonicNow() - start_monotonic_ns_) * 1e-9;
}

// The recorder of round r: its reports read into the common round report,
// recorded by the loop.
void DdsWorld::Record(int64_t round) {
  lab::sim::RemoteRound read = reports_.Read(round, start_monotonic_ns_);
  loop_.RecordRound(round, grid_.StartOf(round) - start_monotonic_ns_, read);
}

// ---- The end ----------------------------------------------------------------------

// No stall outlives the run: robots resumed (unless paused by the
// scenario), the world's staller stopped and reaped.
void DdsWorld::EndStress() {
  stress_.End([this](uint16_t id) { return loop_.player().lifecycle(id) != lab::sim::Lifecycle::kPaused; },
              [this](uint16_t id, bool stop) { fleet_.process(id).Signal(stop ? SIGSTOP : SIGCONT); });
  result_.stalls = stress_.stalls();
  result_.stress_seed = stress_.seed();
}

// Every exit path ends every robot: SIGKILL to each robot's process group, then reap.
void DdsWorld::EndAll() {
  EndStress();
  fleet_.EndAll();
}

// Let the last rounds' reports arrive, then record them.
void DdsWorld::DrainReports() {
  EndStress();
  last_round_ = RoundNow();
  const int64_t drain_until = MonotonicNow() + 300'000'000;
  while (MonotonicNow() < drain_until) {
    TakeReports();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  while (next_recorded_ <= last_round_) Record(next_recorded_++);
  loop_.recorder().FinishReplay(!result_.stopped_early);  // the live page says a stopped run stopped
}

// Stop: Control_ says so, robots exit; SIGKILL whoever has not.
void DdsWorld::StopRobots() {
  control_sample_.state = 2;
  (void)dds_write(control_, &control_sample_);
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    if (loop_.player().lifecycle(id) == lab::sim::Lifecycle::kPaused) fleet_.process(id).Signal(SIGCONT);
  }
  const int64_t exit_deadline = MonotonicNow() + 2'000'000'000;
  for (;;) {
    for (uint16_t id = 0; id < swarm_size_; ++id) fleet_.Reap(id, false);
    if (fleet_.AllReaped() || MonotonicNow() > exit_deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EndAll();
}

// ---- Metrics ------------------------------------------------------------------------

void DdsWorld::WriteMetrics() {
  result_.delivery_ratio = reports_.delivery_ratio();
  result_.skew = loop_.skew();
  result_.cpu_seconds = fleet_.cpu_seconds();
  result_.robot_exits = fleet_.exits();
  const lab::sim::RunEnd end{static_cast<double>(step_ns_) * 1e-9, wall_seconds_, last_round_};
  lab::metrics::Metrics metrics = loop_.Finish(end);
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
  dds.cpu_seconds_per_robot = result_.cpu_seconds;
  dds.reports_rejected = reports_.rejected();
  dds.reports_late = reports_.late();
  dds.reports_other_runs = reports_.other_runs();
  dds.drives_other_runs = links_.drives_other_runs();
  dds.stopped_early = result_.stopped_early;
  dds.robot_exits = result_.robot_exits;
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
