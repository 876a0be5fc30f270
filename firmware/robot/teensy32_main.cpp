// syrof-robot for the Teensy 3.2: the board brought up (startup.cpp), the
// firmware kernel on the NVIC with the PIT (firmware/kernel/teensy32), and
// the robot image (robot_image.h: core/runtime's Robot with the app compiled
// in by `make firmware` or `make firmware APP=path/app.c`, its beacons
// framed for the nRF51822 over UART0, docs/radio-link.md).
//
// Who the robot is comes from its configuration block (config_block.h),
// written into this robot's copy of the image by syrof-firmware-config
// before it is flashed (docs/demo-day.md): its id, the swarm's size, its
// kind and its swarm's kinds, and its private inputs (syrofAppInput). An
// empty block (the image as built) runs with the build settings' id, swarm
// size and kinds and no inputs; a filled block's kinds override the build
// settings'; a damaged one, or one naming a kind this image does not know,
// halts at boot with a line naming why, before anything starts.
//
// The radio's receive interrupt (priority 2, above the kernel) only queues
// bytes; the image's radio task decodes them. No sensor driver publishes yet
// (the topics are advertised), so the estimator predicts from the start pose.

#include <cstdio>

#include "config_storage.h"
#include "robot_image.h"
#include "syrof/firmware/robot/config_block.h"
#include "syrof/board/teensy32/board.h"
#include "syrof/firmware/kernel/nvic_port.h"
#include "syrof/firmware/kernel/teensy32_hardware.h"

// The compiled-in app (app.c) defines it (SYROF_APP_DEFINE).
extern "C" const syrof_app_descriptor* syrof_app_entry(void);

namespace {

namespace board = syrof::board::teensy32;
namespace kernel = syrof::firmware::kernel;
namespace robot = syrof::firmware::robot;

// This robot's place in its swarm when its configuration block is empty:
// set at build time (-DSYROF_ROBOT_ID=..., -DSYROF_ROBOT_SWARM_SIZE=...).
#ifndef SYROF_ROBOT_ID
#define SYROF_ROBOT_ID 0
#endif
#ifndef SYROF_ROBOT_SWARM_SIZE
#define SYROF_ROBOT_SWARM_SIZE 4
#endif
// Its kind and its swarm's kinds when its configuration block is empty
// (-DSYROF_ROBOT_KIND=0|1|2, motion::RobotKind;
// -DSYROF_ROBOT_SWARM_KINDS=mask, bit i kind i, 0: its own alone), from the
// build settings SYROF_FIRMWARE_ROBOT_KIND and SYROF_FIRMWARE_SWARM_KINDS.
#ifndef SYROF_ROBOT_KIND
#define SYROF_ROBOT_KIND 0
#endif
#ifndef SYROF_ROBOT_SWARM_KINDS
#define SYROF_ROBOT_SWARM_KINDS 0
#endif
constexpr uint16_t kSelfId = SYROF_ROBOT_ID;
constexpr uint16_t kSwarmSize = SYROF_ROBOT_SWARM_SIZE;
static_assert(kSwarmSize >= 1 && kSwarmSize <= syrof::wire::kMaxSwarmSize && kSelfId < kSwarmSize);
static_assert(SYROF_ROBOT_KIND >= 0 && SYROF_ROBOT_KIND < syrof::motion::kRobotKindCount, "no such robot kind");
static_assert(SYROF_ROBOT_SWARM_KINDS == 0 || (SYROF_ROBOT_SWARM_KINDS & (1 << SYROF_ROBOT_KIND)) != 0,
              "the robot's kind is not among its swarm's kinds");
constexpr auto kKind = static_cast<syrof::motion::RobotKind>(SYROF_ROBOT_KIND);
constexpr uint8_t kSwarmKinds = SYROF_ROBOT_SWARM_KINDS;

constexpr uint32_t kConsoleBaud = 115'200;
constexpr uint32_t kRadioBaud = 1'000'000;

// Received radio bytes, from the UART0 interrupt (the only writer) to the
// radio task (the only reader).
class ReceiveQueue {
 public:
  static void Push(uint8_t byte, void* context) { static_cast<ReceiveQueue*>(context)->PushByte(byte); }
  static size_t Read(std::span<uint8_t> out, void* context) { return static_cast<ReceiveQueue*>(context)->Pop(out); }

 private:
  void PushByte(uint8_t byte) {
    if (head_ - tail_ == kCapacity) {
      dropped_ = dropped_ + 1;
      return;
    }
    bytes_[head_ % kCapacity] = byte;
    head_ = head_ + 1;
  }
  size_t Pop(std::span<uint8_t> out) {
    size_t taken = 0;
    uint32_t tail = tail_;
    while (taken < out.size() && tail != head_) out[taken++] = bytes_[tail++ % kCapacity];
    tail_ = tail;
    return taken;
  }

  static constexpr uint32_t kCapacity = 512;
  uint8_t bytes_[kCapacity];
  volatile uint32_t head_ = 0;
  volatile uint32_t tail_ = 0;
  volatile uint32_t dropped_ = 0;
};

void ConsoleWrite(const char* line, size_t length, void* /*context*/) {
  (void)board::ConsoleUart().Write(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(line), length));
}

// The queries' scratch memory; its size is checked at start-up.
alignas(16) unsigned char queries_memory[SYROF_FIRMWARE_QUERIES_BYTES];
ReceiveQueue receive_queue;
// The configuration block's id, swarm and inputs (syrofAppInput answers
// from here).
robot::BootConfigBlock boot_config;

[[noreturn]] void Halt(const char* what) {
  std::printf("syrof-robot: %s; halted\n", what);
  board::ConsoleUart().Flush();
  for (;;) asm volatile("wfi");
}

}  // namespace

int main() {
  board::ConsoleUart().Start(kConsoleBaud);
  robot::ImageConfig config{};
  config.self_id = kSelfId;
  config.swarm_size = kSwarmSize;
  config.board = "teensy32";
  config.kind = kKind;
  config.swarm_kinds = kSwarmKinds;
  switch (boot_config.Read(robot::FlashedConfigBlock())) {
    case robot::ConfigBlockState::kEmpty:
      std::printf("syrof-robot %u of %u, %s (Teensy 3.2, 72 MHz; no configuration block: the build's id and kind, no "
                  "inputs)\n",
                  static_cast<unsigned>(kSelfId), static_cast<unsigned>(kSwarmSize), syrof::motion::ToString(kKind));
      break;
    case robot::ConfigBlockState::kFilled: {
      // The block is the whole of who the robot is: its kind too, whatever
      // the build settings say (a block without kind words is an omni robot).
      config.self_id = boot_config.robot_id();
      config.swarm_size = boot_config.swarm_size();
      config.app_inputs = boot_config.inputs();
      config.kind = boot_config.kind();
      config.swarm_kinds = boot_config.swarm_kinds();
      config.member_kinds = boot_config.member_kinds();
      char scenario[17];
      robot::FormatScenarioId(boot_config.scenario_id(), scenario);
      std::printf("syrof-robot %u of %u, %s (Teensy 3.2, 72 MHz)\nconfig robot=%u/%u kind=%s scenario=%s inputs=%u "
                  "(the configuration block)\n",
                  static_cast<unsigned>(config.self_id), static_cast<unsigned>(config.swarm_size),
                  syrof::motion::ToString(config.kind), static_cast<unsigned>(config.self_id),
                  static_cast<unsigned>(config.swarm_size), syrof::motion::ToString(config.kind), scenario,
                  static_cast<unsigned>(config.app_inputs.size()));
      break;
    }
    case robot::ConfigBlockState::kRefused: Halt(boot_config.error());
  }
  if (!board::RadioUart().Start(kRadioBaud, &ReceiveQueue::Push, &receive_queue)) Halt("radio UART rate");
  board::I2cBus0().Start(400'000);

  static kernel::Teensy32Hardware hardware;
  static kernel::NvicPort port(hardware);
  hardware.Attach(port);
  static robot::RobotImage image(port, board::RadioUart(), &ReceiveQueue::Read, &receive_queue, &ConsoleWrite, nullptr);
  if (const char* error = image.Start(config, syrof_app_entry(), queries_memory)) {
    Halt(error);
  }
  std::printf("robot started\n");
  for (;;) asm volatile("wfi");  // thread mode idles; every task runs in an interrupt
}
