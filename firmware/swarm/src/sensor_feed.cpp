#include "syrof/firmware/swarm/sensor_feed.h"

#include "syrof/firmware/drivers/sensor_frames.h"

namespace syrof::firmware::swarm {

bool SensorFeed::Append(const drivers::Frame& frame) {
  uint8_t wire[drivers::kMaxWireBytes];
  const auto length = drivers::EncodeFrame(frame, wire);
  if (!length.ok()) {
    ++counters_.not_encoded;
    return false;
  }
  bytes_.insert(bytes_.end(), wire, wire + length.value());
  return true;
}

void SensorFeed::OnImu(const estimation::ImuReading& reading) {
  if (Append(drivers::MakeImu(sequence_++, drivers::ToPayload(reading)))) ++counters_.imu;
}

void SensorFeed::OnFlow(const estimation::FlowReading& reading) {
  if (Append(drivers::MakeFlow(sequence_++, drivers::ToPayload(reading)))) ++counters_.flow;
}

void SensorFeed::OnUwb(const estimation::UwbReading& reading) {
  if (Append(drivers::MakeUwb(sequence_++, drivers::ToPayload(reading)))) ++counters_.uwb;
}

std::optional<motion::DriveCommand> SensorFeed::PushFromRobot(uint8_t byte, int64_t now_ns) {
  const drivers::DecodeEvent event = decoder_.Push(byte);
  if (event == drivers::DecodeEvent::kError) ++counters_.refused;
  if (event != drivers::DecodeEvent::kFrame) return std::nullopt;
  const drivers::Frame& frame = decoder_.frame();
  if (frame.kind != drivers::FrameKind::kDrive) {
    ++counters_.refused;
    return std::nullopt;
  }
  ++counters_.drives;
  return drivers::ToCommand(frame.drive, now_ns);
}

}  // namespace syrof::firmware::swarm
