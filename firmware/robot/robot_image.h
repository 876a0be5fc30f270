// The robot image's board-independent part, shared by the Teensy 3.2 image
// (teensy32_main.cpp) and the mps2-an386 image that runs under qemu
// (mps2_an386_main.cpp): core/runtime's Robot with the compiled-in app on
// the firmware kernel (NvicPort), its beacons framed for the radio link
// (docs/radio-link.md) on a UART, and two tasks of its own:
//
//   radio link (kRadioDeliveryPriority, every 1 ms): decodes the bytes the
//       radio UART's interrupt queued and hands each ReceivedBeacon frame to
//       Robot::ReceiveBytes. The UART interrupts run above the kernel and
//       never call it, so the task polls their queue.
//   status (kRecorderPriority, every kStatusPeriodNs): one line on the
//       console, "status t_ms=... robot=i/n steps ... overruns=... sync=... mode=...".
//
// The sensor topics (IMU, flow, UWB) are advertised here; the board's
// drivers publish on them (SensorPublishers) or, with none wired, the
// estimator predicts from the start pose.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/app.h"
#include "syrof/app/c_abi_app.h"
#include "syrof/estimation/messages.h"
#include "syrof/firmware/drivers/bus.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/firmware/kernel/nvic_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/runtime/robot.h"
#include "syrof/wire/beacon.h"

namespace syrof::firmware::robot {

/// The status line's period.
inline constexpr int64_t kStatusPeriodNs = 1'000'000'000;
/// The radio link task's period: at 1 Mbaud 100 bytes arrive per period.
inline constexpr int64_t kRadioPollPeriodNs = 1'000'000;

/// Where the radio UART's interrupt queued received bytes: copies up to
/// out.size() of them, oldest first, and returns how many.
using ReadBytesFn = size_t (*)(std::span<uint8_t> out, void* context);
/// Writes a finished console line (non-blocking; a full console drops it).
using ConsoleFn = void (*)(const char* line, size_t length, void* context);

struct ImageConfig {
  uint16_t self_id = 0;
  uint16_t swarm_size = 4;
  bool align_rounds = true;  ///< round alignment from arrivals (docs/clocks.md)
  const char* board = "";    ///< named in the status line
};

/// The robot's radio edge over the radio link: each beacon one SendBeacon frame.
class LinkRadio final : public runtime::Radio {
 public:
  LinkRadio(drivers::UartTx& uart, uint16_t swarm_size) : uart_(uart), swarm_size_(swarm_size) {}
  void Broadcast(const wire::Beacon& beacon) override;
  void set_swarm_size(uint16_t swarm_size) { swarm_size_ = swarm_size; }
  uint32_t sent() const { return sent_; }
  /// Beacons not sent: too long for a frame, or the UART's buffer full.
  uint32_t refused() const { return refused_; }

 private:
  drivers::UartTx& uart_;
  uint16_t swarm_size_;
  uint8_t sequence_ = 0;
  uint32_t sent_ = 0;
  uint32_t refused_ = 0;
};

class RobotImage {
 public:
  /// Nothing starts here; Start() attaches everything and starts the port.
  RobotImage(kernel::NvicPort& port, drivers::UartTx& radio_uart, ReadBytesFn read_radio, void* radio_context,
             ConsoleFn console, void* console_context);
  RobotImage(const RobotImage&) = delete;
  RobotImage& operator=(const RobotImage&) = delete;

  /// Builds the robot for `config` with the app `descriptor` and the queries'
  /// scratch `queries_memory`, advertises the sensor topics, attaches the
  /// robot's tasks and this image's own, and starts the port. Returns nullptr,
  /// or what failed (for the console; the image then halts).
  const char* Start(const ImageConfig& config, const syrof_app_descriptor* descriptor,
                    std::span<unsigned char> queries_memory);

  /// Writes the status line now (also done every kStatusPeriodNs).
  void PrintStatus(int64_t now_ns);

  pubsub::Publisher<estimation::ImuReading>& imu() { return imu_; }
  pubsub::Publisher<estimation::FlowReading>& flow() { return flow_; }
  pubsub::Publisher<estimation::UwbReading>& uwb() { return uwb_; }
  pubsub::Broker& broker() { return broker_; }
  runtime::Robot* robot() { return robot_; }
  const drivers::LinkCounters& link_counters() const { return decoder_.counters(); }

 private:
  class RadioTask final : public os::Task {
   public:
    explicit RadioTask(RobotImage& image) : image_(image) {}
    void Step(int64_t now_ns) override;

   private:
    RobotImage& image_;
  };
  class StatusTask final : public os::Task {
   public:
    explicit StatusTask(RobotImage& image) : image_(image) {}
    void Step(int64_t now_ns) override { image_.PrintStatus(now_ns); }

   private:
    RobotImage& image_;
  };

  kernel::NvicPort& port_;
  LinkRadio radio_;
  ReadBytesFn read_radio_;
  void* radio_context_;
  ConsoleFn console_;
  void* console_context_;
  ImageConfig config_{};
  pubsub::StaticBroker<8, 12> broker_;
  pubsub::Publisher<estimation::ImuReading> imu_;
  pubsub::Publisher<estimation::FlowReading> flow_;
  pubsub::Publisher<estimation::UwbReading> uwb_;
  std::array<wire::Beacon, runtime::Robot::kReceiveBanks * wire::kMaxSwarmSize> receive_storage_{};
  alignas(runtime::Robot) unsigned char robot_memory_[sizeof(runtime::Robot)];
  alignas(app::CAbiApp) unsigned char app_memory_[sizeof(app::CAbiApp)];
  runtime::Robot* robot_ = nullptr;
  drivers::FrameDecoder decoder_;
  uint32_t beacons_received_ = 0;
  RadioTask radio_task_{*this};
  StatusTask status_task_{*this};
};

}  // namespace syrof::firmware::robot
