// The emulated swarm's sensor link on the robot (mps2-an386 image only): the
// host that plays the world sends the lab's simulated IMU, flow and UWB
// readings over a UART in radio-link frames (docs/radio-link.md, "The sensor
// link"); this task decodes them and publishes each on the topic the real
// driver would (RobotImage::imu(), flow(), uwb()), stamped with the port's
// clock at decoding, so the estimator fuses them as in the lab. It also
// subscribes to the motion task's drive command and frames each one back.
//
//   sensors (kSensorTaskPriority, notified: by the UART's receive interrupt
//       through Notify(), and by every drive command published)
//
// Bounded per step: the bytes queued (the UART's ring) and the commands
// queued (kDriveDepth). Nothing allocated.
#pragma once

#include <cstddef>
#include <cstdint>

#include "robot_image.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/motion/drive.h"
#include "syrof/pubsub/topic.h"

namespace syrof::firmware::robot {

/// Counts since start (they wrap).
struct SensorLinkCounters {
  uint32_t readings = 0;      ///< IMU, flow and UWB readings published
  uint32_t refused = 0;       ///< frames the decoder rejected, or of a kind the robot does not take
  uint32_t drives_sent = 0;   ///< Drive frames written
  uint32_t drives_dropped = 0;  ///< commands not sent: the UART's buffer was full
};

class SensorLink final : public ImageExtension, private os::Task {
 public:
  static constexpr size_t kDriveDepth = 2;

  /// `uart` writes to the host; `read` takes the bytes the UART's receive
  /// interrupt queued (ReadBytesFn). Not owned.
  SensorLink(drivers::UartTx& uart, ReadBytesFn read, void* read_context)
      : uart_(uart), read_(read), read_context_(read_context) {}

  /// Adds the task and subscribes it to the drive topic (ImageExtension).
  const char* Attach(RobotImage& image, kernel::NvicPort& port) override;

  /// Makes the task ready: from the receive interrupt (priority 4..15).
  void Notify();

  const SensorLinkCounters& counters() const { return counters_; }
  const drivers::LinkCounters& link_counters() const { return decoder_.counters(); }

 private:
  void Step(int64_t now_ns) override;

  drivers::UartTx& uart_;
  ReadBytesFn read_;
  void* read_context_;
  RobotImage* image_ = nullptr;
  kernel::NvicPort* port_ = nullptr;
  os::TaskId task_id_ = 0;
  drivers::FrameDecoder decoder_;
  pubsub::Subscriber<motion::DriveCommand, kDriveDepth> drive_;
  uint8_t sequence_ = 0;
  SensorLinkCounters counters_{};
};

}  // namespace syrof::firmware::robot
