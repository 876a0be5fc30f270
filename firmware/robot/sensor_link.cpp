#include "sensor_link.h"

#include "syrof/firmware/drivers/sensor_frames.h"
#include "syrof/registry/tasks.h"

namespace syrof::firmware::robot {

const char* SensorLink::Attach(RobotImage& image, kernel::NvicPort& port) {
  const auto id = port.AddTask(*this, {"sensors", os::Trigger::notified(), registry::kSensorTaskPriority});
  if (!id.ok()) return "the sensor link's task";
  task_id_ = id.value();
  if (drive_.Subscribe(image.broker(), motion::kDriveTopic, task_id_) != pubsub::BrokerError::kOk) {
    return "the sensor link's drive subscription";
  }
  image_ = &image;
  port_ = &port;
  return nullptr;
}

void SensorLink::Notify() {
  if (port_ != nullptr) port_->Notify(task_id_);
}

void SensorLink::Step(int64_t now_ns) {
  uint8_t bytes[64];
  for (;;) {
    const size_t count = read_(std::span<uint8_t>(bytes), read_context_);
    for (size_t i = 0; i < count; ++i) {
      const drivers::DecodeEvent event = decoder_.Push(bytes[i]);
      if (event == drivers::DecodeEvent::kError) ++counters_.refused;
      if (event != drivers::DecodeEvent::kFrame) continue;
      const drivers::Frame& frame = decoder_.frame();
      switch (frame.kind) {
        case drivers::FrameKind::kImu: (void)image_->imu().Publish(drivers::ToReading(frame.imu, now_ns)); break;
        case drivers::FrameKind::kFlow: (void)image_->flow().Publish(drivers::ToReading(frame.flow, now_ns)); break;
        case drivers::FrameKind::kUwb: (void)image_->uwb().Publish(drivers::ToReading(frame.uwb, now_ns)); break;
        default: ++counters_.refused; continue;
      }
      ++counters_.readings;
    }
    if (count < sizeof bytes) break;  // bounded: the ring holds a few hundred bytes
  }
  motion::DriveCommand command;
  while (drive_.Take(command)) {
    uint8_t wire[drivers::kMaxWireBytes];
    const auto length = drivers::EncodeFrame(drivers::MakeDrive(sequence_++, drivers::ToPayload(command)), wire);
    if (!length.ok() || uart_.Free() < length.value()) {
      ++counters_.drives_dropped;
      continue;
    }
    (void)uart_.Write(std::span<const uint8_t>(wire, length.value()));
    ++counters_.drives_sent;
  }
}

}  // namespace syrof::firmware::robot
