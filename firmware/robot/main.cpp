// syrof-robot for the Teensy 3.2: the board brought up (startup.cpp), the
// robot's core (core/runtime's Robot with its estimator, synchronizer,
// motion and safety filter) and the app compiled in (`make firmware`, or
// `make firmware APP=path/app.c`), its beacons framed for the nRF51822 over
// UART0 (docs/radio-link.md).
//
// Interim, until the firmware kernel (firmware/kernel's NvicPort) is wired
// in: the robot's tasks run on core/os's simulation port, whose scheduler
// the main loop advances to the board's clock (cooperative: a task is never
// preempted). The radio's receive interrupt only queues bytes; the main
// loop decodes them and hands beacons to the robot. The sensor topics are
// advertised but no driver publishes yet, so the estimator predicts from
// the start pose. This makes the size table real: everything the robot
// runs on the Teensy is linked.

#include <cstdio>

#include "syrof/app.h"
#include "syrof/app/c_abi_app.h"
#include "syrof/board/teensy32/board.h"
#include "syrof/estimation/topics.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/queries/queries.h"
#include "syrof/runtime/robot.h"
#include "syrof/wire/beacon_codec.h"

// The compiled-in app (app.c) defines it (SYROF_APP_DEFINE).
extern "C" const syrof_app_descriptor* syrof_app_entry(void);

namespace {

namespace board = syrof::board::teensy32;
namespace drivers = syrof::firmware::drivers;

// This robot's place in its swarm: set per robot at build time
// (-DSYROF_ROBOT_ID=..., -DSYROF_ROBOT_SWARM_SIZE=...).
#ifndef SYROF_ROBOT_ID
#define SYROF_ROBOT_ID 0
#endif
#ifndef SYROF_ROBOT_SWARM_SIZE
#define SYROF_ROBOT_SWARM_SIZE 4
#endif
constexpr uint16_t kSelfId = SYROF_ROBOT_ID;
constexpr uint16_t kSwarmSize = SYROF_ROBOT_SWARM_SIZE;
static_assert(kSwarmSize >= 1 && kSwarmSize <= syrof::wire::kMaxSwarmSize && kSelfId < kSwarmSize);

constexpr uint32_t kConsoleBaud = 115'200;
constexpr uint32_t kRadioBaud = 1'000'000;

// Received radio bytes, from the UART0 interrupt to the main loop.
class ReceiveQueue {
 public:
  static void Push(uint8_t byte, void* context) { static_cast<ReceiveQueue*>(context)->PushByte(byte); }
  void PushByte(uint8_t byte) {
    if (head_ - tail_ == kCapacity) {
      dropped_ = dropped_ + 1;
      return;
    }
    bytes_[head_ % kCapacity] = byte;
    head_ = head_ + 1;
  }
  bool Pop(uint8_t& byte) {
    if (tail_ == head_) return false;
    byte = bytes_[tail_ % kCapacity];
    tail_ = tail_ + 1;
    return true;
  }

 private:
  static constexpr uint32_t kCapacity = 512;
  uint8_t bytes_[kCapacity];
  volatile uint32_t head_ = 0;
  volatile uint32_t tail_ = 0;
  volatile uint32_t dropped_ = 0;
};

// The robot's radio edge over the radio link: each beacon one SendBeacon frame.
class LinkRadio final : public syrof::runtime::Radio {
 public:
  explicit LinkRadio(drivers::UartTx& uart) : uart_(uart) {}
  void Broadcast(const syrof::wire::Beacon& beacon) override {
    uint8_t beacon_bytes[syrof::wire::kMaxBeaconBytes];
    const auto size = syrof::wire::Encode(beacon, kSwarmSize, beacon_bytes);
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
  }
  uint32_t refused() const { return refused_; }

 private:
  drivers::UartTx& uart_;
  uint8_t sequence_ = 0;
  uint32_t refused_ = 0;
};

// The queries' scratch memory; its size is checked at start-up.
alignas(16) unsigned char queries_memory[SYROF_FIRMWARE_QUERIES_BYTES];

ReceiveQueue receive_queue;
syrof::os::SimScheduler scheduler(16);
syrof::os::SimPort port(scheduler, "robot");
syrof::pubsub::StaticBroker<8, 12> broker(port);
syrof::pubsub::Publisher<syrof::estimation::ImuReading> imu;
syrof::pubsub::Publisher<syrof::estimation::FlowReading> flow;
syrof::pubsub::Publisher<syrof::estimation::UwbReading> uwb;
std::array<syrof::wire::Beacon, syrof::runtime::Robot::kReceiveBanks * kSwarmSize> receive_storage{};

[[noreturn]] void Halt(const char* what) {
  std::printf("syrof-robot: %s; halted\n", what);
  board::ConsoleUart().Flush();
  for (;;) asm volatile("wfi");
}

}  // namespace

int main() {
  board::ConsoleUart().Start(kConsoleBaud);
  std::printf("syrof-robot %u of %u (Teensy 3.2, 72 MHz)\n", static_cast<unsigned>(kSelfId),
              static_cast<unsigned>(kSwarmSize));
  if (!board::RadioUart().Start(kRadioBaud, &ReceiveQueue::Push, &receive_queue)) Halt("radio UART rate");
  board::I2cBus0().Start(400'000);

  const syrof_app_descriptor* descriptor = syrof_app_entry();
  if (syrof::app::Validate(descriptor) != syrof::app::DescriptorError::kOk) Halt("the app's descriptor is invalid");
  static syrof::app::CAbiApp app(*descriptor);

  syrof_queries_workspace* workspace = nullptr;
  if (syrof_queries_workspace_size() > sizeof queries_memory ||
      syrof_queries_workspace_init(queries_memory, sizeof queries_memory, &workspace) != SYROF_QUERIES_OK) {
    Halt("queries workspace too small");
  }

  syrof::runtime::RobotConfig config;
  config.sync = syrof::sync::SyncConfig::ForSwarm(kSwarmSize, kSelfId);
  config.queries_workspace = workspace;
  static LinkRadio radio(board::RadioUart());
  static syrof::runtime::Robot robot(config, app, radio, receive_storage);

  if (imu.Advertise(broker, syrof::estimation::kImuTopic) != syrof::pubsub::BrokerError::kOk ||
      flow.Advertise(broker, syrof::estimation::kFlowTopic) != syrof::pubsub::BrokerError::kOk ||
      uwb.Advertise(broker, syrof::estimation::kUwbTopic) != syrof::pubsub::BrokerError::kOk) {
    Halt("sensor topics");
  }
  const syrof::runtime::RobotSetupError setup = robot.Attach(port, broker);
  if (setup != syrof::runtime::RobotSetupError::kOk) Halt(syrof::runtime::ToString(setup));
  if (port.Start() != syrof::os::PortError::kOk) Halt("port start");
  std::printf("app %s attached\n", app.name());

  drivers::FrameDecoder decoder;
  for (;;) {
    uint8_t byte;
    while (receive_queue.Pop(byte)) {
      if (decoder.Push(byte) != drivers::DecodeEvent::kFrame) continue;
      const drivers::Frame& frame = decoder.frame();
      if (frame.kind == drivers::FrameKind::kReceivedBeacon) {
        robot.ReceiveBytes(std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length));
      }
    }
    scheduler.RunUntil(board::now_ns());
    asm volatile("wfi");  // SysTick wakes the loop every millisecond at the latest
  }
}
