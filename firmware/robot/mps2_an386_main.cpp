// syrof-robot for qemu's mps2-an386: the same robot image as the Teensy's
// (robot_image.h) on the firmware kernel's mps2-an386 hardware, for tests and
// emulated swarms. UART0 is the console (the status lines), UART1 the radio
// link, UART2 the sensor link (sensor_link.h: the world's readings in, drive
// commands out; only with `sensors 1`); qemu's -serial options map to them
// in order, so
//
//   qemu-system-arm -M mps2-an386 -nographic -monitor none
//       -semihosting-config enable=on,target=native -icount shift=0,sleep=off
//       -serial stdio -chardev socket,id=radio,path=SOCK -serial chardev:radio
//       -kernel syrof-robot-mps2.elf -append "id 0 swarm 4 seconds 5"
//
// Command line (semihosting, -append): `id N` (default 0), `swarm N`
// (default 4), `seconds S` (stop after S seconds of guest time and exit 0;
// default 0: run for ever), `align 0|1` (round alignment, default 1),
// `report 0|1` (the swarm host's "R" and "E" lines, default 0),
// `sensors 0|1` (the sensor link on UART2, default 0), `x_mm N`, `y_mm N`,
// `heading_mrad N` (the start pose, arena frame; heading 0..6283), `late N`
// (robot N is switched on later, so it is no initial member; repeatable:
// the swarm host's late joiners, and the joiner itself), the activation
// model's words (boot_words.h: `activation ssync schedule random seed N
// fair_within F`, ...; absent: FSYNC), the robot's private inputs
// (boot_words.h: `inputs ID:N` then N `input NAME=VALUE`; refused, with no
// start, when written for another id or one is missing), the robot's kind
// (boot_words.h: `kind omni|rover|drone`, absent omni, and `swarm_kinds
// K,K,...`, the swarm's kinds, absent its own: the motion layer of that kind;
// `member_kinds LLL...`, every robot's kind, needed in a mixed swarm;
// a kind it does not know is refused, with no start), `hold 0|1` (with
// `sensors 1`: set everything up, print `held id=N t_ms=T app=NAME`, NAME
// the compiled-in app's descriptor name, and start the clock
// only when a Start frame arrives on the sensor link, then run its run_ms;
// `seconds` is then ignored), `scenario HEX` (the 16 hex digits of the
// scenario id the configuration block must carry, below). A word it does
// not know stops the image with exit status 2 and names the word.
//
// The configuration block (config_block.h, written into a copy of this ELF
// by syrof-firmware-config, as for the Teensy) is read first. Empty (as
// built), the command line alone says who the robot is. Filled, the block
// wins: it gives the id, the swarm's size, the kinds and the inputs, and the
// command line may only confirm them: an `id`, `swarm`, `kind`,
// `swarm_kinds` or `scenario` word that differs from the block's (a block
// without kind words is an omni robot among omni robots), or any
// `inputs`/`input` word, stops the image
// with exit status 2 naming both, as does a damaged block (magic, version,
// checksum, a word), before anything starts.
// The UARTs interrupt at priority 2, above the kernel, and their handlers
// only move bytes between the UART and its rings; but the radio's receive
// interrupt sits at 4, masked by the kernel, and also notifies the image's
// radio-link task (no polling: fewer wake-ups for qemu to emulate).

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "robot_image.h"
#include "sensor_link.h"
#include "syrof/board/mps2_an386/cmsdk_uart.h"
#include "syrof/firmware/robot/boot_words.h"
#include "syrof/firmware/robot/config_block.h"
#include "config_storage.h"
#include "syrof/firmware/robot/console_patience.h"
#include "syrof/firmware/kernel/mps2_an386_hardware.h"
#include "syrof/firmware/kernel/nvic_port.h"

extern "C" const syrof_app_descriptor* syrof_app_entry(void);

namespace {

namespace board = syrof::board::mps2_an386;
namespace kernel = syrof::firmware::kernel;
namespace robot = syrof::firmware::robot;

constexpr uint8_t kUartPriority = 2;  // above the kernel (4): never calls it
// The radio's receive interrupt notifies the radio-link task, so it sits
// where the kernel masks it (BASEPRI at the timer's 4): at 4 itself.
constexpr uint8_t kRadioReceivePriority = 4;

board::CmsdkUart console(board::kCmsdkUart0);
board::CmsdkUart radio(board::kCmsdkUart1);
board::CmsdkUart sensor_uart(board::kCmsdkUart2);

// The UART's rings are shared with its interrupt handler; the kernel's tasks
// touch them with the UART interrupts masked (BASEPRI at their priority).
class MaskUarts {
 public:
  MaskUarts() {
    asm volatile(
        "mrs %0, basepri\n"
        "msr basepri_max, %1"
        : "=&r"(previous_)
        : "r"(uint32_t{kUartPriority} << 4)
        : "memory");
  }
  ~MaskUarts() { asm volatile("msr basepri, %0" ::"r"(previous_) : "memory"); }
  MaskUarts(const MaskUarts&) = delete;
  MaskUarts& operator=(const MaskUarts&) = delete;

 private:
  uint32_t previous_;
};

// A UART as the drivers' UartTx, safe to call from any task.
class MaskedUart final : public syrof::firmware::drivers::UartTx {
 public:
  explicit MaskedUart(board::CmsdkUart& uart) : uart_(uart) {}
  size_t Free() const override {
    MaskUarts masked;
    return uart_.Free();
  }
  size_t Write(std::span<const uint8_t> bytes) override {
    MaskUarts masked;
    return uart_.Write(bytes);
  }

 private:
  board::CmsdkUart& uart_;
};
MaskedUart radio_tx(radio);
MaskedUart sensor_tx(sensor_uart);

// context: the CmsdkUart to read.
size_t ReadUart(std::span<uint8_t> out, void* context) {
  MaskUarts masked;
  return static_cast<board::CmsdkUart*>(context)->Read(out);
}

robot::SensorLink sensor_link(sensor_tx, &ReadUart, &sensor_uart);

// While `busy()` (read with the UART interrupts masked) holds, sleeps (WFI)
// until an interrupt, so that qemu halts this guest's vCPU and its I/O
// thread can move the bytes: spinning instead kept a vCPU busy, which under
// SCHED_FIFO (`syrof-firmware-swarm --realtime`) starved the I/O threads of
// every guest on that host core, so console lines came out cut and beacons
// late. PRIMASK is set across the check and the WFI, so an interrupt
// between them still wakes it.
template <typename Busy>
void SleepIfBusy(Busy busy) {
  asm volatile("cpsid i" ::: "memory");
  bool waiting = false;
  {
    MaskUarts masked;
    waiting = busy();
  }
  if (waiting) asm volatile("wfi" ::: "memory");
  asm volatile("cpsie i" ::: "memory");
}

// Writes the whole line, a ring's worth at a time, sleeping while the ring
// is full (SleepIfBusy). `context` is the kernel's port, the clock that
// bounds it: a console that takes no byte for 200 ms loses the rest of the
// line. (The clock is read through the port, under the kernel's mask: an
// unmasked read racing the kernel's own could count a wrap of the timer
// that never happened, and under -icount one did, jumping a robot's clock
// 172 s ahead.)
void ConsoleWrite(const char* line, size_t length, void* context) {
  const auto& port = *static_cast<const kernel::NvicPort*>(context);
  const auto* bytes = reinterpret_cast<const uint8_t*>(line);
  robot::ConsolePatience patience(port.now_ns());
  for (size_t sent = 0; sent < length;) {
    size_t wrote = 0;
    {
      MaskUarts masked;
      wrote = console.Write(std::span<const uint8_t>(bytes + sent, length - sent));
    }
    sent += wrote;
    if (sent == length) return;
    if (patience.Exhausted(port.now_ns(), wrote > 0)) return;
    SleepIfBusy([] { return console.Free() == 0; });
  }
}

robot::RobotImage* image_for_interrupts = nullptr;

void ConsoleInterrupt() { console.OnInterrupt(); }
void RadioInterrupt() { radio.OnInterrupt(); }
void SensorInterrupt() { sensor_uart.OnInterrupt(); }
// The receive handlers wake their task when a frame's closing 0x00 has
// come in, not for every byte: a task run and its decoder's start-up per
// frame instead of per byte.
void SensorReceiveInterrupt() {
  uint32_t zeros_before = 0, zeros_after = 0;
  {
    MaskUarts masked;
    zeros_before = sensor_uart.zeros_received();
    sensor_uart.OnInterrupt();
    zeros_after = sensor_uart.zeros_received();
  }
  if (zeros_after != zeros_before) sensor_link.Notify();
}
void RadioReceiveInterrupt() {
  uint32_t zeros_before = 0, zeros_after = 0;
  {
    MaskUarts masked;  // the transmit interrupt (2) shares the rings
    zeros_before = radio.zeros_received();
    radio.OnInterrupt();
    zeros_after = radio.zeros_received();
  }
  if (zeros_after != zeros_before && image_for_interrupts != nullptr) image_for_interrupts->NotifyRadio();
}

alignas(16) unsigned char queries_memory[SYROF_FIRMWARE_QUERIES_BYTES];
// The activation's boot words and its scripts (the robot's config points here).
robot::BootActivation boot_activation;
// The robot's private inputs (syrofAppInput answers from here).
robot::BootInputs boot_inputs;
// The robot's kind and its swarm's kinds (its motion layer).
robot::BootKind boot_kind;
// The configuration block's id, swarm and inputs, when it is filled.
robot::BootConfigBlock boot_config;
char report_line[2048];

struct Options {
  robot::ImageConfig image{};
  long seconds = 0;
  bool sensors = false;
  bool hold = false;
  // What the command line said of who the robot is (checked against a
  // filled configuration block).
  bool id_given = false;
  bool swarm_given = false;
  bool inputs_given = false;
  bool scenario_given = false;
  bool kind_given = false;
  bool swarm_kinds_given = false;
  bool member_kinds_given = false;
  uint64_t scenario_id = 0;
};

// `kinds` as boot_words.h's swarm_kinds value (omni,drone), in `out`.
const char* KindList(robot::KindSet kinds, std::span<char> out) {
  size_t used = 0;
  out[0] = '\0';
  for (size_t i = 0; i < syrof::motion::kRobotKindCount; ++i) {
    const auto kind = static_cast<syrof::motion::RobotKind>(i);
    if ((kinds & robot::KindBit(kind)) == 0) continue;
    const int n = std::snprintf(out.data() + used, out.size() - used, "%s%s", used == 0 ? "" : ",",
                                syrof::motion::ToString(kind));
    if (n < 0 || static_cast<size_t>(n) >= out.size() - used) break;
    used += static_cast<size_t>(n);
  }
  return out.data();
}

// `text` as exactly 16 hex digits.
bool ScenarioId(const char* text, uint64_t& id) {
  id = 0;
  size_t digits = 0;
  for (; text[digits] != '\0'; ++digits) {
    const char c = text[digits];
    unsigned digit = 0;
    if (c >= '0' && c <= '9') {
      digit = static_cast<unsigned>(c - '0');
    } else if (c >= 'a' && c <= 'f') {
      digit = static_cast<unsigned>(c - 'a' + 10);
    } else {
      return false;
    }
    if (digits == 16) return false;
    id = (id << 4) | digit;
  }
  return digits == 16;
}

// A filled configuration block against what the command line said: the
// block wins, the line may only confirm it. False, with a line on the
// console, when they disagree.
bool TakeConfigBlock(Options& options) {
  char block_scenario[17];
  robot::FormatScenarioId(boot_config.scenario_id(), block_scenario);
  if (options.inputs_given) {
    std::printf("syrof-robot: the command line gives inputs words and the configuration block holds robot %u's "
                "inputs too; give them in one place (a flashed image takes no inputs words)\n",
                static_cast<unsigned>(boot_config.robot_id()));
    return false;
  }
  if (options.id_given && options.image.self_id != boot_config.robot_id()) {
    std::printf("syrof-robot: the configuration block was written for robot %u; the command line says id %u\n",
                static_cast<unsigned>(boot_config.robot_id()), static_cast<unsigned>(options.image.self_id));
    return false;
  }
  if (options.swarm_given && options.image.swarm_size != boot_config.swarm_size()) {
    std::printf("syrof-robot: the configuration block was written for a swarm of %u; the command line says swarm %u\n",
                static_cast<unsigned>(boot_config.swarm_size()), static_cast<unsigned>(options.image.swarm_size));
    return false;
  }
  if (options.scenario_given && options.scenario_id != boot_config.scenario_id()) {
    char expected[17];
    robot::FormatScenarioId(options.scenario_id, expected);
    std::printf("syrof-robot: the configuration block was written for scenario %s; the command line expects "
                "scenario %s\n",
                block_scenario, expected);
    return false;
  }
  if (options.kind_given && boot_kind.self() != boot_config.kind()) {
    std::printf("syrof-robot: the configuration block was written for a%s %s robot; the command line says kind %s\n",
                boot_config.kind() == syrof::motion::RobotKind::kOmni ? "n" : "",
                syrof::motion::ToString(boot_config.kind()), syrof::motion::ToString(boot_kind.self()));
    return false;
  }
  char block_kinds[32];
  KindList(boot_config.swarm_kinds(), block_kinds);
  if (options.swarm_kinds_given && boot_kind.swarm() != boot_config.swarm_kinds()) {
    char line_kinds[32];
    std::printf("syrof-robot: the configuration block was written for a swarm of kinds %s; the command line says "
                "swarm_kinds %s\n",
                block_kinds, KindList(boot_kind.swarm(), line_kinds));
    return false;
  }
  const auto line_members = boot_kind.members();
  const auto block_members = boot_config.member_kinds();
  if (options.member_kinds_given &&
      !std::equal(line_members.begin(), line_members.end(), block_members.begin(), block_members.end())) {
    std::printf("syrof-robot: the configuration block was written with other member_kinds than the command line's\n");
    return false;
  }
  options.image.self_id = boot_config.robot_id();
  options.image.swarm_size = boot_config.swarm_size();
  options.image.app_inputs = boot_config.inputs();
  options.image.kind = boot_config.kind();
  options.image.swarm_kinds = boot_config.swarm_kinds();
  options.image.member_kinds = block_members;
  // The line names every input with the value read, each in the fewest
  // digits (15 to 17) that read back to it, so a test sees what the robot holds.
  std::printf("config robot=%u/%u kind=%s swarm_kinds=%s scenario=%s inputs=%u",
              static_cast<unsigned>(boot_config.robot_id()), static_cast<unsigned>(boot_config.swarm_size()),
              syrof::motion::ToString(boot_config.kind()), block_kinds, block_scenario,
              static_cast<unsigned>(boot_config.inputs().size()));
  for (const syrof::app::Parameter& input : boot_config.inputs()) {
    char value[40];
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(value, sizeof value, "%.*g", digits, input.value);
      if (std::strtod(value, nullptr) == input.value) break;
    }
    std::printf(" %.*s=%s", static_cast<int>(input.name.size()), input.name.data(), value);
  }
  std::printf(" (the configuration block)\n");
  return true;
}

// Reads `key value` pairs and the configuration block; on error prints
// which word and why, returns false.
bool ParseOptions(int argc, char** argv, Options& options) {
  options.image.board = "mps2-an386";
  const robot::ConfigBlockState block = boot_config.Read(robot::FlashedConfigBlock());
  if (block == robot::ConfigBlockState::kRefused) {
    std::printf("syrof-robot: %s\n", boot_config.error());
    return false;
  }
  for (int i = 1; i < argc; i += 2) {
    const char* key = argv[i];
    if (i + 1 >= argc) {
      std::printf("syrof-robot: -append word %d '%s' has no value (expected: key value pairs, e.g. id 0 swarm 4)\n", i,
                  key);
      return false;
    }
    switch (boot_inputs.Read(key, argv[i + 1])) {
      case robot::BootWordRead::kNotMine: break;
      case robot::BootWordRead::kOk:
        options.inputs_given = true;
        continue;
      case robot::BootWordRead::kBadValue:
        std::printf("syrof-robot: -append word %d '%s': '%s' is not a value it takes (inputs ID:N first, then N "
                    "input NAME=VALUE, each name once, each value a finite number; firmware/robot boot_words.h)\n",
                    i + 1, key, argv[i + 1]);
        return false;
      case robot::BootWordRead::kFull:
        std::printf("syrof-robot: -append word %d '%s': '%s' is one input more than its inputs word announced\n", i + 1,
                    key, argv[i + 1]);
        return false;
    }
    switch (boot_kind.Read(key, argv[i + 1])) {
      case robot::BootWordRead::kNotMine: break;
      case robot::BootWordRead::kOk:
        (key[0] == 'k' ? options.kind_given : key[0] == 's' ? options.swarm_kinds_given : options.member_kinds_given) =
            true;
        continue;
      case robot::BootWordRead::kBadValue:
      case robot::BootWordRead::kFull:
        std::printf("syrof-robot: -append word %d '%s': '%s' is not a value it takes (a robot kind this image knows: "
                    "omni, rover or drone; swarm_kinds lists them, each once; member_kinds a letter o, r or d for "
                    "each robot; firmware/robot boot_words.h)\n",
                    i + 1, key, argv[i + 1]);
        return false;
    }
    switch (boot_activation.Read(key, argv[i + 1])) {
      case robot::BootWordRead::kNotMine: break;
      case robot::BootWordRead::kOk: continue;
      case robot::BootWordRead::kBadValue:
        std::printf("syrof-robot: -append word %d '%s': '%s' is not a value it takes (firmware/robot boot_words.h)\n",
                    i + 1, key, argv[i + 1]);
        return false;
      case robot::BootWordRead::kFull:
        std::printf("syrof-robot: -append word %d '%s': longer than the image holds (%u scripted pairs, %u cycles)\n",
                    i + 1, key, static_cast<unsigned>(robot::kMaxBootScriptedActivations),
                    static_cast<unsigned>(robot::kMaxBootScriptedCycles));
        return false;
    }
    if (std::strcmp(key, "scenario") == 0) {
      if (!ScenarioId(argv[i + 1], options.scenario_id)) {
        std::printf("syrof-robot: -append word %d 'scenario': '%s' is not 16 hex digits (a scenario id as "
                    "syrof-firmware-config prints it)\n",
                    i + 1, argv[i + 1]);
        return false;
      }
      options.scenario_given = true;
      continue;
    }
    char* end = nullptr;
    const long value = std::strtol(argv[i + 1], &end, 10);
    if (end == argv[i + 1] || *end != '\0' || value < 0) {
      std::printf("syrof-robot: -append word %d '%s': '%s' is not a whole number >= 0\n", i + 1, key, argv[i + 1]);
      return false;
    }
    if (std::strcmp(key, "id") == 0 && value < syrof::wire::kMaxSwarmSize) {
      options.image.self_id = static_cast<uint16_t>(value);
      options.id_given = true;
    } else if (std::strcmp(key, "swarm") == 0 && value >= 1 && value <= syrof::wire::kMaxSwarmSize) {
      options.image.swarm_size = static_cast<uint16_t>(value);
      options.swarm_given = true;
    } else if (std::strcmp(key, "seconds") == 0) {
      options.seconds = value;
    } else if (std::strcmp(key, "align") == 0 && value <= 1) {
      options.image.align_rounds = value == 1;
    } else if (std::strcmp(key, "report") == 0 && value <= 1) {
      options.image.report_rounds = value == 1;
    } else if (std::strcmp(key, "sensors") == 0 && value <= 1) {
      options.sensors = value == 1;
    } else if (std::strcmp(key, "x_mm") == 0 && value <= 1'000'000) {
      options.image.start_x_m = static_cast<float>(value) * 1e-3f;
    } else if (std::strcmp(key, "y_mm") == 0 && value <= 1'000'000) {
      options.image.start_y_m = static_cast<float>(value) * 1e-3f;
    } else if (std::strcmp(key, "heading_mrad") == 0 && value <= 6283) {
      const float heading = static_cast<float>(value) * 1e-3f;
      options.image.start_heading_rad = heading > 3.14159265f ? heading - 6.28318531f : heading;
    } else if (std::strcmp(key, "late") == 0 && value < syrof::wire::kMaxSwarmSize) {
      options.image.late_joiners.set(static_cast<uint16_t>(value));
    } else if (std::strcmp(key, "hold") == 0 && value <= 1) {
      options.hold = value == 1;
    } else {
      std::printf("syrof-robot: -append word %d: unknown key '%s' or value %ld out of range "
                  "(id 0..31, swarm 1..32, seconds >= 0, align 0|1, report 0|1, sensors 0|1, x_mm and y_mm 0..1000000, "
                  "heading_mrad 0..6283, late 0..31, hold 0|1, scenario HEX, and the activation, input and kind "
                  "words of boot_words.h)\n",
                  i, key, value);
      return false;
    }
  }
  if (const char* error = boot_kind.Check()) {
    std::printf("syrof-robot: %s\n", error);
    return false;
  }
  if (block == robot::ConfigBlockState::kFilled) {
    if (!TakeConfigBlock(options)) return false;
  } else {
    if (options.scenario_given) {
      std::printf("syrof-robot: the command line expects a configuration block (scenario word) and the image has "
                  "none (write one with syrof-firmware-config)\n");
      return false;
    }
    if (options.image.self_id >= options.image.swarm_size) {
      std::printf("syrof-robot: id %u is not below swarm %u\n", static_cast<unsigned>(options.image.self_id),
                  static_cast<unsigned>(options.image.swarm_size));
      return false;
    }
    if (const char* error = boot_inputs.Check(options.image.self_id)) {
      std::printf("syrof-robot: %s\n", error);
      return false;
    }
    options.image.app_inputs = boot_inputs.inputs();
    options.image.kind = boot_kind.self();
    options.image.swarm_kinds = boot_kind.swarm();
    options.image.member_kinds = boot_kind.members();
  }
  options.image.activation = boot_activation.config();
  if (!syrof::sync::IsValid(options.image.activation)) {
    std::printf("syrof-robot: the activation words make no valid schedule (scripts sorted, delays within max_delay)\n");
    return false;
  }
  if (options.hold && !options.sensors) {
    std::printf("syrof-robot: hold 1 needs sensors 1 (the Start frame comes on the sensor link)\n");
    return false;
  }
  return true;
}

// A Start frame as WaitForStart took it.
struct StartFrame {
  uint32_t run_ms = 0;
  int64_t first_byte_ns = 0;  // the clock when its first byte came in
};

// `hold 1`: the robot is prepared, its clock not started. Takes the sensor
// link's bytes one at a time (so that none after the Start frame is taken
// from the sensor task) until a Start frame, sleeping between interrupts.
// Other frames before it are ignored. Each byte after the first waits for
// qemu's I/O thread and this guest's vCPU in turn; with the other guests
// already running it took up to 27 ms to get the rest of the frame, so
// the round grid begins when the first byte came in (StartClockAt).
StartFrame WaitForStart(kernel::Mps2An386Hardware& hardware, kernel::NvicPort& port, uint16_t self_id,
                        const char* app_name) {
  const int sensor_irq = board::CmsdkUartRxIrq(board::kCmsdkUart2);
  hardware.RouteInterrupt(static_cast<uint8_t>(sensor_irq), kUartPriority, &SensorInterrupt);
  // `held id=N t_ms=T app=NAME`: NAME, the compiled-in app's own name (its
  // descriptor's), is the rest of the line, written whole whatever its
  // length (the host checks it: firmware/swarm console_lines.h).
  char line[48];
  const int length = std::snprintf(line, sizeof line, "held id=%u t_ms=%ld app=", static_cast<unsigned>(self_id),
                                   static_cast<long>(port.now_ns() / 1'000'000));
  ConsoleWrite(line, static_cast<size_t>(length), &port);
  ConsoleWrite(app_name, std::strlen(app_name), &port);
  ConsoleWrite("\n", 1, &port);
  syrof::firmware::drivers::FrameDecoder decoder;
  bool at_frame_start = true;  // the next byte begins a frame (frames end with 0x00)
  int64_t first_byte_ns = 0;
  for (;;) {
    uint8_t byte = 0;
    size_t count = 0;
    {
      MaskUarts masked;
      count = sensor_uart.Read(std::span<uint8_t>(&byte, 1));
    }
    if (count == 0) {
      asm volatile("wfi");
      continue;
    }
    if (at_frame_start) first_byte_ns = port.now_ns();
    at_frame_start = byte == 0;
    if (decoder.Push(byte) == syrof::firmware::drivers::DecodeEvent::kFrame &&
        decoder.frame().kind == syrof::firmware::drivers::FrameKind::kStart) {
      return {decoder.frame().run_ms, first_byte_ns};
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!ParseOptions(argc, argv, options)) return 2;
  options.image.report_line = report_line;

  static kernel::Mps2An386Hardware hardware;
  static kernel::NvicPort port(hardware);
  hardware.Attach(port);
  console.Start(/*interrupts=*/true);
  radio.Start(/*interrupts=*/true);
  const int console_irq = board::CmsdkUartRxIrq(board::kCmsdkUart0);
  const int radio_irq = board::CmsdkUartRxIrq(board::kCmsdkUart1);
  hardware.RouteInterrupt(static_cast<uint8_t>(console_irq), kUartPriority, &ConsoleInterrupt);
  hardware.RouteInterrupt(static_cast<uint8_t>(console_irq + 1), kUartPriority, &ConsoleInterrupt);
  static robot::RobotImage image(port, radio_tx, &ReadUart, &radio, &ConsoleWrite, &port);
  options.image.poll_radio = false;
  hardware.RouteInterrupt(static_cast<uint8_t>(radio_irq + 1), kUartPriority, &RadioInterrupt);
  const int sensor_irq = board::CmsdkUartRxIrq(board::kCmsdkUart2);
  if (options.sensors) {
    sensor_uart.Start(/*interrupts=*/true);
    hardware.RouteInterrupt(static_cast<uint8_t>(sensor_irq + 1), kUartPriority, &SensorInterrupt);
    options.image.extension = &sensor_link;
  }
  if (const char* error = image.Prepare(options.image, syrof_app_entry(), queries_memory)) {
    std::printf("syrof-robot: %s\n", error);
    return 1;
  }
  int64_t stop_ns = options.seconds * int64_t{1'000'000'000};
  if (options.hold) {
    const StartFrame start = WaitForStart(hardware, port, options.image.self_id, image.app_name());
    char line[80];
    const int length =
        std::snprintf(line, sizeof line, "started t_ms=%ld run_ms=%lu frame_us=%ld\n",
                      static_cast<long>(start.first_byte_ns / 1'000'000), static_cast<unsigned long>(start.run_ms),
                      static_cast<long>((port.now_ns() - start.first_byte_ns) / 1000));
    ConsoleWrite(line, static_cast<size_t>(length), &port);
    stop_ns = start.run_ms == 0 ? 0 : start.first_byte_ns + int64_t{start.run_ms} * 1'000'000;
    if (const char* error = image.StartClockAt(start.first_byte_ns)) {
      std::printf("syrof-robot: %s\n", error);
      return 1;
    }
  } else if (const char* error = image.StartClock()) {
    std::printf("syrof-robot: %s\n", error);
    return 1;
  }
  // Receiving starts once the radio task exists; the receive interrupt is a
  // level, so a byte already waiting raises it again.
  image_for_interrupts = &image;
  hardware.RouteInterrupt(static_cast<uint8_t>(radio_irq), kRadioReceivePriority, &RadioReceiveInterrupt);
  if (options.sensors) {
    hardware.RouteInterrupt(static_cast<uint8_t>(sensor_irq), kRadioReceivePriority, &SensorReceiveInterrupt);
  }
  while (stop_ns == 0 || port.now_ns() < stop_ns) asm volatile("wfi");

  (void)port.Stop();
  image.PrintStatus(port.now_ns());
  // Let the console's interrupt send the last line before qemu exits,
  // sleeping between its interrupts (SleepIfBusy), for at most 200 ms.
  const int64_t give_up_ns = port.now_ns() + 200'000'000;
  bool idle = false;
  while (!idle && port.now_ns() < give_up_ns) {
    {
      MaskUarts masked;
      idle = console.transmit_idle();
    }
    SleepIfBusy([] { return !console.transmit_idle(); });
  }
  return 0;
}
