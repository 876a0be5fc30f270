// The emulated swarm host's end of one robot's sensor link
// (docs/radio-link.md, "The sensor link"): the lab's simulated readings as
// the frames the robot's sensor task decodes, and the robot's drive commands
// out of the bytes it sends back.
//
//   SensorFeed feed;
//   bank.Sample(world_ns, world.true_state(id), feed);   // readings due now
//   write(fd, feed.bytes().data(), feed.bytes().size()); feed.clear();
//   ... for each byte read: if (auto drive = feed.PushFromRobot(byte, now_ns)) world.SetDrive(id, *drive);
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/motion/drive.h"

namespace syrof::firmware::swarm {

/// Counts since construction.
struct SensorFeedCounters {
  int64_t imu = 0, flow = 0, uwb = 0;  ///< frames written
  int64_t not_encoded = 0;             ///< readings the link refused (a non-finite value)
  int64_t drives = 0;                  ///< Drive frames received
  int64_t refused = 0;                 ///< frames from the robot rejected or of another kind
};

class SensorFeed final : public lab::sensors::ReadingSink {
 public:
  void OnImu(const estimation::ImuReading& reading) override;
  void OnFlow(const estimation::FlowReading& reading) override;
  void OnUwb(const estimation::UwbReading& reading) override;

  /// The frames written since the last clear(), in order, ready for the socket.
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  void clear() { bytes_.clear(); }

  /// One byte from the robot; a drive command when it completes a Drive
  /// frame (stamped `now_ns`, the host's clock).
  std::optional<motion::DriveCommand> PushFromRobot(uint8_t byte, int64_t now_ns);

  const SensorFeedCounters& counters() const { return counters_; }
  const drivers::LinkCounters& link_counters() const { return decoder_.counters(); }

 private:
  bool Append(const drivers::Frame& frame);

  std::vector<uint8_t> bytes_;
  uint8_t sequence_ = 0;
  drivers::FrameDecoder decoder_;
  SensorFeedCounters counters_{};
};

}  // namespace syrof::firmware::swarm
