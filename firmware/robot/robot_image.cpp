#include "robot_image.h"

#include <cstdio>
#include <memory>
#include <new>

#include "syrof/estimation/topics.h"
#include "syrof/firmware/robot/report_lines.h"
#include "syrof/queries/queries.h"
#include "syrof/registry/tasks.h"
#include "syrof/firmware/robot/boot_words.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::firmware::robot {

static_assert(drivers::kMaxLinkBeaconBytes == wire::kMaxRadioBeaconBytes, "the link carries one radio beacon");

void LinkRadio::Broadcast(const wire::Beacon& beacon) {
  uint8_t beacon_bytes[wire::kMaxBeaconBytes];
  const auto size = wire::Encode(beacon, swarm_size_, beacon_bytes);
  if (!size.ok() || size.value() > drivers::kMaxLinkBeaconBytes) {
    ++refused_;
    return;
  }
  uint8_t wire_bytes[drivers::kMaxWireBytes];
  const auto frame = drivers::EncodeFrame(
      drivers::MakeSendBeacon(sequence_++, std::span<const uint8_t>(beacon_bytes, size.value())), wire_bytes);
  if (!frame.ok() || uart_.Free() < frame.value()) {
    ++refused_;
    return;
  }
  (void)uart_.Write(std::span<const uint8_t>(wire_bytes, frame.value()));
  ++sent_;
}

RobotImage::RobotImage(kernel::NvicPort& port, drivers::UartTx& radio_uart, ReadBytesFn read_radio,
                       void* radio_context, ConsoleFn console, void* console_context)
    : port_(port),
      radio_(radio_uart, 1),
      read_radio_(read_radio),
      radio_context_(radio_context),
      console_(console),
      console_context_(console_context),
      broker_(port) {}

const char* RobotImage::Start(const ImageConfig& config, const syrof_app_descriptor* descriptor,
                              std::span<unsigned char> queries_memory) {
  if (const char* error = Prepare(config, descriptor, queries_memory)) return error;
  return StartClock();
}

const char* RobotImage::StartClock() { return StartClockAt(port_.now_ns()); }

const char* RobotImage::StartClockAt(int64_t start_ns) {
  if (robot_ == nullptr) return "the clock started before the robot was prepared";
  return port_.StartAt(start_ns) == os::PortError::kOk ? nullptr : "port start";
}

const char* RobotImage::Prepare(const ImageConfig& config, const syrof_app_descriptor* descriptor,
                                std::span<unsigned char> queries_memory) {
  if (robot_ != nullptr) return "started twice";
  if (config.swarm_size < 1 || config.swarm_size > wire::kMaxSwarmSize || config.self_id >= config.swarm_size) {
    return "robot id or swarm size out of range";
  }
  // Every beacon of a larger swarm would be refused by the link, silently.
  if (wire::EncodedSize(config.swarm_size) > drivers::kMaxLinkBeaconBytes) {
    return "swarm too large for the radio: its beacon is longer than one BLE advertisement (31 bytes)";
  }
  config_ = config;
  // Motion (priority 1) runs a level above the round task (priority 2) on
  // the NVIC: an epoch start's round step (the app's newRound, up to 2 M
  // cycles at 32 robots) no longer holds the 10 ms motion task past its
  // deadline (docs/firmware.md, "Utilisation and response times").
  if (port_.MapPriority(registry::kMotionTaskPriority, registry::kRoundTaskPriority) != os::PortError::kOk ||
      port_.MapPriority(registry::kRoundTaskPriority, registry::kMotionTaskPriority) != os::PortError::kOk) {
    return "the kernel refused the priority map";
  }
  if (app::Validate(descriptor) != app::DescriptorError::kOk) return "the app's descriptor is invalid";
  auto* app = new (app_memory_) app::CAbiApp(*descriptor);
  app_ = app;

  syrof_queries_workspace* workspace = nullptr;
  if (syrof_queries_workspace_size() > queries_memory.size() ||
      syrof_queries_workspace_init(queries_memory.data(), queries_memory.size(), &workspace) != SYROF_QUERIES_OK) {
    return "queries workspace too small";
  }

  runtime::RobotConfig robot_config;
  robot_config.sync = sync::SyncConfig::ForSwarm(config.swarm_size, config.self_id);
  for (const uint16_t late : config.late_joiners) robot_config.sync.initial_members.reset(late);
  robot_config.queries_workspace = workspace;
  robot_config.align_rounds = config.align_rounds;
  // The link's latency on an aligned link (kBeaconLatencyNs).
  robot_config.beacon_delay_ns = kBeaconLatencyNs;
  robot_config.initial_pose.x_m = config.start_x_m;
  robot_config.initial_pose.y_m = config.start_y_m;
  robot_config.initial_pose.heading_rad = config.start_heading_rad;
  robot_config.activation = config.activation;
  robot_config.app_inputs = config.app_inputs;
  // The motion layer of the robot's kind in a swarm of its kinds, through
  // the lab's own path (boot_words.h, ConfigureImageKinds).
  if (const char* error =
          ConfigureImageKinds(robot_config, config.kind, config.swarm_kinds, config.member_kinds, member_kinds_)) {
    return error;
  }
  radio_.set_swarm_size(config.swarm_size);
  const std::span<wire::Beacon> storage(receive_storage_.data(),
                                        size_t{runtime::Robot::kReceiveBanks} * config.swarm_size);
  robot_ = new (robot_memory_) runtime::Robot(robot_config, *app, radio_, storage);

  if (imu_.Advertise(broker_, estimation::kImuTopic) != pubsub::BrokerError::kOk ||
      flow_.Advertise(broker_, estimation::kFlowTopic) != pubsub::BrokerError::kOk ||
      uwb_.Advertise(broker_, estimation::kUwbTopic) != pubsub::BrokerError::kOk) {
    return "sensor topics";
  }
  if (const runtime::RobotSetupError setup = robot_->Attach(port_, broker_); setup != runtime::RobotSetupError::kOk) {
    return runtime::ToString(setup);
  }
  const os::Trigger radio_trigger =
      config.poll_radio ? os::Trigger::periodic(kRadioPollPeriodNs) : os::Trigger::notified();
  const auto radio_id = port_.AddTask(radio_task_, {"radio", radio_trigger, registry::kRadioDeliveryPriority});
  if (radio_id.ok()) radio_task_id_ = radio_id.value();
  if (!radio_id.ok() ||
      !port_.AddTask(status_task_, {"status", os::Trigger::periodic(kStatusPeriodNs), registry::kRecorderPriority})
           .ok()) {
    return "the image's tasks";
  }
  if (config.report_rounds) {
    robot_->set_observer(&observer_);
    if (!port_.AddTask(report_task_, {"report", os::Trigger::periodic(robot_config.radio_round_ns),
                                      registry::kRecorderPriority})
             .ok()) {
      return "the report task";
    }
  }
  if (config.extension != nullptr) {
    if (const char* error = config.extension->Attach(*this, port_)) return error;
  }
  return nullptr;
}

void RobotImage::RadioTask::Step(int64_t /*now_ns*/) {
  uint8_t bytes[64];
  for (;;) {
    const size_t count = image_.read_radio_(std::span<uint8_t>(bytes), image_.radio_context_);
    for (size_t i = 0; i < count; ++i) {
      if (image_.decoder_.Push(bytes[i]) != drivers::DecodeEvent::kFrame) continue;
      const drivers::Frame& frame = image_.decoder_.frame();
      if (frame.kind == drivers::FrameKind::kReceivedBeacon) {
        image_.robot_->ReceiveBytes(std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length));
        ++image_.beacons_received_;
      }
    }
    if (count < sizeof bytes) return;  // bounded: the queue holds a few hundred bytes
  }
}

void RobotImage::EpochObserver::OnEpochStart(uint16_t /*robot*/, int64_t now_ns, const sync::LDMap& ldmap) {
  // The robot counts a start it does not look at before it tells the observer.
  const uint32_t inactive = image_.robot_->counters().inactive_epochs;
  const bool active = inactive == image_.inactive_epochs_seen_;
  image_.inactive_epochs_seen_ = inactive;
  image_.port_.Lock();
  if (image_.pending_sequence_ != image_.printed_sequence_) ++image_.epoch_lines_lost_;
  image_.pending_map_ = ldmap;
  image_.pending_active_ = active;
  image_.pending_ns_ = now_ns;
  ++image_.pending_sequence_;
  image_.port_.Unlock();
}

void RobotImage::Report(int64_t now_ns) {
  if (robot_ == nullptr) return;
  // An epoch start first, so the host sees it before the round's state.
  sync::LDMap& map = report_map_;  // kept off the stack
  bool have_map = false;
  int64_t map_ns = 0;
  bool active = true;
  port_.Lock();
  if (pending_sequence_ != printed_sequence_) {
    map = pending_map_;
    map_ns = pending_ns_;
    active = pending_active_;
    printed_sequence_ = pending_sequence_;
    have_map = true;
  }
  port_.Unlock();
  const std::span<char> line = config_.report_line;
  if (line.size() < 128) return;
  if (have_map) {
    const size_t length = FormatEpochLine(config_.self_id, map_ns, map, active, line);
    if (length > 0) {
      console_(line.data(), length, console_context_);
    } else {
      ++epoch_lines_lost_;
    }
  }
  const estimation::StateEstimate& estimate = robot_->estimate();
  const size_t length = FormatRoundLine(config_.self_id, now_ns, robot_->sync_state(), robot_->estimate_valid(),
                                        estimate.x_m, estimate.y_m, epoch_lines_lost_, line);
  if (length > 0) console_(line.data(), length, console_context_);
}

void RobotImage::PrintStatus(int64_t now_ns) {
  if (robot_ == nullptr) return;
  // Steps per task, by the names the robot and the estimator registered.
  char steps[160];
  size_t used = 0;
  for (os::TaskId id = 0; id < port_.task_count() && used < sizeof steps; ++id) {
    const int written = std::snprintf(steps + used, sizeof steps - used, " %s=%lu", port_.task_name(id),
                                      static_cast<unsigned long>(port_.steps(id)));
    if (written < 0) break;
    used += static_cast<size_t>(written);
  }
  const sync::SyncState& state = robot_->sync_state();
  char line[448];
  const int length = std::snprintf(
      line, sizeof line,
      "status t_ms=%lu board=%s robot=%u/%u steps%s overruns=%lu sync=%s epoch=%u mode=%s phase=%s members=%u "
      "sent=%lu heard=%lu link_rejected=%lu align_rounds=%lu shifts=%lu phase_error_us=%ld activation=%s "
      "inactive=%lu inputs=%u kind=%s\n",
      static_cast<unsigned long>(now_ns / 1'000'000), config_.board, static_cast<unsigned>(config_.self_id),
      static_cast<unsigned>(config_.swarm_size), steps, static_cast<unsigned long>(port_.total_overruns()),
      sync::ToString(state.status), static_cast<unsigned>(state.epoch), wire::ToString(state.epoch_mode),
      wire::ToString(state.phase), static_cast<unsigned>(state.members.count()),
      static_cast<unsigned long>(radio_.sent()), static_cast<unsigned long>(beacons_received_),
      static_cast<unsigned long>(decoder_.counters().rejected),
      static_cast<unsigned long>(robot_->alignment_stats().rounds_with_samples),
      static_cast<unsigned long>(robot_->counters().alignment_shifts),
      static_cast<long>(robot_->alignment_stats().last_error_ns / 1000), sync::ToString(config_.activation.model),
      static_cast<unsigned long>(robot_->counters().inactive_epochs), static_cast<unsigned>(config_.app_inputs.size()),
      motion::ToString(config_.kind));
  if (length > 0) console_(line, static_cast<size_t>(length) < sizeof line ? length : sizeof line - 1, console_context_);
}

}  // namespace syrof::firmware::robot
