#include "syrof/sim_dds/robot_process.h"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <thread>
#include <type_traits>
#include <variant>

#include "syrof/app_host/app_supply.h"
#include "syrof/estimation/topics.h"
#include "syrof/lab/sensors/sensor_publishers.h"
#include "syrof/lab/sim/recording_app.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/motion/drive.h"
#include "syrof/os/posix_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/queries/queries.h"
#include "syrof/registry/tasks.h"
#include "syrof/runtime/robot.h"
#include "syrof/sim_dds/beacon_radio.h"
#include "syrof/sim_dds/report_codec.h"
#include "syrof/sim_dds/topics.h"
#include "take_samples.h"

namespace syrof::sim_dds {
namespace {

std::atomic<bool> g_stop_requested{false};
void RequestStop(int) { g_stop_requested.store(true); }

int64_t CpuTimeNs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// Writes Report_ samples: from the round task (observer hooks, round
// observations) and, for init's fault, from the main thread before the port
// starts. The mutex keeps sequence numbers in writing order.
class ReportWriter {
 public:
  ReportWriter(dds_entity_t writer, uint64_t run_id, uint16_t robot) : writer_(writer), run_id_(run_id), robot_(robot) {}
  void Write(ReportKind kind, int64_t monotonic_ns, const std::vector<uint8_t>& body) {
    std::lock_guard<std::mutex> guard(mutex_);
    syrof_msg_dds__Report_ sample{};
    sample.run_id = run_id_;
    sample.robot = robot_;
    sample.sequence_number = sequence_++;
    sample.kind = static_cast<uint8_t>(kind);
    sample.robot_time_ns = monotonic_ns;
    sample.body._length = static_cast<uint32_t>(body.size());
    sample.body._maximum = sample.body._length;
    sample.body._buffer = const_cast<uint8_t*>(body.data());
    sample.body._release = false;
    if (dds_write(writer_, &sample) < 0) ++failed_;
  }
  uint64_t failed() const { return failed_; }

 private:
  std::mutex mutex_;
  dds_entity_t writer_;
  uint64_t run_id_;
  uint16_t robot_;
  uint32_t sequence_ = 0;
  uint64_t failed_ = 0;
};

// The robot's observer: every hook becomes a Report_ (report_codec.h), its
// time on CLOCK_MONOTONIC so the world can place it on the run's grid.
class ReportObserver final : public runtime::RobotObserver {
 public:
  ReportObserver(ReportWriter& writer, const os::PosixPort& port) : writer_(writer), port_(port) {}
  void OnEpochStart(uint16_t, int64_t now_ns, const sync::LDMap& ldmap) override {
    writer_.Write(ReportKind::kEpochStart, port_.PortToMonotonic(now_ns), EncodeEpochStart(ldmap));
  }
  void OnMembership(uint16_t, int64_t now_ns, const wire::MemberSet& removed, const wire::MemberSet& joined) override {
    writer_.Write(ReportKind::kMembership, port_.PortToMonotonic(now_ns), EncodeMembership(removed, joined));
  }
  void OnBecameJoiner(uint16_t, int64_t now_ns) override {
    writer_.Write(ReportKind::kBecameJoiner, port_.PortToMonotonic(now_ns), {});
  }
  void OnAppFault(uint16_t, int64_t now_ns, app::Callback callback, uint16_t epoch,
                  const app::CallStatus& status) override {
    writer_.Write(ReportKind::kAppFault, port_.PortToMonotonic(now_ns),
                  EncodeAppFault(static_cast<uint8_t>(callback), epoch, static_cast<uint8_t>(status.verdict()),
                                 status.detail()));
  }
  void OnInvalidCommand(uint16_t, int64_t now_ns, uint16_t epoch, const app::CommandCheck& check) override {
    std::array<char, 64> what{};
    writer_.Write(ReportKind::kInvalidCommand, port_.PortToMonotonic(now_ns),
                  EncodeInvalidCommand(epoch, app::Describe(check, what.data(), what.size())));
  }
  void OnPayloadRefused(uint16_t, int64_t now_ns, uint16_t epoch, size_t length) override {
    writer_.Write(ReportKind::kPayloadRefused, port_.PortToMonotonic(now_ns),
                  EncodePayloadRefused(epoch, static_cast<uint32_t>(length)));
  }
  void OnSafetyIntervention(uint16_t, int64_t time_ns, uint16_t other) override {
    const int64_t monotonic = port_.PortToMonotonic(time_ns);
    writer_.Write(ReportKind::kSafety, monotonic, EncodeSafety(monotonic, other));
  }
  void OnSafetyPrecaution(uint16_t, int64_t time_ns, uint16_t other) override {
    const int64_t monotonic = port_.PortToMonotonic(time_ns);
    writer_.Write(ReportKind::kPrecaution, monotonic, EncodePrecaution(monotonic, other));
  }

 private:
  ReportWriter& writer_;
  const os::PosixPort& port_;
};

// The robot's Radio: the beacon goes to BeaconRadio; then, still in the
// round task after the synchronizer's step, the round's observation goes to
// the world (the lab's recorder reads the same fields from each robot).
class RoundTap final : public runtime::Radio {
 public:
  // align: the robot aligns its rounds from the beacons it hears (and moves
  // its boundaries), so it numbers its own rounds rather than reading them
  // off the world's grid; beacon_delay_ns: the arrival expected from an
  // aligned sender after its boundary.
  RoundTap(ReportWriter& writer, const os::PosixPort& port, int64_t radio_round_ns, bool align, int64_t beacon_delay_ns)
      : writer_(writer), port_(port), radio_round_ns_(radio_round_ns), align_(align), beacon_delay_ns_(beacon_delay_ns) {}
  void Connect(BeaconRadio* radio, const runtime::Robot* robot) {
    radio_ = radio;
    robot_ = robot;
  }
  void set_start(int64_t start_monotonic_ns) { origin_ns_.store(start_monotonic_ns); }
  // The newest StateEstimate, from the main thread's polled subscription:
  // Robot::estimate() reads the motion task's copy too, which is only safe
  // from the port's own thread on SimPort.
  void set_estimate(const estimation::StateEstimate& estimate) {
    std::lock_guard<std::mutex> guard(estimate_mutex_);
    estimate_ = estimate;
  }
  estimation::StateEstimate latest_estimate() const {
    std::lock_guard<std::mutex> guard(estimate_mutex_);
    return estimate_;
  }
  // The current round, or -1 before the start: on the world's grid, or with
  // alignment on the robot's own, whose origin follows its moved boundaries.
  int64_t CurrentRound() const {
    const int64_t origin = origin_ns_.load();
    if (origin < 0) return -1;
    const int64_t since = os::PosixPort::MonotonicNowNs() - origin;
    return since < 0 ? -1 : since / radio_round_ns_;
  }
  // The round whose beacons arrive now: the nearest round to the arrival
  // expected from an aligned sender (its boundary plus beacon_delay_ns).
  int64_t ExpectedRound() const {
    const int64_t origin = origin_ns_.load();
    if (origin < 0) return -1;
    const int64_t since = os::PosixPort::MonotonicNowNs() - origin - beacon_delay_ns_ + radio_round_ns_ / 2;
    return since < 0 ? -1 : since / radio_round_ns_;
  }
  void Broadcast(const wire::Beacon& beacon) override {
    if (robot_ == nullptr) {
      if (radio_ != nullptr) radio_->Broadcast(beacon);
      return;
    }
    // The round from the step's release: the nearest on the grid (or the
    // robot's own grid), so a boundary moved by the alignment keeps its
    // number. The skew's sample is when the beacon actually went out,
    // however late the thread woke.
    const int64_t release = port_.PortToMonotonic(robot_->last_round_ns());
    int64_t round = std::max<int64_t>(0, (release - origin_ns_.load() + radio_round_ns_ / 2) / radio_round_ns_);
    if (align_) {
      // The swarm's count where the senders agree on another (a late
      // joiner, a grid the swarm drifted off); then the origin under this
      // boundary, so CurrentRound and the sample's round say `round`.
      const int64_t offset = radio_ != nullptr ? radio_->AgreedRoundOffset(round - 1) : 0;
      round = std::max<int64_t>(0, round + offset);
      origin_ns_.store(release - round * radio_round_ns_);
      if (offset != 0) {
        radio_->ForgetRoundOffsets();  // measured against the old count
        count_adoptions_.fetch_add(1, std::memory_order_relaxed);
      }
    }
    if (radio_ != nullptr) radio_->Broadcast(beacon);
    RoundReport report;
    report.round = static_cast<uint32_t>(round);
    report.activation_ns = os::PosixPort::MonotonicNowNs();
    const sync::SyncState& state = robot_->sync_state();
    report.status = static_cast<uint8_t>(state.status);
    report.phase = static_cast<uint8_t>(state.phase);
    report.epoch_mode = static_cast<uint8_t>(state.epoch_mode);
    report.epoch = state.epoch;
    const estimation::StateEstimate estimate = latest_estimate();
    report.estimate_valid = (estimate.status & estimation::kEstimateInitialized) != 0 ? 1 : 0;
    report.est_x_m = estimate.x_m;
    report.est_y_m = estimate.y_m;
    report.est_heading_rad = estimate.heading_rad;
    report.beacons_heard = radio_ != nullptr ? static_cast<uint32_t>(radio_->counters().received) : 0;
    if (radio_ != nullptr) report.heard_in_round = radio_->HeardInRound(static_cast<int64_t>(report.round) - 1);
    writer_.Write(ReportKind::kRound, report.activation_ns, EncodeRound(report));
  }
  // Times this robot took the swarm's round count (align only).
  uint64_t count_adoptions() const { return count_adoptions_.load(std::memory_order_relaxed); }

 private:
  ReportWriter& writer_;
  const os::PosixPort& port_;
  int64_t radio_round_ns_;
  bool align_;
  int64_t beacon_delay_ns_;
  std::atomic<int64_t> origin_ns_{-1};  // monotonic instant of round 0's boundary; -1 before the start
  std::atomic<uint64_t> count_adoptions_{0};
  mutable std::mutex estimate_mutex_;
  estimation::StateEstimate estimate_{};
  BeaconRadio* radio_ = nullptr;
  const runtime::Robot* robot_ = nullptr;
};

// The app's returned global states, for app-level agreement: the lab's
// RecordingApp feed, as reports.
class AppStateReporter final : public lab::sim::AppStateSink {
 public:
  explicit AppStateReporter(ReportWriter& writer) : writer_(writer) {}
  void OnAppState(uint16_t, bool new_round, const syrof_ldmap& ldmap, uint8_t state) override {
    AppStateReport report;
    report.new_round = new_round;
    report.epoch = ldmap.epoch;
    report.cooperative = ldmap.mode == SYROF_MODE_COOPERATIVE;
    report.map_fingerprint = lab::sim::MapFingerprint(ldmap);
    report.state = state;
    writer_.Write(ReportKind::kAppState, os::PosixPort::MonotonicNowNs(), EncodeAppState(report));
  }

 private:
  ReportWriter& writer_;
};

// A CLOCK_REALTIME instant on this host's CLOCK_MONOTONIC.
int64_t RealtimeToMonotonic(int64_t realtime_ns) {
  timespec realtime{};
  clock_gettime(CLOCK_REALTIME, &realtime);
  const int64_t monotonic_now = os::PosixPort::MonotonicNowNs();
  const int64_t realtime_now = static_cast<int64_t>(realtime.tv_sec) * 1'000'000'000 + realtime.tv_nsec;
  return realtime_ns - realtime_now + monotonic_now;
}

// Polled subscriptions name no task (a port ignores unknown ids).
constexpr os::TaskId kPolledTask = UINT16_MAX;

std::string fmt_double(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

struct Entities {
  dds_entity_t imu = 0, flow = 0, uwb = 0, control = 0;
  dds_entity_t drive = 0, report = 0, status = 0;
};

// The robot's readers and writers into `e`; false once one failed (said on
// `err`).
bool CreateEntities(const Participant& participant, uint16_t robot, Entities& e, std::ostream& err,
                    const std::string& who) {
  const std::pair<dds_entity_t*, EntityOrError> entities[] = {
      {&e.imu, CreateReader(participant, TopicKind::kImu, robot)},
      {&e.flow, CreateReader(participant, TopicKind::kFlow, robot)},
      {&e.uwb, CreateReader(participant, TopicKind::kUwb, robot)},
      {&e.control, CreateReader(participant, TopicKind::kControl)},
      {&e.drive, CreateWriter(participant, TopicKind::kDrive, robot)},
      {&e.report, CreateWriter(participant, TopicKind::kReport)},
      {&e.status, CreateWriter(participant, TopicKind::kStatus)},
  };
  for (const auto& [slot, entity] : entities) {
    if (!entity.ok()) {
      err << who << entity.error->ToString() << "\n";
      return false;
    }
    *slot = entity.entity;
  }
  return true;
}

BeaconRadioOptions RadioOptionsFor(const lab::scenario::Scenario& scenario, const RobotProcessOptions& options,
                                   const runtime::RobotConfig& config, const RoundTap& tap) {
  BeaconRadioOptions radio_options;
  radio_options.self = options.robot;
  radio_options.run_id = options.run_id;  // another run on this domain is not this swarm
  radio_options.swarm_size = static_cast<uint16_t>(scenario.robots.size());
  radio_options.channel = scenario.channel;
  // The lab's channel seed: the same loss in both runtimes.
  radio_options.seed = lab::sim::ChannelSeed(scenario.seed);
  radio_options.radio_round_ns = config.radio_round_ns;
  radio_options.current_round = [&tap] { return tap.CurrentRound(); };
  if (config.align_rounds) radio_options.expected_round = [&tap] { return tap.ExpectedRound(); };
  // The stress's late beacons: held by this receiver, per link (SampleDelayNs).
  if (options.stress.on() && options.stress.delayed_fraction > 0) {
    radio_options.hold_ns = [stress = options.stress, self = options.robot](uint16_t sender, uint32_t round) {
      return lab::sim::SampleDelayNs(stress, lab::sim::DelayedStream::kBeacon, sender, self, round);
    };
  }
  return radio_options;
}

// The process's main thread once its robot is set up: Status_ at once and
// once a second; it waits for the world's start on Control_, then drives
// the robot's hardware (sensor samples in, drive commands out) until the
// world says stop or is gone, the parent dies, or SIGINT/SIGTERM.
class WorldLink {
 public:
  WorldLink(const RobotProcessOptions& options, const Entities& e, int64_t radio_round_ns, os::PosixPort& port,
            lab::sensors::SensorPublishers& sensors, RoundTap& tap, const BeaconRadio& radio,
            pubsub::Subscriber<estimation::StateEstimate>& estimates, pubsub::Subscriber<motion::DriveCommand>& drive,
            std::ostream& err, const std::string& who)
      : options_(options), e_(e), radio_round_ns_(radio_round_ns), port_(port), sensors_(sensors), tap_(tap),
        radio_(radio), estimates_(estimates), drive_(drive), err_(err), who_(who) {}

  // Returns the process's exit code.
  int Run(const Participant& participant);

 private:
  void WriteStatus();
  void TakeControl();
  void TakeSensors(int64_t now);
  void OnImu(const syrof_msg_dds__Imu_& s, int64_t now);
  void OnFlow(const syrof_msg_dds__Flow_& s, int64_t now);
  void OnUwb(const syrof_msg_dds__Uwb_& s, int64_t now);
  // Holds a reading the stress makes late (SampleDelayNs) until its due
  // instant on the port's clock; false when it is not late.
  template <typename Sample>
  bool Hold(const Sample& s, lab::sim::DelayedStream stream, int64_t now);
  void PassEstimateAndDrive();
  bool WorldLost(int64_t now);

  const RobotProcessOptions& options_;
  const Entities& e_;
  const int64_t radio_round_ns_;
  os::PosixPort& port_;
  lab::sensors::SensorPublishers& sensors_;
  RoundTap& tap_;
  const BeaconRadio& radio_;
  pubsub::Subscriber<estimation::StateEstimate>& estimates_;
  pubsub::Subscriber<motion::DriveCommand>& drive_;
  std::ostream& err_;
  const std::string& who_;

  uint8_t state_ = 1;  // attached
  int64_t start_monotonic_ = -1;
  bool stop_ = false;
  bool world_seen_ = false;
  int64_t world_missing_since_ = -1;
  int exit_code_ = 0;
  // Readings the stress holds, by the port time they arrive (a late network delivery).
  std::multimap<int64_t, std::variant<syrof_msg_dds__Imu_, syrof_msg_dds__Flow_, syrof_msg_dds__Uwb_>> held_;
};

int WorldLink::Run(const Participant& participant) {
  WriteStatus();
  // Wait for the world, then drive the robot's hardware until it says stop.
  const dds_entity_t waitset = dds_create_waitset(participant.handle());
  for (const dds_entity_t reader : {e_.imu, e_.flow, e_.uwb, e_.control}) {
    (void)dds_set_status_mask(reader, DDS_DATA_AVAILABLE_STATUS);
    (void)dds_waitset_attach(waitset, reader, reader);
  }
  int64_t next_status_ns = port_.now_ns() + 1'000'000'000;
  while (!stop_) {
    (void)dds_waitset_wait(waitset, nullptr, 0, DDS_MSECS(4));
    if (g_stop_requested.load()) break;
    if (options_.parent_pid != 0 && getppid() != static_cast<pid_t>(options_.parent_pid)) break;
    TakeControl();
    const int64_t now = port_.now_ns();
    TakeSensors(now);
    PassEstimateAndDrive();
    if (WorldLost(now)) break;
    if (now >= next_status_ns) {
      next_status_ns += 1'000'000'000;
      WriteStatus();
    }
  }
  if (start_monotonic_ >= 0) (void)port_.Stop();
  state_ = 3;
  WriteStatus();
  (void)dds_delete(waitset);
  return exit_code_;
}

void WorldLink::WriteStatus() {
  syrof_msg_dds__Status_ status{};
  status.robot = options_.robot;
  status.run_id = options_.run_id;
  status.pid = static_cast<uint32_t>(getpid());
  status.state = state_;
  const BeaconRadioCounters c = radio_.counters();
  status.rounds = static_cast<uint32_t>(tap_.CurrentRound() < 0 ? 0 : tap_.CurrentRound());
  status.beacons_sent = static_cast<uint32_t>(c.sent);
  status.beacons_received = static_cast<uint32_t>(c.delivered);
  status.beacons_rejected = static_cast<uint32_t>(c.rejected);
  status.beacons_lost = static_cast<uint32_t>(c.lost);
  status.cpu_ns = static_cast<uint64_t>(CpuTimeNs());
  (void)dds_write(e_.status, &status);
}

void WorldLink::TakeControl() {
  TakeSamples<syrof_msg_dds__Control_>(e_.control, [&](const syrof_msg_dds__Control_& control, const dds_sample_info_t&) {
    if (control.run_id != options_.run_id) return;  // another run's world
    if (control.state == 2) stop_ = true;
    if (control.state == 1 && start_monotonic_ < 0 && control.radio_round_ns == radio_round_ns_ &&
        control.start_monotonic_ns > 0) {
      // On several hosts only CLOCK_REALTIME is shared (kept in sync by
      // the hosts): the start is read on it and converted to this host's
      // CLOCK_MONOTONIC.
      start_monotonic_ = options_.realtime_start ? RealtimeToMonotonic(control.start_realtime_ns)
                                                 : control.start_monotonic_ns;
      start_monotonic_ += options_.clock_offset_us * 1000;
      tap_.set_start(start_monotonic_);
      const int64_t origin = port_.MonotonicToPort(start_monotonic_);
      // A robot started after the run began (a joiner) has an origin
      // before its port's: the grid is still the world's.
      if (port_.StartAt(origin) != os::PortError::kOk) {
        err_ << who_ << "the port did not start\n";
        stop_ = true;
        exit_code_ = 1;
      }
      state_ = 2;
      WriteStatus();
    }
  });
}

// The sensor samples for this robot, once started, published on its broker
// stamped with the port's clock `now`; then the held ones now due, stamped
// with the instant they arrive, as a late network delivers them.
void WorldLink::TakeSensors(int64_t now) {
  TakeSamples<syrof_msg_dds__Imu_>(e_.imu, [&](const syrof_msg_dds__Imu_& s, const dds_sample_info_t&) {
    if (!Hold(s, lab::sim::DelayedStream::kImu, now)) OnImu(s, now);
  });
  TakeSamples<syrof_msg_dds__Flow_>(e_.flow, [&](const syrof_msg_dds__Flow_& s, const dds_sample_info_t&) {
    if (!Hold(s, lab::sim::DelayedStream::kFlow, now)) OnFlow(s, now);
  });
  TakeSamples<syrof_msg_dds__Uwb_>(e_.uwb, [&](const syrof_msg_dds__Uwb_& s, const dds_sample_info_t&) {
    if (!Hold(s, lab::sim::DelayedStream::kUwb, now)) OnUwb(s, now);
  });
  while (!held_.empty() && held_.begin()->first <= now) {
    std::visit(
        [&](const auto& s) {
          using Sample = std::decay_t<decltype(s)>;
          if constexpr (std::is_same_v<Sample, syrof_msg_dds__Imu_>) OnImu(s, now);
          if constexpr (std::is_same_v<Sample, syrof_msg_dds__Flow_>) OnFlow(s, now);
          if constexpr (std::is_same_v<Sample, syrof_msg_dds__Uwb_>) OnUwb(s, now);
        },
        held_.begin()->second);
    held_.erase(held_.begin());
  }
}

template <typename Sample>
bool WorldLink::Hold(const Sample& s, lab::sim::DelayedStream stream, int64_t now) {
  if (s.robot != options_.robot || s.run_id != options_.run_id || start_monotonic_ < 0) return false;
  const int64_t hold_ns = lab::sim::SampleDelayNs(options_.stress, stream, lab::sim::kFromWorld, options_.robot, s.world_time_ns);
  if (hold_ns <= 0) return false;
  held_.emplace(now + hold_ns, s);
  return true;
}

void WorldLink::OnImu(const syrof_msg_dds__Imu_& s, int64_t now) {
  if (s.robot != options_.robot || s.run_id != options_.run_id || start_monotonic_ < 0) return;
  estimation::ImuReading reading{};
  reading.timestamp_ns = now;
  std::memcpy(reading.accel_g, s.accel_g, sizeof reading.accel_g);
  std::memcpy(reading.gyro_dps, s.gyro_dps, sizeof reading.gyro_dps);
  sensors_.OnImu(reading);
}

void WorldLink::OnFlow(const syrof_msg_dds__Flow_& s, int64_t now) {
  if (s.robot != options_.robot || s.run_id != options_.run_id || start_monotonic_ < 0 || s.interval_ns == 0) return;
  sensors_.OnFlow(estimation::FlowReading{now, s.interval_ns, s.delta_x_px, s.delta_y_px});
}

void WorldLink::OnUwb(const syrof_msg_dds__Uwb_& s, int64_t now) {
  if (s.robot != options_.robot || s.run_id != options_.run_id || start_monotonic_ < 0) return;
  estimation::UwbReading reading{};
  reading.timestamp_ns = now;
  std::memcpy(reading.range_m, s.range_m, sizeof reading.range_m);
  reading.valid_mask = s.valid_mask & ((1u << estimation::kMaxAnchors) - 1);
  reading.sweep = s.sweep;
  sensors_.OnUwb(reading);
}

// The newest estimate to the round tap; the newest drive command to the
// world as Drive_.
void WorldLink::PassEstimateAndDrive() {
  estimation::StateEstimate estimate{};
  if (estimates_.TakeLatest(estimate)) tap_.set_estimate(estimate);
  motion::DriveCommand command{};
  if (drive_.TakeLatest(command)) {
    syrof_msg_dds__Drive_ sample{};
    sample.robot = options_.robot;
    sample.run_id = options_.run_id;
    sample.robot_time_ns = port_.PortToMonotonic(command.timestamp_ns);
    sample.kind = static_cast<uint8_t>(command.kind);
    sample.vx_mps = command.vx_mps;
    sample.vy_mps = command.vy_mps;
    sample.yaw_rate_radps = command.yaw_rate_radps;
    sample.left_mps = command.left_mps;
    sample.right_mps = command.right_mps;
    (void)dds_write(e_.drive, &sample);
  }
}

// The world's liveliness: its control writer matched, then gone for
// kWorldLostNs.
bool WorldLink::WorldLost(int64_t now) {
  dds_subscription_matched_status_t matched{};
  if (dds_get_subscription_matched_status(e_.control, &matched) == DDS_RETCODE_OK) {
    if (matched.current_count > 0) {
      world_seen_ = true;
      world_missing_since_ = -1;
    } else if (world_seen_) {
      if (world_missing_since_ < 0) world_missing_since_ = now;
      if (now - world_missing_since_ > kWorldLostNs) return true;
    }
  }
  return false;
}

}  // namespace

std::vector<std::string> RobotArguments(const RobotProcessOptions& o) {
  std::vector<std::string> a = {"--scenario", o.scenario_path, "--robot", std::to_string(o.robot), "--run-id",
                                std::to_string(o.run_id), "--domain", std::to_string(o.domain_id), "--interface",
                                o.interface, "--parent", std::to_string(o.parent_pid)};
  if (o.overrides.seed) a.insert(a.end(), {"--seed", std::to_string(*o.overrides.seed)});
  if (o.overrides.robots) a.insert(a.end(), {"--robots", std::to_string(*o.overrides.robots)});
  if (o.overrides.duration_s) a.insert(a.end(), {"--duration", fmt_double(*o.overrides.duration_s)});
  if (o.overrides.app) a.insert(a.end(), {"--app", *o.overrides.app});
  if (!o.log_directory.empty()) a.insert(a.end(), {"--log-dir", o.log_directory});
  if (o.realtime) a.insert(a.end(), {"--realtime", "1"});
  if (o.align_rounds) a.insert(a.end(), {"--align-rounds", "1"});
  if (o.realtime_start) a.insert(a.end(), {"--realtime-start", "1"});
  if (o.clock_offset_us != 0) a.insert(a.end(), {"--clock-offset-us", std::to_string(o.clock_offset_us)});
  if (o.stress.on() && o.stress.delayed_fraction > 0) {
    a.insert(a.end(), {"--late-seed", std::to_string(o.stress.seed), "--late-fraction",
                       fmt_double(o.stress.delayed_fraction), "--late-min-ms", std::to_string(o.stress.min_delay_ms),
                       "--late-max-ms", std::to_string(o.stress.max_delay_ms)});
  }
  return a;
}

ParsedRobotArguments ParseRobotArguments(const std::vector<std::string>& arguments) {
  ParsedRobotArguments parsed;
  RobotProcessOptions o;
  bool have_scenario = false, have_robot = false, have_run = false, have_domain = false;
  for (size_t i = 0; i < arguments.size(); i += 2) {
    const std::string& name = arguments[i];
    if (i + 1 >= arguments.size()) {
      parsed.error = lab::Error{.where = "", .message = "argument " + name + " has no value"};
      return parsed;
    }
    const std::string& value = arguments[i + 1];
    try {
      size_t used = 0;
      auto whole = [&](unsigned long long bound) {
        const unsigned long long number = std::stoull(value, &used, 10);
        if (used != value.size() || number > bound || value.front() == '-') throw std::out_of_range(name);
        return number;
      };
      if (name == "--scenario") {
        o.scenario_path = value;
        have_scenario = true;
      } else if (name == "--robot") {
        o.robot = static_cast<uint16_t>(whole(UINT16_MAX));
        have_robot = true;
      } else if (name == "--run-id") {
        o.run_id = whole(UINT64_MAX);
        have_run = true;
      } else if (name == "--domain") {
        o.domain_id = static_cast<uint32_t>(whole(kMaxDomainId));
        have_domain = true;
      } else if (name == "--interface") {
        o.interface = value;
      } else if (name == "--parent") {
        o.parent_pid = static_cast<int64_t>(whole(INT32_MAX));
      } else if (name == "--seed") {
        o.overrides.seed = whole(UINT64_MAX);
      } else if (name == "--robots") {
        o.overrides.robots = static_cast<int>(whole(INT32_MAX));
      } else if (name == "--duration") {
        o.overrides.duration_s = std::stod(value, &used);
        if (used != value.size() || !std::isfinite(*o.overrides.duration_s)) throw std::out_of_range(name);
      } else if (name == "--app") {
        o.overrides.app = value;
      } else if (name == "--log-dir") {
        o.log_directory = value;
      } else if (name == "--realtime") {
        o.realtime = whole(1) == 1;
      } else if (name == "--align-rounds") {
        o.align_rounds = whole(1) == 1;
      } else if (name == "--realtime-start") {
        o.realtime_start = whole(1) == 1;
      } else if (name == "--clock-offset-us") {
        o.clock_offset_us = std::stoll(value, &used, 10);
        if (used != value.size() || o.clock_offset_us < -kMaxClockOffsetUs || o.clock_offset_us > kMaxClockOffsetUs) {
          throw std::out_of_range(name);
        }
      } else if (name == "--late-seed") {
        o.stress.seed = whole(UINT64_MAX);
      } else if (name == "--late-fraction") {
        o.stress.delayed_fraction = std::stod(value, &used);
        if (used != value.size() || !(o.stress.delayed_fraction >= 0 && o.stress.delayed_fraction <= 1)) {
          throw std::out_of_range(name);
        }
      } else if (name == "--late-min-ms") {
        o.stress.min_delay_ms = static_cast<int64_t>(whole(10'000));
      } else if (name == "--late-max-ms") {
        o.stress.max_delay_ms = static_cast<int64_t>(whole(10'000));
      } else {
        parsed.error = lab::Error{.where = "", .message = "unknown argument " + name};
        return parsed;
      }
    } catch (const std::exception&) {
      parsed.error = lab::Error{.where = "argument " + name, .message = "\"" + value + "\" is not a valid value"};
      return parsed;
    }
  }
  if (!have_scenario || !have_robot || !have_run || !have_domain) {
    parsed.error = lab::Error{.where = "", .message = "--scenario, --robot, --run-id and --domain are required"};
    return parsed;
  }
  parsed.options = o;
  return parsed;
}

app_host::AppsResult RobotApps(const lab::scenario::Scenario& scenario, const RobotProcessOptions& options) {
  app_host::AppRequest request;
  request.log_directory = options.log_directory;
  return app_host::AppsFor(scenario, request);
}

int RunRobotProcess(const RobotProcessOptions& options, std::ostream& err) {
  // Die with the world, even if it is SIGKILLed; and if it already died
  // between fork and here, stop now.
  (void)prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (options.parent_pid != 0 && getppid() != static_cast<pid_t>(options.parent_pid)) return 1;
  struct sigaction action {};
  action.sa_handler = RequestStop;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  const std::string who = "syrof-robot " + std::to_string(options.robot) + ": ";

  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(options.scenario_path, options.overrides);
  if (!loaded.ok()) {
    err << who << loaded.error->ToString() << "\n";
    return 2;
  }
  const lab::scenario::Scenario& scenario = *loaded.scenario;
  if (options.robot >= scenario.robots.size()) {
    err << who << "robot " << options.robot << " is not in the scenario (" << scenario.robots.size() << " robots)\n";
    return 2;
  }
  const auto swarm_size = static_cast<uint16_t>(scenario.robots.size());
  const lab::scenario::RobotSpec& spec = scenario.robots[options.robot];

  const app_host::AppsResult apps = RobotApps(scenario, options);
  if (!apps.ok()) {
    err << who << apps.error->ToString() << "\n";
    return 2;
  }
  std::unique_ptr<app::App> app = apps.supply.factory(options.robot);
  if (app == nullptr) {
    err << who << "no app named " << scenario.app.name << "\n";
    return 2;
  }

  CycloneOptions cyclone;
  cyclone.interface = options.interface;
  const bool realtime = options.realtime && CanUseFifoScheduling();
  if (options.realtime && !realtime) {
    err << who << "--realtime: SCHED_FIFO refused (needs root or CAP_SYS_NICE); the tasks run at normal priority\n";
  }
  // Above every task of the robot (PosixPort: the minimum plus the task's
  // priority): a beacon taken off the network is what a round waits for.
  if (realtime) cyclone.network_fifo_priority = sched_get_priority_min(SCHED_FIFO) + registry::kSensorTaskPriority + 1;
  ParticipantOrError made = Participant::Create(options.domain_id, cyclone);
  if (!made.ok()) {
    err << who << made.error->ToString() << "\n";
    return 1;
  }
  const Participant& participant = *made.participant;
  Entities e;
  if (!CreateEntities(participant, options.robot, e, err, who)) return 1;

  runtime::RobotConfig config = lab::sim::RobotConfigFor(scenario, spec);
  // Every process reads one CLOCK_MONOTONIC on a host: the world's start
  // grid lines rounds up. Across hosts without synchronised clocks the
  // robots align from their beacons instead, which arrive a transport's
  // latency after the sender's boundary (docs/dds.md).
  config.align_rounds = options.align_rounds;
  if (options.align_rounds) config.beacon_delay_ns = kBeaconLatencyNs;
  lab::sim::QueriesWorkspace workspace;
  config.queries_workspace = workspace.handle();
  std::vector<app::Parameter> params;
  for (const auto& [name, value] : scenario.app.params) params.push_back(app::Parameter{name, value});
  config.app_params = params;
  const std::vector<app::Parameter> inputs = lab::sim::InputsOf(scenario, options.robot);
  config.app_inputs = inputs;
  const std::vector<motion::RobotKind> member_kinds = lab::sim::MemberKindsOf(scenario);
  config.member_kinds = member_kinds;

  os::PosixPortOptions port_options;
  port_options.realtime_priorities = options.realtime;
  os::PosixPort port(port_options);
  pubsub::StaticBroker<8, 12> broker(port);
  lab::sensors::SensorPublishers sensors;
  ReportWriter reports(e.report, options.run_id, options.robot);
  ReportObserver observer(reports, port);
  RoundTap tap(reports, port, config.radio_round_ns, config.align_rounds, config.beacon_delay_ns);
  AppStateReporter app_states(reports);
  lab::sim::RecordingApp recorded_app(std::move(app), options.robot, app_states, /*keep_history=*/false);
  std::vector<wire::Beacon> receive_storage(runtime::Robot::kReceiveBanks * static_cast<size_t>(swarm_size));
  runtime::Robot robot(config, recorded_app, tap, receive_storage);
  pubsub::Subscriber<motion::DriveCommand> drive;
  if (sensors.Advertise(broker) != pubsub::BrokerError::kOk) {
    err << who << "the sensor topics could not be advertised\n";
    return 1;
  }
  robot.set_observer(&observer);
  if (const runtime::RobotSetupError error = robot.Attach(port, broker); error != runtime::RobotSetupError::kOk) {
    err << who << "the robot could not be set up: " << runtime::ToString(error) << "\n";
    return 1;
  }
  pubsub::Subscriber<estimation::StateEstimate> estimates;
  if (drive.Subscribe(broker, motion::kDriveTopic, kPolledTask) != pubsub::BrokerError::kOk ||
      estimates.Subscribe(broker, estimation::kStateEstimateTopic, kPolledTask) != pubsub::BrokerError::kOk) {
    err << who << "the drive or estimate topic could not be subscribed\n";
    return 1;
  }
  BeaconRadioOrError radio = BeaconRadio::Create(participant, RadioOptionsFor(scenario, options, config, tap));
  if (!radio.ok()) {
    err << who << radio.error->ToString() << "\n";
    return 1;
  }
  if (const std::optional<Error> error = radio.radio->StartReceiving(robot)) {
    err << who << error->ToString() << "\n";
    return 1;
  }
  tap.Connect(radio.radio.get(), &robot);

  WorldLink link(options, e, config.radio_round_ns, port, sensors, tap, *radio.radio, estimates, drive, err, who);
  return link.Run(participant);
}

}  // namespace syrof::sim_dds
