#include "syrof/sim_dds/swarm.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
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
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/replay/writer.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/world_player.h"
#include "syrof/lab/world/world.h"
#include "syrof/sync/synchronizer.h"
#include "syrof/os/posix_port.h"
#include "syrof/sim_dds/participant.h"
#include "syrof/sim_dds/report_codec.h"
#include "syrof/sim_dds/robot_process.h"
#include "syrof/sim_dds/topics.h"
#include "take_samples.h"

namespace syrof::sim_dds {
namespace {

namespace scenario = lab::scenario;
namespace replay = lab::replay;

int64_t Nanoseconds(double seconds) { return std::llround(seconds * 1e9); }
int64_t MonotonicNow() { return os::PosixPort::MonotonicNowNs(); }

double Percentile(std::vector<int64_t> values, double fraction) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(std::ceil(fraction * values.size())) - (fraction > 0 ? 1 : 0));
  return static_cast<double>(values[index]);
}

// Sends one robot's simulated readings as its DDS sensor samples.
class DdsSensorSink final : public lab::sensors::ReadingSink {
 public:
  DdsSensorSink(uint16_t robot, dds_entity_t imu, dds_entity_t flow, dds_entity_t uwb)
      : robot_(robot), imu_(imu), flow_(flow), uwb_(uwb) {}
  void OnImu(const estimation::ImuReading& r) override {
    syrof_msg_dds__Imu_ s{};
    s.robot = robot_;
    s.world_time_ns = r.timestamp_ns;
    std::memcpy(s.accel_g, r.accel_g, sizeof s.accel_g);
    std::memcpy(s.gyro_dps, r.gyro_dps, sizeof s.gyro_dps);
    (void)dds_write(imu_, &s);
  }
  void OnFlow(const estimation::FlowReading& r) override {
    syrof_msg_dds__Flow_ s{};
    s.robot = robot_;
    s.world_time_ns = r.timestamp_ns;
    s.interval_ns = r.interval_ns;
    s.delta_x_px = r.delta_x_px;
    s.delta_y_px = r.delta_y_px;
    (void)dds_write(flow_, &s);
  }
  void OnUwb(const estimation::UwbReading& r) override {
    syrof_msg_dds__Uwb_ s{};
    s.robot = robot_;
    s.world_time_ns = r.timestamp_ns;
    std::memcpy(s.range_m, r.range_m, sizeof s.range_m);
    s.valid_mask = r.valid_mask;
    s.sweep = r.sweep;
    (void)dds_write(uwb_, &s);
  }

 private:
  uint16_t robot_;
  dds_entity_t imu_, flow_, uwb_;
};

// A report placed on the run's grid.
struct Received {
  uint16_t robot = 0;
  int64_t time_ns = 0;  // run time (since the grid's origin)
  ReportBody body;
};

struct RobotSlot {
  pid_t pid = -1;
  bool app_faulted = false;  // its report said so; the process stopped its app itself
  RoundReport last;          // the newest round observation
  bool has_last = false;
  double cpu_seconds = 0;
  bool reaped = false;
  std::optional<int> exit;
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
      if (r.pid > 0) (void)kill(r.pid, SIGCONT);
      return true;
    }
    return r.pid > 0 || spawn_(id);
  }

  void StopRobot(uint16_t id, int64_t /*world_ns*/, lab::sim::StopReason reason) override {
    const pid_t pid = robots_[id].pid;
    if (pid <= 0) return;
    if (reason == lab::sim::StopReason::kCrash) (void)kill(pid, SIGKILL);
    if (reason == lab::sim::StopReason::kPause) (void)kill(pid, SIGSTOP);
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
    result.error = std::move(why);
    return result;
  };
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(options.scenario_path, options.overrides);
  if (!loaded.ok()) return fail(2, loaded.error->ToString());
  const scenario::Scenario& sc = *loaded.scenario;
  const auto n = static_cast<uint16_t>(sc.robots.size());
  const int64_t alpha = Nanoseconds(sc.timing.radio_round_s);
  const int64_t physics_ns = Nanoseconds(sc.timing.physics_step_s);
  const int64_t end_ns = Nanoseconds(sc.timing.duration_s);
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
  ParticipantOrError made = Participant::Create(domain, cyclone);
  if (!made.ok()) return fail(1, made.error->ToString());
  const Participant& participant = *made.participant;

  auto entity = [&](EntityOrError e, dds_entity_t& out) {
    if (!e.ok()) return false;
    out = e.entity;
    return true;
  };
  dds_entity_t control = 0, report_reader = 0, status_reader = 0;
  std::vector<RobotSlot> robots(n);
  bool entities_ok = entity(CreateWriter(participant, TopicKind::kControl), control) &&
                     entity(CreateReader(participant, TopicKind::kReport), report_reader) &&
                     entity(CreateReader(participant, TopicKind::kStatus), status_reader);
  for (uint16_t id = 0; id < n && entities_ok; ++id) {
    RobotSlot& r = robots[id];
    entities_ok = entity(CreateWriter(participant, TopicKind::kImu, id), r.imu) &&
                  entity(CreateWriter(participant, TopicKind::kFlow, id), r.flow) &&
                  entity(CreateWriter(participant, TopicKind::kUwb, id), r.uwb) &&
                  entity(CreateReader(participant, TopicKind::kDrive, id), r.drive);
    r.bank = std::make_unique<lab::sensors::SensorBank>(sc.sensors, lab::sim::SensorSeed(sc.seed, id));
    r.sink = std::make_unique<DdsSensorSink>(id, r.imu, r.flow, r.uwb);
  }
  if (!entities_ok) return fail(1, "the world's DDS readers and writers could not be created (domain " + std::to_string(domain) + ")");

  lab::world::World world(sc.arena, lab::sim::Bodies(sc));
  lab::metrics::Collector collector(lab::metrics::CollectorConfig{n, alpha, static_cast<uint16_t>(sc.timing.silence_rounds)});
  std::ofstream replay_file;
  std::unique_ptr<replay::Writer> replay_writer;
  if (options.replay) {
    replay_file.open(std::filesystem::path(options.out_dir) / "replay", std::ios::binary);
    replay_writer = std::make_unique<replay::Writer>(replay_file, lab::sim::ReplayHeader(sc));
  }

  // ---- Processes ----------------------------------------------------------
  pid_t group = 0;  // the robots' process group (the first robot's pid)
  RobotProcessOptions robot_options;
  robot_options.scenario_path = options.scenario_path;
  robot_options.overrides = options.overrides;
  robot_options.run_id = run_id;
  robot_options.domain_id = domain;
  robot_options.interface = options.interface;
  robot_options.log_directory = (std::filesystem::path(options.out_dir) / "robots").string();
  robot_options.parent_pid = getpid();
  robot_options.realtime = options.realtime;
  robot_options.align_rounds = options.align_rounds;
  robot_options.realtime_start = options.realtime_start;
  auto spawn = [&](uint16_t id) -> bool {
    robot_options.robot = id;
    robot_options.clock_offset_us = id < options.robot_clock_offsets_us.size() ? options.robot_clock_offsets_us[id] : 0;
    const SwarmOptions::RobotNetwork* network =
        id < options.robot_networks.size() ? &options.robot_networks[id] : nullptr;
    robot_options.interface =
        network != nullptr && !network->interface.empty() ? network->interface : options.interface;
    int netns = -1;
    if (network != nullptr && !network->netns_path.empty()) {
      netns = open(network->netns_path.c_str(), O_RDONLY | O_CLOEXEC);
      if (netns < 0) return false;
    }
    std::vector<std::string> args = RobotArguments(robot_options);
    args.insert(args.begin(), robot_binary);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid < 0) {
      if (netns >= 0) close(netns);
      return false;
    }
    if (pid == 0) {
      // Only async-signal-safe calls between fork and exec.
      (void)prctl(PR_SET_PDEATHSIG, SIGKILL);
      (void)setpgid(0, group);
      if (netns >= 0 && setns(netns, CLONE_NEWNET) != 0) _exit(126);
      execv(argv[0], argv.data());
      _exit(127);
    }
    if (netns >= 0) close(netns);
    (void)setpgid(pid, group);  // both sides, so neither races the other
    if (group == 0) group = pid;
    robots[id].pid = pid;
    result.robot_pids.push_back(pid);
    return true;
  };
  auto reap = [&](RobotSlot& r, bool block) {
    if (r.pid <= 0 || r.reaped) return;
    int status = 0;
    rusage usage{};
    const pid_t done = wait4(r.pid, &status, block ? 0 : WNOHANG, &usage);
    if (done == r.pid) {
      r.reaped = true;
      r.exit = WIFSIGNALED(status) ? -WTERMSIG(status) : WEXITSTATUS(status);
      r.cpu_seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                      static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) * 1e-6;
    }
  };
  // Every exit path ends every robot: SIGKILL to the group, then reap.
  auto end_all = [&] {
    if (group > 0) (void)kill(-group, SIGKILL);
    for (RobotSlot& r : robots) {
      if (r.pid > 0 && !r.reaped) (void)kill(r.pid, SIGKILL);
      reap(r, true);
    }
  };
  struct EndGuard {
    std::function<void()> end;
    ~EndGuard() { end(); }
  } guard{end_all};

  for (uint16_t id = 0; id < n; ++id) {
    if (sc.robots[id].present_at_start && !spawn(id)) return fail(1, "fork failed for robot " + std::to_string(id));
  }

  // ---- Discovery: every present robot attached ------------------------------
  std::vector<uint8_t> attached(n, 0);
  std::vector<syrof_msg_dds__Status_> last_status(n);
  auto take_status = [&] {
    TakeSamples<syrof_msg_dds__Status_>(status_reader, [&](const syrof_msg_dds__Status_& s, const dds_sample_info_t&) {
      if (s.run_id != run_id || s.robot >= n) return;
      last_status[s.robot] = s;
      if (s.state >= 1) attached[s.robot] = 1;
    });
  };
  const int64_t discovery_deadline = MonotonicNow() + Nanoseconds(options.discovery_timeout_s);
  for (;;) {
    take_status();
    bool all = true;
    for (uint16_t id = 0; id < n; ++id) all = all && (!sc.robots[id].present_at_start || attached[id] != 0);
    if (all) break;
    for (RobotSlot& r : robots) {
      reap(r, false);
      if (r.reaped) return fail(1, "a robot process exited before it attached (see its messages above)");
    }
    if (MonotonicNow() > discovery_deadline) return fail(1, "robots did not attach within the discovery timeout");
    if (options.stop != nullptr && options.stop->load()) {
      result.stopped_early = true;
      return fail(0, "");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }

  // ---- The run --------------------------------------------------------------
  const int64_t start = MonotonicNow() + 300'000'000;  // every robot hears it before the first round
  syrof_msg_dds__Control_ control_sample{};
  control_sample.run_id = run_id;
  control_sample.state = 1;
  control_sample.start_monotonic_ns = start;
  {
    timespec realtime{};
    clock_gettime(CLOCK_REALTIME, &realtime);
    control_sample.start_realtime_ns =
        static_cast<int64_t>(realtime.tv_sec) * 1'000'000'000 + realtime.tv_nsec + (start - MonotonicNow());
  }
  control_sample.radio_round_ns = alpha;
  if (dds_write(control, &control_sample) < 0) return fail(1, "the control sample could not be written");
  // The robots' lifecycle, the faults and the join wait: the lab's rules.
  ProcessRuntime runtime(robots, spawn);
  lab::sim::WorldPlayer player(sc, world, collector);
  player.StartPresentRobots(runtime);

  std::map<int64_t, std::vector<Received>> reports_by_round;
  std::map<int64_t, BoundaryTruth> truths;
  std::vector<int64_t> skews_ns;
  std::vector<lab::metrics::RobotRound> robot_rounds(n);
  std::vector<replay::RobotFrame> frames(n);
  std::map<int64_t, wire::MemberSet> round_senders;  // robots that reported (broadcast) in a round
  int64_t reports_rejected = 0, reports_late = 0, reports_foreign = 0;
  int64_t next_recorded = 1;
  double expected_deliveries = 0;
  double in_round_deliveries = 0;
  lab::metrics::AgreementTracker agreement;
  lab::goals::GoalMonitor goal_monitor(sc.goal);
  bool any_epoch = false;
  uint16_t newest_epoch = 0;

  // The robots' rounds on the world's clock. On one grid (no alignment)
  // round r starts at start + r * alpha. Aligning robots move their
  // boundaries together and number their own rounds, so the world follows
  // them: the origin is the median over running robots of (when a robot's
  // round report went out) - round * alpha, from each robot's newest report.
  int64_t round_origin = start;
  std::vector<std::optional<int64_t>> robot_origins(n);
  auto round_at = [&](int64_t monotonic_ns) {
    const int64_t since = monotonic_ns - round_origin;
    return since >= 0 ? since / alpha : -((-since + alpha - 1) / alpha);
  };
  auto follow_robots = [&] {
    std::vector<int64_t> origins;
    for (uint16_t id = 0; id < n; ++id) {
      if (player.running(id) && robot_origins[id]) origins.push_back(*robot_origins[id]);
    }
    if (origins.empty()) return;
    std::nth_element(origins.begin(), origins.begin() + static_cast<std::ptrdiff_t>(origins.size() / 2), origins.end());
    round_origin = origins[origins.size() / 2];
  };

  auto take_reports = [&] {
    TakeSamples<syrof_msg_dds__Report_>(report_reader, [&](const syrof_msg_dds__Report_& s, const dds_sample_info_t&) {
      if (s.run_id != run_id) {
        ++reports_foreign;
        return;
      }
      if (s.robot >= n) {
        ++reports_rejected;
        return;
      }
      DecodedReport decoded = DecodeReport(s.kind, std::span<const uint8_t>(s.body._buffer, s.body._length), n);
      if (!decoded.body) {
        ++reports_rejected;
        log << "syrof swarm: robot " << s.robot << "'s report " << s.sequence_number << " refused: " << decoded.error << "\n";
        return;
      }
      Received received{s.robot, s.robot_time_ns - start, std::move(*decoded.body)};
      const int64_t round = received.body.kind == ReportKind::kRound
                                ? static_cast<int64_t>(received.body.round.round)
                                : round_at(s.robot_time_ns + alpha / 2);
      if (options.align_rounds && received.body.kind == ReportKind::kRound) {
        robot_origins[s.robot] = received.body.round.activation_ns - round * alpha;
      }
      if (round < next_recorded) {
        ++reports_late;
        return;
      }
      reports_by_round[round].push_back(std::move(received));
    });
  };

  // The running robots' true positions (at a recorded boundary, or now),
  // for the scenario's goal checks.
  auto running_poses = [&](const BoundaryTruth* truth) {
    std::vector<lab::goals::RobotPose> poses;
    for (uint16_t id = 0; id < n; ++id) {
      const replay::Presence presence = truth != nullptr ? truth->presence[id] : player.presence(id);
      if (presence != replay::Presence::kRunning || robots[id].app_faulted) continue;
      const lab::world::BodyState& body = truth != nullptr ? truth->bodies[id] : world.state(id);
      poses.push_back(lab::goals::RobotPose{id, body.x_m, body.y_m, world.body_radius_m(id)});
    }
    return poses;
  };

  // The recorder of round r: the lab's StepRecorder from reports.
  auto record = [&](int64_t round) {
    const auto truth_it = truths.find(round);
    const int64_t round_time_ns = truth_it != truths.end() ? truth_it->second.time_ns : round_origin - start + round * alpha;
    std::vector<Received> reports;
    if (auto it = reports_by_round.find(round); it != reports_by_round.end()) {
      reports = std::move(it->second);
      reports_by_round.erase(it);
    }
    std::stable_sort(reports.begin(), reports.end(), [](const Received& a, const Received& b) { return a.robot < b.robot; });
    std::vector<replay::Event> events;
    std::vector<replay::RobotMap> maps;
    std::vector<int64_t> activations;
    std::vector<int64_t> phase_boundaries;
    wire::MemberSet senders;
    std::vector<std::pair<uint16_t, wire::MemberSet>> heard;  // each reporting robot's in-round deliveries
    std::optional<uint16_t> epoch_sample;  // a newer epoch started this round: the goal checks sample poses
    auto event = [&](replay::EventKind kind, int64_t time_ns, uint16_t robot, uint16_t epoch, uint8_t mode,
                     uint16_t other = replay::kNoRobot) {
      replay::Event e{};
      e.kind = kind;
      e.robot = robot;
      e.other = other;
      e.epoch = epoch;
      e.mode = mode;
      e.time_ns = time_ns;
      events.push_back(e);
    };
    for (Received& r : reports) {
      RobotSlot& slot = robots[r.robot];
      const uint16_t epoch = slot.has_last ? slot.last.epoch : 0;
      const uint8_t mode = slot.has_last ? slot.last.epoch_mode : 1;
      switch (r.body.kind) {
        case ReportKind::kEpochStart:
          collector.OnEpochStart(r.robot, round, r.time_ns, r.body.ldmap);
          if (!any_epoch || sync::EpochDifference(r.body.ldmap.epoch, newest_epoch) > 0) {
            any_epoch = true;
            newest_epoch = r.body.ldmap.epoch;
            epoch_sample = newest_epoch;
          }
          event(replay::EventKind::kEpochStart, r.time_ns, r.robot, r.body.ldmap.epoch,
                static_cast<uint8_t>(r.body.ldmap.mode));
          maps.push_back(replay::RobotMap{r.robot, lab::sim::ToEpochMap(r.body.ldmap)});
          break;
        case ReportKind::kMembership:
          collector.OnMembership(r.robot, round, r.body.removed, r.body.joined);
          for (const uint16_t m : r.body.removed) event(replay::EventKind::kMemberRemoved, r.time_ns, r.robot, epoch, mode, m);
          for (const uint16_t m : r.body.joined) event(replay::EventKind::kMemberJoined, r.time_ns, r.robot, epoch, mode, m);
          break;
        case ReportKind::kBecameJoiner:
          event(replay::EventKind::kBecameJoiner, r.time_ns, r.robot, epoch, mode);
          break;
        case ReportKind::kAppFault:
          collector.OnAppFault(lab::metrics::AppFault{
              r.robot, app::ToString(static_cast<app::Callback>(r.body.callback)), r.body.epoch, r.time_ns,
              app::ToString(static_cast<app::Verdict>(r.body.verdict)), r.body.text});
          event(replay::EventKind::kAppFault, r.time_ns, r.robot, r.body.epoch, mode);
          slot.app_faulted = true;
          break;
        case ReportKind::kInvalidCommand:
          collector.OnInvalidCommand(r.robot, r.body.epoch, r.body.text);
          break;
        case ReportKind::kPayloadRefused:
          collector.OnPayloadRefused(r.robot, r.body.epoch, std::to_string(r.body.length) + " bytes");
          break;
        case ReportKind::kSafety:
          collector.OnSafetyIntervention(r.body.time_ns - start, r.robot,
                                         r.body.other == motion::kWallObstacle ? std::nullopt
                                                                               : std::optional<uint16_t>(r.body.other));
          event(replay::EventKind::kSafetyIntervention, r.body.time_ns - start, r.robot, epoch, mode,
                r.body.other == motion::kWallObstacle ? replay::kNoRobot : r.body.other);
          break;
        case ReportKind::kRound:
          slot.last = r.body.round;
          slot.has_last = true;
          activations.push_back(r.body.round.activation_ns);
          senders.set(r.robot);
          heard.emplace_back(r.robot, r.body.round.heard_in_round);
          if (r.body.round.status == 0) phase_boundaries.push_back(r.body.round.activation_ns - start);
          break;
        case ReportKind::kAppState: {
          const AppStateReport& a = r.body.app_state;
          using Call = lab::metrics::AgreementTracker::Call;
          agreement.OnAppState(r.robot, round, a.new_round ? Call::kNewRound : Call::kEndOfRound, a.epoch,
                               a.cooperative, a.map_fingerprint, a.state);
          break;
        }
      }
    }
    // In-round delivery: each robot that reported this round could have
    // heard, within the round before, the beacon of every other robot that
    // sent one then; its report says whose it did hear.
    if (auto previous = round_senders.find(round - 1); previous != round_senders.end()) {
      for (const auto& [receiver, heard_set] : heard) {
        wire::MemberSet expected = previous->second;
        expected.reset(receiver);
        wire::MemberSet delivered = heard_set;
        delivered &= expected;
        expected_deliveries += expected.count();
        in_round_deliveries += delivered.count();
      }
      round_senders.erase(previous);
    }
    round_senders[round] = senders;
    if (activations.size() >= 2) {
      const auto [low, high] = std::minmax_element(activations.begin(), activations.end());
      skews_ns.push_back(*high - *low);
    }
    collector.OnRoundPhases(phase_boundaries);
    for (uint16_t id = 0; id < n; ++id) {
      RobotSlot& slot = robots[id];
      const replay::Presence presence = truth_it != truths.end() ? truth_it->second.presence[id] : player.presence(id);
      const lab::world::BodyState body = truth_it != truths.end() ? truth_it->second.bodies[id] : world.state(id);
      lab::metrics::RobotRound& rr = robot_rounds[id];
      rr = lab::metrics::RobotRound{};
      rr.id = id;
      rr.running = presence == replay::Presence::kRunning && !slot.app_faulted;
      rr.sync_member = slot.has_last && slot.last.status == 0;
      rr.member = rr.running && rr.sync_member;
      rr.paused = presence == replay::Presence::kPaused;
      rr.epoch = slot.last.epoch;
      rr.epoch_mode = static_cast<wire::Mode>(slot.last.epoch_mode);
      rr.phase = static_cast<wire::Phase>(slot.last.phase);
      rr.estimate_valid = rr.running && slot.last.estimate_valid != 0 && round_time_ns >= player.scored_from_ns(id);
      rr.true_x_m = body.x_m;
      rr.true_y_m = body.y_m;
      rr.est_x_m = slot.last.est_x_m;
      rr.est_y_m = slot.last.est_y_m;
      replay::RobotFrame& f = frames[id];
      f.id = id;
      f.presence = slot.app_faulted && presence != replay::Presence::kAbsent ? replay::Presence::kCrashed : presence;
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
    collector.OnRoundEnd(round, robot_rounds);
    if (!goal_monitor.empty()) {
      const std::vector<lab::goals::RobotPose> running = running_poses(truth_it != truths.end() ? &truth_it->second : nullptr);
      const double time_s = static_cast<double>(round_time_ns) * 1e-9;
      goal_monitor.OnRound(time_s, running);
      if (epoch_sample) goal_monitor.OnEpoch(*epoch_sample, time_s, running);
    }
    if (truth_it != truths.end()) {
      events.insert(events.begin(), truth_it->second.events.begin(), truth_it->second.events.end());
      truths.erase(truth_it);
    }
    std::stable_sort(events.begin(), events.end(), [](const replay::Event& a, const replay::Event& b) { return a.time_ns < b.time_ns; });
    if (replay_writer != nullptr) replay_writer->WriteRound(static_cast<uint32_t>(round), round_time_ns, frames, events, maps);
  };

  int64_t step_ns = 0;
  int64_t next_truth = 1;  // the next round whose boundary truth is taken
  int64_t next_progress_ns = 1'000'000'000;
  while (step_ns < end_ns) {
    if (options.stop != nullptr && options.stop->load()) {
      result.stopped_early = true;
      break;
    }
    step_ns += physics_ns;
    // Sleep until this step's instant on the grid.
    const int64_t due = start + step_ns;
    const int64_t wait = due - MonotonicNow();
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
    // Faults on the radio-round grid, as real ones, with the lab's rules.
    player.PlayFaults(step_ns, runtime);
    // Drive commands to the bodies of running robots.
    for (uint16_t id = 0; id < n; ++id) {
      RobotSlot& r = robots[id];
      TakeSamples<syrof_msg_dds__Drive_>(r.drive, [&](const syrof_msg_dds__Drive_& s, const dds_sample_info_t&) {
        if (s.robot != id || !player.running(id) || s.kind > 1) return;
        motion::DriveCommand command{};
        command.timestamp_ns = s.robot_time_ns;
        command.kind = static_cast<motion::DriveKind>(s.kind);
        command.vx_mps = s.vx_mps;
        command.vy_mps = s.vy_mps;
        command.yaw_rate_radps = s.yaw_rate_radps;
        command.left_mps = s.left_mps;
        command.right_mps = s.right_mps;
        world.SetDrive(id, command);
      });
    }
    world.Step(step_ns, static_cast<double>(physics_ns) * 1e-9);
    player.TakeContacts(runtime);
    // Sensors of running robots.
    for (uint16_t id = 0; id < n; ++id) {
      RobotSlot& r = robots[id];
      if (player.running(id)) r.bank->Sample(step_ns, world.true_state(id), *r.sink);
    }
    // A round boundary of the robots: keep the truth for the recorder.
    while (next_truth <= round_at(start + step_ns)) {
      BoundaryTruth truth;
      truth.time_ns = step_ns;
      for (uint16_t id = 0; id < n; ++id) {
        truth.bodies.push_back(world.state(id));
        truth.presence.push_back(player.presence(id));
      }
      truth.events = player.TakeEvents();
      truths[next_truth++] = std::move(truth);
    }
    take_reports();
    if (options.align_rounds) follow_robots();
    take_status();
    for (uint16_t id = 0; id < n; ++id) {
      if (player.lifecycle(id) == lab::sim::Lifecycle::kCrashed) reap(robots[id], false);
    }
    while (next_recorded + kRecordLagRounds <= round_at(start + step_ns)) record(next_recorded++);
    if (options.progress && step_ns >= next_progress_ns) {
      options.progress(static_cast<double>(step_ns) * 1e-9);
      next_progress_ns += 1'000'000'000;
    }
  }
  const double wall_seconds = static_cast<double>(MonotonicNow() - start) * 1e-9;
  // Let the last rounds' reports arrive, then record them.
  const int64_t last_round = round_at(start + step_ns);
  const int64_t drain_until = MonotonicNow() + 300'000'000;
  while (MonotonicNow() < drain_until) {
    take_reports();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  while (next_recorded <= last_round) record(next_recorded++);
  if (replay_writer != nullptr) replay_writer->Finish();

  // Stop: Control_ says so, robots exit; SIGKILL whoever has not.
  control_sample.state = 2;
  (void)dds_write(control, &control_sample);
  for (uint16_t id = 0; id < n; ++id) {
    if (player.lifecycle(id) == lab::sim::Lifecycle::kPaused && robots[id].pid > 0) (void)kill(robots[id].pid, SIGCONT);
  }
  const int64_t exit_deadline = MonotonicNow() + 2'000'000'000;
  for (;;) {
    bool all = true;
    for (RobotSlot& r : robots) {
      reap(r, false);
      all = all && (r.pid <= 0 || r.reaped);
    }
    if (all || MonotonicNow() > exit_deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  end_all();

  // ---- Metrics ----------------------------------------------------------------
  result.delivery_ratio = expected_deliveries > 0 ? in_round_deliveries / expected_deliveries : 0;
  result.skew.rounds = static_cast<int64_t>(skews_ns.size());
  result.skew.p50_us = Percentile(skews_ns, 0.50) * 1e-3;
  result.skew.p99_us = Percentile(skews_ns, 0.99) * 1e-3;
  result.skew.max_us = skews_ns.empty() ? 0 : static_cast<double>(*std::max_element(skews_ns.begin(), skews_ns.end())) * 1e-3;
  for (const RobotSlot& r : robots) {
    result.cpu_seconds.push_back(r.cpu_seconds);
    result.robot_exits.push_back(r.exit);
  }

  lab::metrics::RunFacts facts = lab::sim::ScenarioFacts(sc, world);
  facts.sim_seconds = static_cast<double>(step_ns) * 1e-9;
  facts.wall_seconds = wall_seconds;
  facts.radio_rounds = last_round;
  // The built-in app's goal from the final true poses, as the lab does, or
  // the scenario's declared checks (goal:), sampled on the recorded rounds.
  std::vector<lab::apps::GoalPose> poses;
  for (uint16_t id = 0; id < n; ++id) {
    const lab::world::BodyState& body = world.state(id);
    poses.push_back(lab::apps::GoalPose{id, body.x_m, body.y_m, body.heading_rad,
                                        player.running(id) && !robots[id].app_faulted,
                                        world.body_radius_m(id)});
  }
  facts.goal = lab::sim::BuiltinGoal(sc, poses);
  if (!sc.goal.empty()) {
    facts.goal = lab::sim::DeclaredGoal(sc.app.name, goal_monitor.Finish(facts.sim_seconds, running_poses(nullptr)));
  }
  lab::metrics::Metrics metrics = collector.Finish(facts);
  metrics.runtime = "dds";
  metrics.agreement = agreement.Finish();
  lab::metrics::DdsMetrics dds;
  dds.domain_id = domain;
  dds.delivery_ratio = result.delivery_ratio;
  dds.skew_rounds = result.skew.rounds;
  dds.skew_p50_us = result.skew.p50_us;
  dds.skew_p99_us = result.skew.p99_us;
  dds.skew_max_us = result.skew.max_us;
  dds.cpu_seconds_per_robot = result.cpu_seconds;
  dds.reports_rejected = reports_rejected;
  dds.reports_late = reports_late;
  dds.reports_other_runs = reports_foreign;
  dds.stopped_early = result.stopped_early;
  for (const RobotSlot& r : robots) dds.robot_exits.push_back(r.exit);
  metrics.dds = std::move(dds);
  result.metrics_json = lab::metrics::ToJson(metrics);
  result.metrics = std::move(metrics);
  std::ofstream(std::filesystem::path(options.out_dir) / "metrics.json") << result.metrics_json;
  return result;
}

}  // namespace syrof::sim_dds
