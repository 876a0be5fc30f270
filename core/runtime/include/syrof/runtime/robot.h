// One robot's software: the task graph that runs unchanged in the simulated
// lab, in a robot process, and on the Teensy:
//
//   sensor drivers -> state task -> Kalman task -> StateEstimate
//   radio -> Receive() / ReceiveBytes() ... round task: synchronizer Step(),
//                          app callbacks, Radio::Broadcast() (radio.h)
//   StateEstimate + the app's command -> motion task: controller, then the
//                          safety filter (docs/safety.md) -> DriveCommand
//
// The round task runs once per radio round. It hands the synchronizer the
// beacons received since its last step and the robot's own snapshot (the
// latest estimate in the beacon's fixed-point units plus the app's payload),
// and reports "maneuver finished" once PROGRESS has lasted the configured
// number of rounds. When an epoch starts it builds the app's LDMap and calls
// newRound; the command goes to the motion controller. When the maneuver
// ends the robot stops and endOfRound is called. Under SSYNC
// (RobotConfig::activation) an epoch the schedule leaves the robot out of
// gets neither call: the robot holds still through it.
//
// Receiving: beacons heard during a round are stepped at the round's end.
// ReceiveBytes() may run on another thread or in an interrupt while the
// round task runs (a DDS listener, a UART interrupt): it decodes outside the
// port's critical section and holds it only to copy the beacon into a slot.
// The receive storage is three banks used in turn: one fills while the round
// task steps the one it last took, and the one before keeps the beacons that
// arrived at that round's boundary (deferred, stepped one round later). The
// round task moves to the next bank under the same critical section, so a
// frame that arrives during a step counts for the next round.
//
// Safety: every beacon heard (member or presence-only) updates the safety
// filter's report of its sender; the motion task limits every drive command
// against those reports, in every mode. A robot that is joining, and so
// sends no synchronizer beacon, broadcasts a presence-only beacon each round
// (wire::Beacon::presence_only) so the others' filters see it; presence-only
// beacons are removed from the round's beacons before the synchronizer's
// step, which therefore sees exactly what it would without them.
//
// The app is untrusted: a command app::CheckCommand refuses becomes STOP, and
// a refused payload changes nothing; both are counted and reported. A call
// that faults stops the robot for good, as a crash would (no more app calls,
// steps or beacons; drive STOP). RobotObserver hears all three.
//
// The sensor drivers publish on the estimation topics before Attach(); the
// actuator driver subscribes to motion::kDriveTopic after it. Nothing is
// allocated after construction.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string_view>

#include "syrof/base/state_digest.h"
#include "syrof/app/app.h"
#include "syrof/app/call_status.h"
#include "syrof/app/command_check.h"
#include "syrof/estimation/estimator.h"
#include "syrof/motion/controller.h"
#include "syrof/motion/drive.h"
#include "syrof/motion/robot_kind.h"
#include "syrof/motion/safety_filter.h"
#include "syrof/os/port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/registry/tasks.h"
#include "syrof/runtime/radio.h"
#include "syrof/runtime/robot_observer.h"
#include "syrof/sync/activation.h"
#include "syrof/sync/config.h"
#include "syrof/sync/ldmap.h"
#include "syrof/sync/round_alignment.h"
#include "syrof/sync/synchronizer.h"
#include "syrof/wire/beacon.h"

namespace syrof::runtime {

/// Longest PROGRESS, in radio rounds: with F <= sync::kMaxSilenceRounds it
/// keeps every legitimate stay in one epoch well below sync::kMaxStayRounds
/// (docs/protocol.md, "Epoch numbers").
inline constexpr uint16_t kMaxManeuverRounds = 4096;

/// Everything one robot needs to know at start-up.
struct RobotConfig {
  sync::SyncConfig sync;                       ///< swarm size, self id, K, F, quorum, initial members
  int64_t radio_round_ns = registry::kDefaultRadioRoundNs;  ///< alpha
  uint16_t maneuver_rounds = 20;               ///< radio rounds PROGRESS lasts (K .. kMaxManeuverRounds)
  estimation::EstimatorConfig<float> estimator{};
  estimation::InitialPose<float> initial_pose{};  ///< where the robot starts (known placement)
  motion::ControllerConfig motion{};
  /// This robot's kind and every robot's by id (the scenario's `kind:`,
  /// common to the swarm like its size): what the app reads as
  /// syrof_app_info::kind and each member's kind in the map. Set by
  /// runtime::ConfigureKinds (kind) and the runtime (member_kinds, kept
  /// alive as app_params); a member whose id is past the table's end reads
  /// SYROF_KIND_UNKNOWN.
  motion::RobotKind kind = motion::RobotKind::kOmni;
  std::span<const motion::RobotKind> member_kinds;
  /// The safety filter (its self_id is taken from sync.self_id). Disabled:
  /// drive commands pass unchanged and no presence-only beacon is sent.
  motion::SafetyConfig safety{};
  /// Send presence-only beacons while joining (normally: safety.enabled;
  /// tests switch it alone).
  bool announce_presence = true;
  float arena_width_m = 4;
  float arena_height_m = 4;
  syrof_queries_workspace* queries_workspace = nullptr;  ///< shared scratch for the app's queries
  /// Round alignment (sync/round_alignment.h, docs/clocks.md): move the
  /// round task's boundary onto the group's, from where beacons arrive.
  /// Needs arrival times (Receive with a time, or ReceiveBytes) and a port
  /// that can ShiftPeriodic. Off: the errors are still measured.
  bool align_rounds = false;
  /// From a sender's round boundary to its beacon's arrival on an aligned
  /// link (the radio's latency). With align_rounds, a beacon is stepped at
  /// the end of the round in which it arrived no later than half a round
  /// after this delay (earlier ones wait for the next round), so senders up
  /// to half a round early or late either way land in the right round.
  int64_t beacon_delay_ns = 0;
  /// What syrofAppParameter answers (the scenario's app params); the table
  /// and its names must outlive the robot. Empty: no parameters.
  std::span<const app::Parameter> app_params;
  /// What syrofAppInput answers: this robot's private inputs (the
  /// scenario's `inputs`, its own value of each); kept alive as app_params.
  std::span<const app::Parameter> app_inputs;
  /// Which members move in each epoch (sync/activation.h,
  /// docs/activation.md); the same on every robot of the swarm. FSYNC (the
  /// default): all. An epoch this robot is inactive in: no newRound and no
  /// endOfRound, the drive command STOP, the global state and payload kept;
  /// the synchronizer steps and beacons as ever.
  sync::ActivationConfig activation{};
};

/// Why a robot could not be set up.
enum class [[nodiscard]] RobotSetupError : uint8_t {
  kOk = 0,
  kInvalidSyncConfig,   ///< sync::Validate refused the config, or sync::IsValid the activation
  kInvalidTiming,       ///< radio_round_ns <= 0, or maneuver_rounds < K or above kMaxManeuverRounds
  kEstimatorFailed,     ///< the estimator could not attach (sensor topics missing?)
  kAddTaskFailed,       ///< the port refused a task
  kBrokerFailed,        ///< a topic could not be advertised or subscribed
  kAlreadyAttached,
};

/// The enumerator's name without the k.
const char* ToString(RobotSetupError error);

/// Counters for diagnostics and tests.
struct RobotCounters {
  uint32_t rounds = 0;
  uint32_t beacons_sent = 0;
  uint32_t beacons_received = 0;   ///< accepted into the inbox
  uint32_t beacons_malformed = 0;  ///< bytes that did not decode
  uint32_t beacons_overflow = 0;   ///< more than a round's storage (or inbox) holds
  uint32_t beacons_stepped = 0;    ///< handed to the synchronizer's steps
  uint32_t new_rounds = 0;         ///< newRound calls
  uint32_t inactive_epochs = 0;    ///< epochs started that the activation schedule left this robot out of (SSYNC), or that it did not look in (ASYNC)
  uint32_t moves_cut = 0;          ///< ASYNC non-rigid: moves stopped once they covered min_move_mm
  uint32_t end_of_rounds = 0;      ///< endOfRound calls
  uint32_t payloads_refused = 0;   ///< sendMessageData calls over the limit
  uint32_t invalid_commands = 0;   ///< newRound commands CheckCommand refused (replaced by STOP)
  uint32_t presence_sent = 0;      ///< presence-only beacons broadcast while joining
  uint32_t presence_received = 0;  ///< presence-only beacons heard (kept from the synchronizer)
  uint32_t relays_sent = 0;        ///< beacons that relayed a silent robot's position (wire::Relay)
  uint32_t relays_taken = 0;       ///< relayed positions recorded: of robots this one held no report of
  uint32_t safety_interventions = 0;  ///< intervention starts: the filter began to limit commands that broke the charged rule
  uint32_t safety_precautions = 0;    ///< precaution starts: it began to limit commands only for its wider cover (motion::SafetyOutcome)
  uint32_t safety_reports_dropped = 0;  ///< intervention and precaution starts not reported (more than a round holds)
  uint32_t beacons_deferred = 0;   ///< arrived at or after a round's boundary: stepped the round after
  uint32_t beacons_dropped = 0;    ///< forgotten unstepped (DropReceived)
  uint32_t alignment_shifts = 0;   ///< rounds whose boundary alignment moved
};

class Robot final : private app::Platform {
 public:
  static constexpr size_t kReceiveBanks = 3;

  /// `app` and `radio` must outlive the robot. `receive_storage` holds beacons
  /// that arrive as bytes (ReceiveBytes), in kReceiveBanks banks of
  /// size() / kReceiveBanks slots: one receives while the round task steps
  /// another, and the third keeps the beacons deferred to the next step. Give
  /// it kReceiveBanks times the frames one round may accept (kReceiveBanks x
  /// swarm size; at most kReceiveBanks x wire::kMaxSwarmSize are used). It may
  /// be empty when beacons only arrive decoded (Receive). Not owned; it must
  /// outlive the robot.
  Robot(const RobotConfig& config, app::App& app, Radio& radio, std::span<wire::Beacon> receive_storage = {});
  Robot(const Robot&) = delete;
  Robot& operator=(const Robot&) = delete;

  /// Adds the robot's tasks to `port` and its topics to `broker` (the sensor
  /// topics must already have publishers), sets the estimator's initial pose
  /// and calls the app's init. Once, before the port starts.
  RobotSetupError Attach(os::Port& port, pubsub::Broker& broker);

  /// A beacon heard this round, by address: it must stay valid until the
  /// round task's next step. The lab's decode-once fast path (one decoded
  /// beacon serves every receiver): no lock, so call it only from the thread
  /// that runs the round task, between its steps (the lab's delivery task on
  /// the same SimPort scheduler), never concurrently with ReceiveBytes.
  /// Surplus beacons (more than wire::kMaxSwarmSize in a round) are counted
  /// as overflow and dropped.
  void Receive(const wire::Beacon& beacon);

  /// The same, for a beacon that arrived at `arrival_ns` on this robot's
  /// clock (port time): it is stepped in the round that contains its
  /// arrival, [previous boundary, boundary), so one arriving at or after the
  /// boundary being stepped waits for the next (the lab with real clocks,
  /// docs/clocks.md). It also tells the round alignment where the sender's
  /// boundary is. The beacon must stay valid until the step that takes it.
  void Receive(const wire::Beacon& beacon, int64_t arrival_ns);

  /// Receive(*beacons[i]) for each, in order, in one call (the lab hands a
  /// robot its round's beacons at once).
  void Receive(std::span<const wire::Beacon* const> beacons);

  /// Forgets the beacons received and not yet stepped: a robot switched off
  /// loses its radio's buffer. Counted in beacons_dropped. Only between
  /// steps, from the round task's thread.
  void DropReceived();

  /// A frame heard: decoded outside any lock, then copied into the receiving
  /// bank of receive storage under the port's critical section, for the
  /// round task's next step. Safe from any thread, or from an interrupt on a
  /// port whose critical section masks interrupts (the firmware's), while
  /// the round task runs (after Attach; before Attach only from the thread
  /// that will start the port). Not from a POSIX signal handler: the POSIX
  /// port's critical section is a mutex. Each call counts exactly one of beacons_received,
  /// beacons_overflow (the bank is full) or beacons_malformed (the bytes did
  /// not decode). Bounded: one decode, one beacon copy in the lock.
  void ReceiveBytes(std::span<const uint8_t> frame);

  /// Sets the watcher (or none). Not owned.
  void set_observer(RobotObserver* observer) { observer_ = observer; }

  uint16_t id() const { return config_.sync.self_id; }
  const sync::SyncState& sync_state() const { return state_; }
  /// The newest estimate the round or motion task has taken. Like
  /// counters(): read it from the port's thread (SimPort) or once the port
  /// has stopped.
  const estimation::StateEstimate& estimate() const {
    return motion_estimate_.timestamp_ns > estimate_.timestamp_ns ? motion_estimate_ : estimate_;
  }
  bool estimate_valid() const { return (estimate().status & estimation::kEstimateInitialized) != 0; }
  uint8_t global_state() const { return global_state_; }
  /// Whether the app faulted (the robot is then stopped; see OnAppFault).
  bool app_faulted() const { return !app_fault_.ok(); }
  const syrof_car_command& command() const { return command_; }
  /// Read them from the round task's thread, or once the port has stopped:
  /// ReceiveBytes' producer updates the receive counters under the port's
  /// critical section.
  const RobotCounters& counters() const { return counters_; }
  const estimation::Estimator<float>& estimator() const { return estimator_; }
  const sync::LDMap& ldmap() const { return ldmap_; }
  const RobotConfig& config() const { return config_; }
  /// Round alignment's figures (measured even when alignment is off).
  const sync::AlignmentStats& alignment_stats() const { return alignment_stats_; }
  /// When the round task last stepped (a round boundary), port time.
  int64_t last_round_ns() const { return last_round_ns_; }

  /// Everything the robot's future steps read into `digest`
  /// (base/state_digest.h): the synchronizer, the map, the estimator, the
  /// beacons waiting in the inbox and the receive bank, the app's commands
  /// and payload, the safety reports. The counters and statistics stay out,
  /// and so do the ports, queues and app it reaches through pointers (their
  /// owners add them). From the port's thread between steps (SimPort).
  void AddToDigest(base::StateDigest& digest) const;

 private:
  class RoundTask final : public os::Task {
   public:
    explicit RoundTask(Robot& robot) : robot_(robot) {}
    void Step(int64_t now_ns) override { robot_.RunRound(now_ns); }

   private:
    Robot& robot_;
  };
  class MotionTask final : public os::Task {
   public:
    explicit MotionTask(Robot& robot) : robot_(robot) {}
    void Step(int64_t now_ns) override { robot_.RunMotion(now_ns); }

   private:
    Robot& robot_;
  };

  // app::Platform
  syrof_app_status SendMessageData(std::span<const uint8_t> payload) override;
  syrof_queries_workspace* queries_workspace() override { return config_.queries_workspace; }
  syrof_app_status AppParameter(std::string_view name, double& value) override {
    return app::FindParameter(config_.app_params, name, value);
  }
  syrof_app_status AppInput(std::string_view name, double& value) override {
    return app::FindParameter(config_.app_inputs, name, value, SYROF_APP_NO_SUCH_INPUT);
  }

  void RunRound(int64_t now_ns);
  void RunMotion(int64_t now_ns);
  void RefreshEstimate();
  wire::Snapshot OwnSnapshot() const;
  void FillAppMap(const sync::LDMap& ldmap);
  void EndManeuver(int64_t now_ns);
  bool LookAndCompute(int64_t now_ns, syrof_car_command& command, app::CommandCheck& check);
  void ReportEpochStart(int64_t now_ns, const app::CommandCheck& check);
  void StartAsyncEpoch(int64_t now_ns);
  void CutAsyncMove();
  void BeginAppCall(int64_t now_ns, uint16_t epoch);
  void StopApp(app::Callback callback, int64_t now_ns, uint16_t epoch, const app::CallStatus& status);
  uint32_t ClockMs(int64_t now_ns) const;

  RobotConfig config_;
  app::App& app_;
  Radio& radio_;
  std::span<wire::Beacon> receive_storage_;
  RobotObserver* observer_ = nullptr;

  estimation::Estimator<float> estimator_;
  motion::MotionController controller_;
  RoundTask round_task_;
  MotionTask motion_task_;
  os::Port* port_ = nullptr;
  pubsub::Subscriber<estimation::StateEstimate> estimate_subscriber_;
  pubsub::Publisher<motion::DriveCommand> drive_publisher_;
  estimation::StateEstimate estimate_{};  // the round task's
  pubsub::Subscriber<estimation::StateEstimate> motion_estimate_subscriber_;
  estimation::StateEstimate motion_estimate_{};  // the motion task's

  sync::SyncState state_;
  sync::StepOutput out_;
  sync::LDMap ldmap_;  // the current epoch's map
  void TakeReceivedBank();
  void HandToMotion(const syrof_car_command& command);
  // Safety: the round's beacons into the reports, presence-only ones out of
  // the inbox; the motion task's intervention starts out to the observer.
  void TakeSafetyReports(int64_t now_ns);
  void ReportInterventions();
  void AnnouncePresence();
  void AttachRelay(int64_t now_ns, wire::Beacon& beacon);

  // The round's inbox: read by the step, filled by Receive() and, at the
  // step's start, by TakeReceivedBank(). Only the round task's thread.
  // Each entry's arrival time (port clock; kArrivalUnknown when not given).
  // Room for two rounds: beacons deferred to the next round stay here.
  // These five arrays are written before they are read (an entry is read
  // only below its count), so they are left uninitialized: zeroing them
  // (88 KB a robot on the host, sized for the largest swarm) was most of
  // building a robot, and touched memory a small swarm never uses.
  static constexpr int64_t kArrivalUnknown = INT64_MIN;
  std::array<const wire::Beacon*, 2 * wire::kMaxSwarmSize> inbox_;
  std::array<int64_t, 2 * wire::kMaxSwarmSize> inbox_arrival_ns_;
  size_t inbox_count_ = 0;
  std::array<const wire::Beacon*, 2 * wire::kMaxSwarmSize> deferred_;
  std::array<int64_t, 2 * wire::kMaxSwarmSize> deferred_arrival_ns_;
  size_t deferred_count_ = 0;
  size_t carried_count_ = 0;  // the inbox's first entries: deferred by the last step
  // Whether some inbox entry may have a known arrival time. While false
  // (the lab's shared clock: every beacon comes through Receive() without
  // one) no beacon can be deferred and alignment has no sample, so the
  // round skips both and the arrival times are not moved around.
  bool inbox_timed_ = false;
  std::array<int64_t, kReceiveBanks * wire::kMaxSwarmSize> received_arrival_ns_;  // parallel to receive_storage_
  int64_t RoundSplitNs(int64_t boundary_ns) const;
  void DeferLateArrivals(int64_t now_ns);
  void AlignRound(int64_t now_ns, int64_t round_start_ns, int64_t unseen_shift_ns);
  os::TaskId round_task_id_ = 0;
  int64_t last_shift_ns_ = 0;  // the last round's alignment correction
  sync::AlignmentStats alignment_stats_;
  sync::AlignmentStep last_alignment_;
  // receive_storage_ in kReceiveBanks banks of bank_size_ slots. Under the
  // port's critical section: receiving_bank_ and stored_count_ (what
  // ReceiveBytes fills) and the receive counters. The other two banks belong
  // to the round task: the one its last swap took, and the one before, whose
  // deferred beacons (carried_count_) it steps in between.
  size_t bank_size_ = 0;
  uint8_t receiving_bank_ = 0;
  size_t stored_count_ = 0;

  std::array<syrof_member_state, wire::kMaxSwarmSize> app_members_{};
  syrof_ldmap app_map_{};
  syrof_car_command command_{};
  // The round task's latest command for the motion task, under the port's
  // critical section (the controller is the motion task's alone).
  syrof_car_command handed_command_{};
  bool command_handed_ = false;

  // Safety. The round task writes shared_reports_ under the port's critical
  // section and sets reports_changed_; the motion task copies them into
  // motion_reports_ under it, then filters from its copy without the lock.
  motion::SafetyFilter safety_filter_;
  motion::SafetyReports shared_reports_;
  motion::SafetyReports motion_reports_;
  bool reports_changed_ = false;
  // Where the search for the next silent robot to relay goes on from (the
  // last one relayed, or the last one looked at). Starting at the robot's
  // own id spreads the swarm's relays over the silent robots.
  uint16_t relay_cursor_ = 0;
  // Robots a beacon looks at for one to relay (AttachRelay).
  static constexpr size_t kRelayLookAhead = 16;
  // Intervention starts from the motion task to the round task (which tells
  // the observer), under the port's critical section. A round has at most
  // radio_round / motion period motion steps, so 8 is plenty; more are
  // counted in safety_reports_dropped.
  struct InterventionStart {
    int64_t time_ns;
    uint16_t other;
    bool precaution;  // a precaution's start, not an intervention's
  };
  std::array<InterventionStart, 8> intervention_starts_{};
  size_t intervention_count_ = 0;
  uint8_t global_state_ = 0;
  uint8_t payload_length_ = 0;
  std::array<uint8_t, wire::kMaxPayloadBytes> payload_{};
  bool maneuver_active_ = false;
  uint16_t rounds_in_progress_ = 0;
  // ASYNC (sync/activation.h): the cycle under way, the move's command
  // (spread over its epochs), how far the move came and whether it was cut.
  sync::AsyncTracker async_tracker_{};
  syrof_car_command async_move_{};
  bool async_last_move_epoch_ = false;
  bool async_cut_pending_ = false;
  bool async_cut_done_ = false;
  float async_covered_m_ = 0;
  app::CallStatus app_fault_;  // ok until the app faults
  int64_t app_call_now_ns_ = 0;  // the current (or last) app call, for reports
  uint16_t app_call_epoch_ = 0;
  int64_t start_ns_ = 0;
  bool started_ = false;
  int64_t last_round_ns_ = 0;  // when the round task last stepped; a longer gap is a pause
  RobotCounters counters_;
};

/// A syrof_app_info for `config` (what init receives).
syrof_app_info AppInfo(const RobotConfig& config);

}  // namespace syrof::runtime
