// The robot image's board-independent part, shared by the Teensy 3.2 image
// (teensy32_main.cpp) and the mps2-an386 image that runs under qemu
// (mps2_an386_main.cpp): core/runtime's Robot with the compiled-in app on
// the firmware kernel (NvicPort), its beacons framed for the radio link
// (docs/radio-link.md) on a UART, and tasks of its own:
//
//   radio link (kRadioDeliveryPriority, every 1 ms, or when the board's
//       receive interrupt notifies it: ImageConfig::poll_radio): decodes the
//       bytes the radio UART's interrupt queued and hands each
//       ReceivedBeacon frame to Robot::ReceiveBytes. On the Teensy the UART
//       interrupts run above the kernel and never call it, so the task polls.
//   status (kRecorderPriority, every kStatusPeriodNs): one line on the
//       console, "status t_ms=... robot=i/n steps ... overruns=... sync=... mode=...".
//   report (kRecorderPriority, every radio round; only with
//       ImageConfig::report_rounds): the lines an emulated swarm's host reads
//       (docs/firmware.md, "The emulated swarm"): "R ..." the robot's state
//       each round, and "E ..." each epoch start with its LDMap, queued by
//       the round task (the robot's observer) and printed here, so every
//       console line comes from one level and none interleave. The "E" line
//       says whether the robot looked at that start (its activation
//       schedule's decision, ImageConfig::activation).
//
// The sensor topics (IMU, flow, UWB) are advertised here; the board's
// drivers publish on them (imu(), flow(), uwb()) or, with none wired, the
// estimator predicts from the start pose. Under qemu the emulated swarm's
// sensor link (sensor_link.h, an ImageExtension) publishes the readings the
// host's simulated world sends.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/app.h"
#include "syrof/app/c_abi_app.h"
#include "syrof/estimation/messages.h"
#include "syrof/motion/robot_kind.h"
#include "syrof/firmware/drivers/bus.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/firmware/kernel/nvic_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/registry/tasks.h"
#include "syrof/runtime/robot.h"
#include "syrof/runtime/robot_observer.h"
#include "syrof/sync/activation.h"
#include "syrof/sync/ldmap.h"
#include "syrof/wire/beacon.h"
#include "syrof/wire/member_set.h"

namespace syrof::firmware::robot {

/// The status line's period.
inline constexpr int64_t kStatusPeriodNs = 1'000'000'000;
/// The radio link task's period when it polls: at 1 Mbaud 100 bytes arrive
/// per period.
inline constexpr int64_t kRadioPollPeriodNs = 1'000'000;

/// Where the radio UART's interrupt queued received bytes: copies up to
/// out.size() of them, oldest first, and returns how many.
using ReadBytesFn = size_t (*)(std::span<uint8_t> out, void* context);
/// Writes a finished console line (non-blocking; a full console drops it).
using ConsoleFn = void (*)(const char* line, size_t length, void* context);

class RobotImage;

/// A board's addition to the image (the emulated swarm's sensor link):
/// attached after the robot and before the port starts. Returns nullptr, or
/// what failed.
class ImageExtension {
 public:
  virtual const char* Attach(RobotImage& image, kernel::NvicPort& port) = 0;

 protected:
  ~ImageExtension() = default;
};

struct ImageConfig {
  uint16_t self_id = 0;
  uint16_t swarm_size = 4;
  bool align_rounds = true;  ///< round alignment from arrivals (docs/clocks.md)
  const char* board = "";    ///< named in the status line
  bool report_rounds = false;  ///< print the "R" and "E" lines
  /// The radio-link task polls every kRadioPollPeriodNs (true), or runs when
  /// notified (false): the board's receive interrupt, at a priority the
  /// kernel masks, calls NotifyRadio() (mps2-an386; fewer wake-ups under qemu).
  bool poll_radio = true;
  /// Where the report task formats them (not owned): an "E" line of 32
  /// members takes about 1.5 KB; shorter maps need less.
  std::span<char> report_line{};
  /// Where the robot starts, arena frame (the estimator's initial pose).
  float start_x_m = 0;
  float start_y_m = 0;
  float start_heading_rad = 0;
  /// Robots switched on later (a scenario's `join` faults): not initial
  /// members, as in the lab (lab/sim robot_config). A robot in it starts as a
  /// joiner; the others start their first epoch without it.
  wire::MemberSet late_joiners{};
  /// Which members move in each epoch (sync/activation.h), the same on every
  /// robot of the swarm; its scripts must outlive the image (the mps2-an386
  /// image reads it from its boot words, boot_words.h). FSYNC by default.
  sync::ActivationConfig activation{};
  /// What syrofAppInput answers: this robot's private inputs (the
  /// scenario's `inputs:`, its own value of each); the table and its names
  /// must outlive the image (the mps2-an386 image reads them from its boot
  /// words, boot_words.h). Empty: no inputs.
  std::span<const app::Parameter> app_inputs{};
  /// This robot's kind and the kinds in its swarm (bit i for
  /// motion::RobotKind i; 0: its own kind alone): its motion layer, as the
  /// lab's robot of that kind has it (runtime::ConfigureKinds, with the
  /// kinds' default limits, motion::DefaultKindLimits). The mps2-an386 image
  /// reads them from its boot words, the Teensy's from its build settings.
  motion::RobotKind kind = motion::RobotKind::kOmni;
  uint8_t swarm_kinds = 0;
  /// Every robot's kind by id (boot_words.h's member_kinds), what the app
  /// reads of its members; needed in a swarm of more than one kind, and
  /// then swarm_size of them, kept alive as app_inputs. Empty in a swarm of
  /// one kind: every robot is of it.
  std::span<const motion::RobotKind> member_kinds{};
  ImageExtension* extension = nullptr;  ///< not owned
};

/// From a sender's round boundary to its beacon's arrival, on an aligned
/// link: the beacon is sent at the boundary, and the radio delivers it half a
/// round later, as the lab's radio does (docs/clocks.md; the emulated swarm's
/// host holds each beacon that long), plus up to one radio-task period before
/// the receiver reads it. A beacon that arrived right at the receivers'
/// boundaries would land in one round or the next by a microsecond; mid-round
/// it lands in the round it belongs to. Real nRF51822 firmware has to keep
/// the same latency (docs/firmware.md).
inline constexpr int64_t kBeaconLatencyNs = registry::kDefaultRadioRoundNs / 2 + kRadioPollPeriodNs;

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
  /// Prepare() then StartClock().
  const char* Start(const ImageConfig& config, const syrof_app_descriptor* descriptor,
                    std::span<unsigned char> queries_memory);
  /// Everything Start() does but starting the port: the robot is built and
  /// its tasks attached, and no task runs until StartClock().
  const char* Prepare(const ImageConfig& config, const syrof_app_descriptor* descriptor,
                      std::span<unsigned char> queries_memory);
  /// Starts the port: the robot's round grid begins at this instant (the
  /// emulated swarm's common start, `hold 1`). nullptr, or what failed.
  const char* StartClock();
  /// As StartClock(), but the grid begins at `start_ns` on the port's clock,
  /// an instant already past (when the Start frame's first byte came in).
  const char* StartClockAt(int64_t start_ns);

  /// Makes the radio-link task ready (ImageConfig::poll_radio false). Safe
  /// from an interrupt whose priority the kernel masks (4..15).
  void NotifyRadio() { port_.Notify(radio_task_id_); }

  /// Writes the status line now (also done every kStatusPeriodNs).
  void PrintStatus(int64_t now_ns);

  /// The name of the app compiled into the image (its descriptor's, as
  /// app::CAbiApp::name() gives it), once Prepare() built it; nullptr before.
  const char* app_name() const { return app_ != nullptr ? app_->name() : nullptr; }

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
  class ReportTask final : public os::Task {
   public:
    explicit ReportTask(RobotImage& image) : image_(image) {}
    void Step(int64_t now_ns) override { image_.Report(now_ns); }

   private:
    RobotImage& image_;
  };
  // Hears the robot's epoch starts (in the round task) for the report task.
  class EpochObserver final : public runtime::RobotObserver {
   public:
    explicit EpochObserver(RobotImage& image) : image_(image) {}
    void OnEpochStart(uint16_t robot, int64_t now_ns, const sync::LDMap& ldmap) override;
    void OnMembership(uint16_t, int64_t, const wire::MemberSet&, const wire::MemberSet&) override {}
    void OnBecameJoiner(uint16_t, int64_t) override {}
    void OnAppFault(uint16_t, int64_t, app::Callback, uint16_t, const app::CallStatus&) override {}
    void OnInvalidCommand(uint16_t, int64_t, uint16_t, const app::CommandCheck&) override {}
    void OnPayloadRefused(uint16_t, int64_t, uint16_t, size_t) override {}

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
  std::array<motion::RobotKind, wire::kMaxSwarmSize> member_kinds_{};  // RobotConfig::member_kinds
  alignas(runtime::Robot) unsigned char robot_memory_[sizeof(runtime::Robot)];
  alignas(app::CAbiApp) unsigned char app_memory_[sizeof(app::CAbiApp)];
  const app::CAbiApp* app_ = nullptr;  // in app_memory_, once Prepare() built it
  runtime::Robot* robot_ = nullptr;
  drivers::FrameDecoder decoder_;
  uint32_t beacons_received_ = 0;
  RadioTask radio_task_{*this};
  os::TaskId radio_task_id_ = 0;
  StatusTask status_task_{*this};
  ReportTask report_task_{*this};
  EpochObserver observer_{*this};
  // The latest epoch start, written by the round task under the port's lock
  // and printed by the report task; epochs last many rounds, so one slot
  // holds each start until it is printed.
  sync::LDMap pending_map_{};
  sync::LDMap report_map_{};
  bool pending_active_ = true;
  // The robot's inactive_epochs at the last epoch start: it grows at a start
  // the robot did not look at.
  uint32_t inactive_epochs_seen_ = 0;
  int64_t pending_ns_ = 0;
  uint32_t pending_sequence_ = 0;
  uint32_t printed_sequence_ = 0;
  uint32_t epoch_lines_lost_ = 0;

  void Report(int64_t now_ns);
};

}  // namespace syrof::firmware::robot
