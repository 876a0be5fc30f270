#include "syrof/runtime/robot.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "syrof/base/check.h"
#include "syrof/estimation/topics.h"
#include "syrof/registry/tasks.h"
#include "syrof/wire/beacon_codec.h"
#include "syrof/wire/fixed_point.h"

namespace syrof::runtime {

const char* ToString(RobotSetupError error) {
  switch (error) {
    case RobotSetupError::kOk: return "Ok";
    case RobotSetupError::kInvalidSyncConfig: return "InvalidSyncConfig";
    case RobotSetupError::kInvalidTiming: return "InvalidTiming";
    case RobotSetupError::kEstimatorFailed: return "EstimatorFailed";
    case RobotSetupError::kAddTaskFailed: return "AddTaskFailed";
    case RobotSetupError::kBrokerFailed: return "BrokerFailed";
    case RobotSetupError::kAlreadyAttached: return "AlreadyAttached";
  }
  return "?";
}

namespace {

// The app reads a motion::RobotKind as the ABI's syrof_robot_kind.
static_assert(static_cast<int>(motion::RobotKind::kOmni) == SYROF_KIND_OMNI &&
                  static_cast<int>(motion::RobotKind::kRover) == SYROF_KIND_ROVER &&
                  static_cast<int>(motion::RobotKind::kDrone) == SYROF_KIND_DRONE &&
                  motion::kRobotKindCount == 3,
              "the ABI's kinds are the motion layer's");

motion::SafetyConfig SafetyConfigFor(const RobotConfig& config) {
  motion::SafetyConfig safety = config.safety;
  safety.self_id = config.sync.self_id;
  return safety;
}

}  // namespace

syrof_app_info AppInfo(const RobotConfig& config) {
  syrof_app_info info{};
  info.abi_version = SYROF_APP_ABI_VERSION;
  info.self_id = config.sync.self_id;
  info.swarm_size = config.sync.swarm_size;
  info.radio_round_ms = static_cast<uint32_t>(config.radio_round_ns / 1'000'000);
  info.maneuver_ms = static_cast<uint32_t>(config.radio_round_ns * config.maneuver_rounds / 1'000'000);
  info.arena_width_m = config.arena_width_m;
  info.arena_height_m = config.arena_height_m;
  info.body_radius_m = config.motion.limits.body_radius_m;
  info.max_speed_mps = config.motion.limits.max_speed_mps;
  info.kind = static_cast<uint8_t>(config.kind);
  return info;
}

Robot::Robot(const RobotConfig& config, app::App& app, Radio& radio, std::span<wire::Beacon> receive_storage)
    : config_(config),
      app_(app),
      radio_(radio),
      receive_storage_(receive_storage),
      estimator_(config.estimator),
      controller_(config.motion),
      round_task_(*this),
      motion_task_(*this),
      bank_size_(std::min(receive_storage.size() / kReceiveBanks, size_t{wire::kMaxSwarmSize})),
      safety_filter_(SafetyConfigFor(config), config.motion, config.sync.swarm_size),
      relay_cursor_(config.sync.self_id) {}

RobotSetupError Robot::Attach(os::Port& port, pubsub::Broker& broker) {
  if (port_ != nullptr) return RobotSetupError::kAlreadyAttached;
  if (sync::Validate(config_.sync) != sync::ConfigError::kOk || !sync::IsValid(config_.activation)) {
    return RobotSetupError::kInvalidSyncConfig;
  }
  if (config_.radio_round_ns <= 0 || config_.maneuver_rounds < config_.sync.vote_rounds ||
      config_.maneuver_rounds > kMaxManeuverRounds) {
    return RobotSetupError::kInvalidTiming;
  }
  if (estimator_.Attach(port, broker) != estimation::EstimatorSetupError::kOk) {
    return RobotSetupError::kEstimatorFailed;
  }
  // Both tasks start at the port's start: the round task's first step ends
  // the first radio round.
  const auto round_id = port.AddTask(
      round_task_, {"runtime.round", os::Trigger::periodic(config_.radio_round_ns, config_.radio_round_ns),
                    registry::kRoundTaskPriority});
  const auto motion_id = port.AddTask(
      motion_task_, {"runtime.motion", os::Trigger::periodic(registry::kMotionPeriodNs), registry::kMotionTaskPriority});
  if (!round_id.ok() || !motion_id.ok()) return RobotSetupError::kAddTaskFailed;
  round_task_id_ = round_id.value();
  // One estimate subscription per task: the round and motion tasks may run
  // on different threads, so each keeps its own copy of the latest estimate.
  if (estimate_subscriber_.Subscribe(broker, estimation::kStateEstimateTopic, round_id.value()) !=
          pubsub::BrokerError::kOk ||
      motion_estimate_subscriber_.Subscribe(broker, estimation::kStateEstimateTopic, motion_id.value()) !=
          pubsub::BrokerError::kOk ||
      drive_publisher_.Advertise(broker, motion::kDriveTopic) != pubsub::BrokerError::kOk) {
    return RobotSetupError::kBrokerFailed;
  }
  port_ = &port;

  estimator_.SetInitialPose(config_.initial_pose);
  estimate_.x_m = config_.initial_pose.x_m;
  estimate_.y_m = config_.initial_pose.y_m;
  estimate_.heading_rad = config_.initial_pose.heading_rad;
  motion_estimate_ = estimate_;
  state_ = sync::InitialState(config_.sync, OwnSnapshot());
  command_ = syrof_car_command{};
  controller_.SetCommand(command_);  // the port has not started: no motion task yet
  // An app that fails here leaves a robot that is set up but stopped.
  BeginAppCall(port.now_ns(), state_.epoch);
  const app::CallStatus status = app_.Init(AppInfo(config_), *this, global_state_);
  if (!status.ok()) StopApp(app::Callback::kInit, port.now_ns(), state_.epoch, status);
  return RobotSetupError::kOk;
}

void Robot::Receive(const wire::Beacon& beacon) { Receive(beacon, kArrivalUnknown); }

void Robot::Receive(const wire::Beacon& beacon, int64_t arrival_ns) {
  if (inbox_count_ >= inbox_.size()) {
    ++counters_.beacons_overflow;
    return;
  }
  inbox_arrival_ns_[inbox_count_] = arrival_ns;
  inbox_[inbox_count_++] = &beacon;
  if (arrival_ns != kArrivalUnknown) inbox_timed_ = true;
  ++counters_.beacons_received;
}

void Robot::Receive(std::span<const wire::Beacon* const> beacons) {
  const size_t taken = std::min(beacons.size(), inbox_.size() - inbox_count_);
  std::copy_n(beacons.begin(), taken, inbox_.begin() + static_cast<std::ptrdiff_t>(inbox_count_));
  std::fill_n(inbox_arrival_ns_.begin() + static_cast<std::ptrdiff_t>(inbox_count_), taken, kArrivalUnknown);
  inbox_count_ += taken;
  counters_.beacons_received += static_cast<uint32_t>(taken);
  counters_.beacons_overflow += static_cast<uint32_t>(beacons.size() - taken);
}

void Robot::DropReceived() {
  counters_.beacons_dropped += static_cast<uint32_t>(inbox_count_ + deferred_count_);
  inbox_count_ = 0;
  deferred_count_ = 0;
  carried_count_ = 0;
  inbox_timed_ = false;
}

void Robot::ReceiveBytes(std::span<const uint8_t> frame) {
  // Decode outside the critical section: it is the long part, and it touches
  // only this call's local.
  const auto decoded = wire::Decode(frame, config_.sync.swarm_size);
  // port_ is set by Attach, before the port starts (and so before any
  // producer runs); before Attach there is no round task to race with.
  os::Port* const port = port_;
  if (port != nullptr) port->Lock();
  if (!decoded.ok()) {
    ++counters_.beacons_malformed;
  } else if (stored_count_ >= bank_size_) {
    ++counters_.beacons_overflow;
  } else {
    received_arrival_ns_[receiving_bank_ * bank_size_ + stored_count_] = port != nullptr ? port->now_ns() : 0;
    receive_storage_[receiving_bank_ * bank_size_ + stored_count_++] = decoded.value();
    ++counters_.beacons_received;
  }
  if (port != nullptr) port->Unlock();
}

void Robot::TakeReceivedBank() {
  if (bank_size_ == 0) return;
  size_t bank = 0;
  size_t count = 0;
  {
    os::CriticalSection lock(*port_);
    bank = receiving_bank_;
    count = stored_count_;
    // Round robin over three banks: the one taken two swaps ago may still
    // hold beacons deferred to this step, so it is not the next to receive.
    receiving_bank_ = static_cast<uint8_t>((receiving_bank_ + 1U) % kReceiveBanks);
    stored_count_ = 0;
    // Only when Receive() and ReceiveBytes() are mixed can the inbox be short
    // of room: the surplus becomes overflow, so each frame still counts once.
    const size_t room = inbox_.size() - inbox_count_;
    if (count > room) {
      counters_.beacons_received -= static_cast<uint32_t>(count - room);
      counters_.beacons_overflow += static_cast<uint32_t>(count - room);
      count = room;
    }
  }
  // The taken bank is the round task's until the next swap: no lock needed.
  const wire::Beacon* const first = receive_storage_.data() + bank * bank_size_;
  if (count > 0) inbox_timed_ = true;  // ReceiveBytes stamps every frame
  for (size_t i = 0; i < count; ++i) {
    inbox_arrival_ns_[inbox_count_] = received_arrival_ns_[bank * bank_size_ + i];
    inbox_[inbox_count_++] = first + i;
  }
}

syrof_app_status Robot::SendMessageData(std::span<const uint8_t> payload) {
  if (payload.size() > wire::kMaxPayloadBytes) {
    ++counters_.payloads_refused;
    if (observer_ != nullptr) observer_->OnPayloadRefused(id(), app_call_now_ns_, app_call_epoch_, payload.size());
    return SYROF_APP_PAYLOAD_TOO_LONG;
  }
  payload_.fill(0);
  std::copy(payload.begin(), payload.end(), payload_.begin());
  payload_length_ = static_cast<uint8_t>(payload.size());
  return SYROF_APP_OK;
}

uint32_t Robot::ClockMs(int64_t now_ns) const { return static_cast<uint32_t>((now_ns - start_ns_) / 1'000'000); }

void Robot::RefreshEstimate() {
  estimation::StateEstimate latest{};
  if (estimate_subscriber_.TakeLatest(latest)) estimate_ = latest;
}

wire::Snapshot Robot::OwnSnapshot() const {
  wire::Snapshot snapshot;
  snapshot.x_mm = wire::ToMillimetres(estimate_.x_m);
  snapshot.y_mm = wire::ToMillimetres(estimate_.y_m);
  snapshot.heading_mrad = wire::ToMilliradians(estimate_.heading_rad);
  snapshot.vx_mm_s = wire::ToMillimetresPerSecond(estimate_.vx_mps);
  snapshot.vy_mm_s = wire::ToMillimetresPerSecond(estimate_.vy_mps);
  snapshot.payload_length = payload_length_;
  snapshot.payload = payload_;
  return snapshot;
}

void Robot::FillAppMap(const sync::LDMap& ldmap) {
  size_t count = 0;
  for (const uint16_t id : ldmap.members) {
    const wire::Snapshot& snapshot = ldmap.snapshots[id];
    syrof_member_state& member = app_members_[count++];
    member.id = id;
    member.x_mm = snapshot.x_mm;
    member.y_mm = snapshot.y_mm;
    member.heading_mrad = snapshot.heading_mrad;
    member.vx_mm_s = snapshot.vx_mm_s;
    member.vy_mm_s = snapshot.vy_mm_s;
    member.phase = static_cast<uint8_t>(ldmap.phases[id]);
    member.payload_length = snapshot.payload_length;
    std::memcpy(member.payload, snapshot.payload.data(), sizeof member.payload);
    member.kind = id < config_.member_kinds.size() ? static_cast<uint8_t>(config_.member_kinds[id])
                                                   : static_cast<uint8_t>(SYROF_KIND_UNKNOWN);
  }
  app_map_.epoch = ldmap.epoch;
  app_map_.mode = static_cast<uint8_t>(ldmap.mode);
  app_map_.self_id = config_.sync.self_id;
  app_map_.member_count = static_cast<uint16_t>(count);
  app_map_.members = app_members_.data();
}

void Robot::BeginAppCall(int64_t now_ns, uint16_t epoch) {
  app_call_now_ns_ = now_ns;
  app_call_epoch_ = epoch;
}

void Robot::StopApp(app::Callback callback, int64_t now_ns, uint16_t epoch, const app::CallStatus& status) {
  app_fault_ = status;
  maneuver_active_ = false;
  command_ = syrof_car_command{};
  HandToMotion(command_);
  if (observer_ != nullptr) observer_->OnAppFault(id(), now_ns, callback, epoch, status);
}

void Robot::EndManeuver(int64_t now_ns) {
  maneuver_active_ = false;
  command_ = syrof_car_command{};
  HandToMotion(command_);
  BeginAppCall(now_ns, app_map_.epoch);
  const app::CallStatus status = app_.EndOfRound(app_map_, global_state_, ClockMs(now_ns));
  ++counters_.end_of_rounds;
  if (!status.ok()) StopApp(app::Callback::kEndOfRound, now_ns, app_map_.epoch, status);
}

// The look and the compute of an epoch: newRound on the epoch's map. False
// when the app faulted (the robot is stopped). A command the controller could
// not carry out is `check`ed, reported, and replaced by STOP: the robot holds
// still for the maneuver.
bool Robot::LookAndCompute(int64_t now_ns, syrof_car_command& command, app::CommandCheck& check) {
  FillAppMap(ldmap_);
  command = syrof_car_command{};
  BeginAppCall(now_ns, ldmap_.epoch);
  const app::CallStatus status = app_.NewRound(command, app_map_, global_state_, ClockMs(now_ns));
  ++counters_.new_rounds;
  if (!status.ok()) {
    StopApp(app::Callback::kNewRound, now_ns, ldmap_.epoch, status);
    return false;
  }
  check = app::CheckCommand(command);
  if (!check.ok()) {
    ++counters_.invalid_commands;
    command = syrof_car_command{};
  }
  return true;
}

// The epoch's start for the observer, and the command `check` refused.
void Robot::ReportEpochStart(int64_t now_ns, const app::CommandCheck& check) {
  if (observer_ == nullptr) return;
  observer_->OnEpochStart(id(), now_ns, ldmap_);
  if (!check.ok()) observer_->OnInvalidCommand(id(), now_ns, ldmap_.epoch, check);
}

// ASYNC (sync/activation.h): the robot looks when no cycle is under way;
// its move runs in the maneuvers the cycle's timing names, at the command's
// speed divided by their number, so it covers what one maneuver would.
void Robot::StartAsyncEpoch(int64_t now_ns) {
  const sync::AsyncTracker::Step step = async_tracker_.OnEpochStart(config_.activation, ldmap_.epoch, id());
  rounds_in_progress_ = 0;
  if (step.looks) {
    syrof_car_command command{};
    app::CommandCheck check;
    if (!LookAndCompute(now_ns, command, check)) return;
    const float spread = static_cast<float>(step.cycle.move_epochs);
    async_move_ = command;
    async_move_.speed_mps = command.speed_mps / spread;
    async_move_.vx_mps = command.vx_mps / spread;
    async_move_.vy_mps = command.vy_mps / spread;
    ReportEpochStart(now_ns, check);
  } else {
    ++counters_.inactive_epochs;
    ReportEpochStart(now_ns, app::CommandCheck{});
  }
  if (step.first_move_epoch) {
    async_covered_m_ = 0;
    async_cut_pending_ = step.cycle.cut;
    async_cut_done_ = false;
  }
  command_ = step.moves && !async_cut_done_ ? async_move_ : syrof_car_command{};
  HandToMotion(command_);
  // A move's maneuver ends with endOfRound only when it is the move's last.
  maneuver_active_ = step.moves;
  async_last_move_epoch_ = step.last_move_epoch;
}

// Non-rigid ASYNC: a move the scheduler cuts stops once it has covered
// min_move_mm: the path length of the robot's own velocity estimate, summed
// each radio round of the move (its position estimate's noise is of the
// order of a short move; the velocity's, integrated, is not).
void Robot::CutAsyncMove() {
  const float vx = estimate_.vx_mps;
  const float vy = estimate_.vy_mps;
  async_covered_m_ += std::sqrt(vx * vx + vy * vy) * (static_cast<float>(config_.radio_round_ns) * 1e-9f);
  if (async_covered_m_ * 1000.0f < static_cast<float>(config_.activation.min_move_mm)) return;
  async_cut_pending_ = false;
  async_cut_done_ = true;
  ++counters_.moves_cut;
  command_ = syrof_car_command{};
  HandToMotion(command_);
}

void Robot::RunRound(int64_t now_ns) {
  if (app_faulted()) {
    // Stopped as a crashed robot is: what arrived is dropped unread.
    TakeReceivedBank();
    inbox_count_ = 0;
    inbox_timed_ = false;
    return;
  }
  if (!started_) {
    started_ = true;
    start_ns_ = now_ns - config_.radio_round_ns;
    last_round_ns_ = start_ns_;
  }
  // Rounds since the previous step, to the nearest round: 1 unless the task
  // did not run (a pause), which the synchronizer must know of.
  // A boundary the alignment moved is a round, however long.
  const int64_t gap_rounds =
      (now_ns - last_round_ns_ - last_shift_ns_ + config_.radio_round_ns / 2) / config_.radio_round_ns;
  const int64_t round_start_ns = last_round_ns_;
  const int64_t unseen_shift_ns = last_shift_ns_;  // moved the boundary now passing, after this round's beacons left
  last_shift_ns_ = 0;
  last_round_ns_ = now_ns;
  ++counters_.rounds;
  RefreshEstimate();
  ReportInterventions();
  const bool in_progress = state_.status == sync::Status::kMember && state_.phase == wire::Phase::kProgress;
  if (in_progress) ++rounds_in_progress_;

  TakeReceivedBank();
  DeferLateArrivals(now_ns);
  // The samples are read before the safety reports compact the inbox; the
  // correction is applied after the step, when the robot's status is known.
  const bool aligned_gap = gap_rounds == 1;
  if (gap_rounds > 1 && config_.safety.enabled) {
    // Paused: nothing was heard since the last step (docs/safety.md).
    os::CriticalSection lock(*port_);
    shared_reports_.MarkListeningGap(round_start_ns, now_ns - config_.radio_round_ns);
    reports_changed_ = true;
  }
  TakeSafetyReports(now_ns);
  sync::StepInput input;
  input.own_snapshot = OwnSnapshot();
  input.maneuver_finished = in_progress && rounds_in_progress_ >= config_.maneuver_rounds;
  input.rounds_elapsed = gap_rounds < 1 ? 1u : gap_rounds > 0xFFFFFFFF ? 0xFFFFFFFFu : static_cast<uint32_t>(gap_rounds);
  sync::Step(config_.sync, state_, std::span<const wire::Beacon* const>(inbox_.data(), inbox_count_), input, out_,
             ldmap_);
  counters_.beacons_stepped += static_cast<uint32_t>(inbox_count_);
  if (aligned_gap) AlignRound(now_ns, round_start_ns, unseen_shift_ns);
  inbox_count_ = 0;
  for (size_t i = 0; i < deferred_count_; ++i) {
    inbox_[i] = deferred_[i];
    inbox_arrival_ns_[i] = deferred_arrival_ns_[i];
  }
  inbox_count_ = deferred_count_;
  carried_count_ = deferred_count_;
  inbox_timed_ = deferred_count_ > 0;  // only beacons with an arrival time are deferred
  deferred_count_ = 0;

  // The maneuver ends when PROGRESS ends, whatever ended it (its time is up,
  // or the robot lost its group).
  const bool still_in_progress =
      state_.status == sync::Status::kMember && state_.phase == wire::Phase::kProgress && !out_.epoch_started;
  if (maneuver_active_ && !still_in_progress) {
    if (config_.activation.model != sync::ActivationModel::kAsync || async_last_move_epoch_) {
      EndManeuver(now_ns);
    } else {
      // ASYNC: a maneuver of a move that goes on in a later epoch: hold
      // until then, no endOfRound yet.
      maneuver_active_ = false;
      HandToMotion(syrof_car_command{});
    }
  }
  if (app_faulted()) return;

  if (out_.epoch_started && config_.activation.model == sync::ActivationModel::kAsync) {
    StartAsyncEpoch(now_ns);
    if (app_faulted()) return;
  } else if (out_.epoch_started && !sync::IsActive(config_.activation, ldmap_.epoch, ldmap_.members, id())) {
    // Left out of this epoch (SSYNC): no look, no compute, no move. The
    // maneuver's rounds still count, for the synchronizer's PROGRESS.
    ++counters_.inactive_epochs;
    command_ = syrof_car_command{};
    HandToMotion(command_);
    rounds_in_progress_ = 0;
    if (observer_ != nullptr) observer_->OnEpochStart(id(), now_ns, ldmap_);
  } else if (out_.epoch_started) {
    syrof_car_command command{};
    app::CommandCheck check;
    if (!LookAndCompute(now_ns, command, check)) return;
    command_ = command;
    HandToMotion(command_);
    maneuver_active_ = true;
    rounds_in_progress_ = 0;
    ReportEpochStart(now_ns, check);
  }
  if (observer_ != nullptr) {
    if (!out_.removed.empty() || !out_.joined.empty()) observer_->OnMembership(id(), now_ns, out_.removed, out_.joined);
    if (out_.became_joiner) observer_->OnBecameJoiner(id(), now_ns);
  }
  if (async_cut_pending_ && maneuver_active_) CutAsyncMove();
  if (out_.send) {
    AttachRelay(now_ns, out_.beacon);
    radio_.Broadcast(out_.beacon);
    ++counters_.beacons_sent;
  } else {
    AnnouncePresence();
  }
}

// Every beacon heard this round reports where its sender was one radio round
// ago (it was built at the end of the sender's previous round); a WAIT or
// VOTE beacon carries the snapshot frozen when the sender's maneuver ended,
// so its sender may have braked from the frozen velocity since (the braking
// allowance). Presence-only beacons then leave the inbox: the synchronizer
// never sees them.
void Robot::TakeSafetyReports(int64_t now_ns) {
  const int64_t sent_ns = now_ns - config_.radio_round_ns;
  const float braking_mps2 = config_.safety.others_braking_mps2;
  const auto horizon_ns = static_cast<int64_t>(config_.safety.horizon_s * 1e9f);
  size_t presence = 0;
  if (config_.safety.enabled) {
    os::CriticalSection lock(*port_);
    for (size_t i = 0; i < inbox_count_; ++i) {
      const wire::Beacon& beacon = *inbox_[i];
      const wire::Snapshot& snapshot = beacon.snapshot;
      const bool parked = !beacon.presence_only && beacon.phase != wire::Phase::kProgress;
      presence += beacon.presence_only ? 1 : 0;
      shared_reports_.Report(beacon.robot_id, sent_ns, snapshot.x_mm, snapshot.y_mm, parked, snapshot.vx_mm_s,
                             snapshot.vy_mm_s, braking_mps2, config_.safety.others_lag_s);
      // A relayed position is at least a horizon old where it was sent
      // (AttachRelay): stamped so, its disc is the capped one.
      const wire::Relay& relay = beacon.relay;
      if (relay.relays() && relay.robot_id() != id() &&
          shared_reports_.Relayed(relay.robot_id(), sent_ns - horizon_ns, wire::FromRelayUnits(relay.x_16mm),
                                  wire::FromRelayUnits(relay.y_16mm), wire::kRelayRoundingMm)) {
        ++counters_.relays_taken;
      }
    }
    if (inbox_count_ > 0) reports_changed_ = true;
  } else {
    for (size_t i = 0; i < inbox_count_; ++i) presence += inbox_[i]->presence_only ? 1 : 0;
  }
  // Nearly always there is no presence-only beacon, and nothing to move.
  if (presence == 0) return;
  size_t kept = 0;
  for (size_t i = 0; i < inbox_count_; ++i) {
    const wire::Beacon* beacon = inbox_[i];
    inbox_[kept] = beacon;
    if (inbox_timed_) inbox_arrival_ns_[kept] = inbox_arrival_ns_[i];
    kept += beacon->presence_only ? 0 : 1;
  }
  counters_.presence_received += static_cast<uint32_t>(inbox_count_ - kept);
  inbox_count_ = kept;
}

// Where this step's beacons end: arrivals at or after it belong to the next
// step. Without alignment, the boundary itself (a beacon belongs to the round
// containing its arrival). With alignment, half a round before the arrival
// expected from a sender aligned with this boundary, so that a sender may be
// up to half a round early or late either way. Sending at the boundary (a
// DDS robot sends right after its step), the boundary alone would tolerate a
// sender early by less than the link's delay, a fraction of a millisecond;
// the lab's radio sends half a round after the boundary, where the two agree.
int64_t Robot::RoundSplitNs(int64_t boundary_ns) const {
  if (!config_.align_rounds) return boundary_ns;
  return boundary_ns + config_.beacon_delay_ns - config_.radio_round_ns / 2;
}

// A beacon belongs to the round that RoundSplitNs closes: one that arrived
// at or after this step's split waits in deferred_ for the next step. A
// beacon carried from the last step is stepped now, never deferred twice:
// its bank receives again after the next swap.
void Robot::DeferLateArrivals(int64_t now_ns) {
  if (!inbox_timed_) return;  // no arrival time: nothing is late
  const int64_t split_ns = RoundSplitNs(now_ns);
  size_t kept = 0;
  for (size_t i = 0; i < inbox_count_; ++i) {
    const int64_t arrival = inbox_arrival_ns_[i];
    if (i >= carried_count_ && arrival != kArrivalUnknown && arrival >= split_ns &&
        deferred_count_ < deferred_.size()) {
      deferred_[deferred_count_] = inbox_[i];
      deferred_arrival_ns_[deferred_count_++] = arrival;
      ++counters_.beacons_deferred;
      continue;
    }
    inbox_[kept] = inbox_[i];
    inbox_arrival_ns_[kept++] = arrival;
  }
  inbox_count_ = kept;
}

// Where this round's synchronizer beacons arrived says where their senders'
// boundaries are (round_alignment.h); the next boundary moves accordingly.
// Presence-only beacons were removed by TakeSafetyReports: a joiner is not
// followed. The inbox is still this round's (the step does not change it).
void Robot::AlignRound(int64_t now_ns, int64_t round_start_ns, int64_t unseen_shift_ns) {
  if (!inbox_timed_) {
    // No sample: Align would decide nothing and count nothing.
    last_alignment_ = sync::AlignmentStep{};
    return;
  }
  std::array<sync::AlignmentSample, sync::kMaxAlignmentSamples> samples{};
  size_t count = 0;
  const int64_t from_ns = RoundSplitNs(round_start_ns);
  const int64_t until_ns = RoundSplitNs(now_ns);
  for (size_t i = 0; i < inbox_count_ && count < samples.size(); ++i) {
    const int64_t arrival = inbox_arrival_ns_[i];
    if (arrival == kArrivalUnknown || arrival < from_ns || arrival >= until_ns) continue;
    samples[count++] = sync::AlignmentSample{inbox_[i]->robot_id, arrival - round_start_ns};
  }
  sync::AlignmentConfig alignment = sync::AlignmentConfig::ForRound(config_.radio_round_ns, id());
  alignment.expected_delay_ns = config_.beacon_delay_ns;
  alignment.enabled = config_.align_rounds;
  const bool member = state_.status == sync::Status::kMember;
  last_alignment_ = sync::Align(alignment, std::span<const sync::AlignmentSample>(samples.data(), count), member,
                                alignment_stats_, unseen_shift_ns);
  if (last_alignment_.correction_ns != 0 &&
      port_->ShiftPeriodic(round_task_id_, last_alignment_.correction_ns) == os::PortError::kOk) {
    ++counters_.alignment_shifts;
    last_shift_ns_ = last_alignment_.correction_ns;
  }
}

void Robot::ReportInterventions() {
  std::array<InterventionStart, 8> starts{};
  size_t count = 0;
  {
    os::CriticalSection lock(*port_);
    count = intervention_count_;
    std::copy(intervention_starts_.begin(), intervention_starts_.begin() + static_cast<std::ptrdiff_t>(count),
              starts.begin());
    intervention_count_ = 0;
  }
  if (observer_ == nullptr) return;
  for (size_t i = 0; i < count; ++i) {
    if (starts[i].precaution) {
      observer_->OnSafetyPrecaution(id(), starts[i].time_ns, starts[i].other);
    } else {
      observer_->OnSafetyIntervention(id(), starts[i].time_ns, starts[i].other);
    }
  }
}

// A member's beacon relays one robot it has not heard from for a horizon
// (crashed, paused, out of reach), taking the silent robots in turn: a
// robot switched on after another fell silent hears of its body this way
// (docs/safety.md, "A robot that was never told"). Each beacon looks at
// kRelayLookAhead robots past the last one relayed (every robot in a swarm
// of up to that many), so a round's step stays bounded in a large swarm. The
// round task is the reports' only writer, so it reads them without the lock.
void Robot::AttachRelay(int64_t now_ns, wire::Beacon& beacon) {
  beacon.relay = wire::Relay{};
  if (!config_.safety.enabled || beacon.presence_only) return;
  const auto horizon_ns = static_cast<int64_t>(config_.safety.horizon_s * 1e9f);
  const uint16_t silent = shared_reports_.NextSilent(relay_cursor_, id(), config_.sync.swarm_size,
                                                     now_ns - horizon_ns, kRelayLookAhead);
  if (silent == motion::SafetyReports::kNoSilentReport) return;
  const motion::SafetyReport& report = shared_reports_[silent];
  beacon.relay.slot = static_cast<uint16_t>(silent + 1);
  beacon.relay.x_16mm = wire::ToRelayUnits(report.x_mm);
  beacon.relay.y_16mm = wire::ToRelayUnits(report.y_mm);
  ++counters_.relays_sent;
}

// A joiner sends no synchronizer beacon; it says where it is instead.
void Robot::AnnouncePresence() {
  if (!config_.announce_presence || state_.status != sync::Status::kJoining) return;
  wire::Beacon beacon;
  beacon.robot_id = id();
  beacon.presence_only = true;
  const wire::Snapshot own = OwnSnapshot();
  beacon.snapshot.x_mm = own.x_mm;
  beacon.snapshot.y_mm = own.y_mm;
  beacon.snapshot.heading_mrad = own.heading_mrad;
  beacon.snapshot.vx_mm_s = own.vx_mm_s;
  beacon.snapshot.vy_mm_s = own.vy_mm_s;
  radio_.Broadcast(beacon);
  ++counters_.presence_sent;
}

// The round task and the motion task may run on different threads (the
// POSIX port) or preempt each other (the firmware): the controller belongs to
// the motion task, and the round task hands it the command through a slot
// under the port's critical section. Only the last command handed before a
// motion step counts (a STOP then a new command in one round is the new one).
void Robot::HandToMotion(const syrof_car_command& command) {
  os::CriticalSection lock(*port_);
  handed_command_ = command;
  command_handed_ = true;
}

void Robot::RunMotion(int64_t now_ns) {
  // The app's clock (start_ns_) is the round task's alone: it starts one
  // radio round before the round task's first step, when the port started.
  syrof_car_command command{};
  bool handed = false;
  {
    os::CriticalSection lock(*port_);
    if (command_handed_) {
      command = handed_command_;
      command_handed_ = false;
      handed = true;
    }
  }
  if (handed) controller_.SetCommand(command);
  estimation::StateEstimate latest{};
  if (motion_estimate_subscriber_.TakeLatest(latest)) motion_estimate_ = latest;
  const motion::DriveCommand desired = controller_.Update(motion_estimate_, now_ns);
  // A robot that stands still (or turns in place) needs no reports: most of
  // a swarm, most of the time.
  if (!safety_filter_.NeedsReports(desired)) {
    (void)drive_publisher_.Publish(desired);
    return;
  }
  {
    os::CriticalSection lock(*port_);
    if (reports_changed_) {
      motion_reports_.CopyFrom(shared_reports_, config_.sync.swarm_size);
      reports_changed_ = false;
    }
  }
  motion::SafetyOutcome outcome;
  const motion::DriveCommand drive = safety_filter_.Apply(desired, motion_estimate_, motion_reports_, now_ns, outcome);
  if (outcome.started || outcome.precaution_started) {
    os::CriticalSection lock(*port_);
    ++(outcome.started ? counters_.safety_interventions : counters_.safety_precautions);
    if (intervention_count_ < intervention_starts_.size()) {
      intervention_starts_[intervention_count_++] = InterventionStart{now_ns, outcome.other, !outcome.started};
    } else {
      ++counters_.safety_reports_dropped;
    }
  }
  (void)drive_publisher_.Publish(drive);
}

}  // namespace syrof::runtime
