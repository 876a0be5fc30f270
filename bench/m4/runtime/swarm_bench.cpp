// Worst observed instructions per task of the robot, on the emulated
// Cortex-M4 (qemu mps2-an386, -icount shift=0: one counted cycle per
// executed instruction), in a swarm of 32: the schedulability table of
// docs/firmware.md.
//
// 32 runtime::Robot instances, each on its own SimPort of one SimScheduler
// (as the lab runs them), each port wrapped in a MeasuredPort that counts
// every step of the tasks the robot attaches: estimation.state,
// estimation.kalman, runtime.round and runtime.motion, the robot's own code.
// Around them, unmeasured, a small world:
//   - each robot's body moves as its DriveCommand says (omni: the velocity;
//     rover: the wheels), and the lab's simulated sensors (lab/sensors'
//     SensorBank: MPU-9250, flow, DWM1000 with its outliers and dropouts,
//     seeded per robot) sample it at their rates onto the robot's broker;
//   - the radio: each beacon is encoded (core/wire) into a ReceivedBeacon
//     frame of the radio link (docs/radio-link.md) and reaches every other
//     robot half a round after it was sent, as the lab's radio and the
//     emulated swarm's host deliver it.
// Each robot's radio-link task (firmware.radio, measured) decodes the frames
// as the firmware image's radio task does: the streaming FrameDecoder byte
// by byte, then Robot::ReceiveBytes (the beacon's core/wire decode and its
// copy into the receive bank) per ReceivedBeacon frame.
//
// The robots start on a grid with a 0.7 m position uncertainty (placed by
// hand), so their first UWB sweeps place them by least squares: the Kalman
// steps that fix a sweep, some with an outlier the sensors drew, are the
// filter's slowest. Each app runs for kRunSeconds (several epochs); the
// apps are the firmware image's (the C app `make firmware` compiles in:
// cli/new_project/app.c, unless SYROF_FIRMWARE_APP names another; on robot
// 0 only, as its globals are per robot, the others running the lab's circle) and the lab's built-in
// circle, gather and leader_follow; gather once more with rovers. Every
// count is printed as worst and mean over the 32 robots' steps.
//
// Built with SYROF_BENCH_STRONGEST_INPUTS (bench_m4_runtime_swarm_strongest,
// linked with assignments/strongest's reference instead of the starter, as
// syrof-robot-mps2-strongest is): every robot runs that C app (its globals,
// the app info and a scratch table, are the same on every robot of one
// swarm), with its private input table (RobotConfig::app_inputs, what
// syrofAppInput searches) empty, full with 16 names of the longest length
// the table takes sharing a 62-byte prefix, `charge` alone (the
// assignment's own input), and `charge` last after 15 such names. Robot 0
// also times single syrofAppInput calls against its table, through the C
// ABI and the robot as the app calls it: the worst miss (a 63-byte name
// that shares the 62-byte prefix) and `charge`. Built once more with
// SYROF_BENCH_ROBOTS=4 (bench_m4_runtime_swarm_strongest_4): the same at
// the assignment's swarm size.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numbers>

#include "measured_port.h"
#include "syrof/app/c_abi_app.h"
#include "syrof/board/cycles.h"
#include "syrof/estimation/topics.h"
#include "syrof/firmware/drivers/radio_link.h"
#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sensors/sensor_publishers.h"
#include "syrof/motion/drive.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/queries/queries.h"
#include "syrof/registry/tasks.h"
#include "syrof/runtime/robot.h"
#include "syrof/wire/beacon_codec.h"

extern "C" const syrof_app_descriptor* syrof_app_entry(void);

namespace {

using namespace syrof;
namespace drivers = syrof::firmware::drivers;
using bench::StepStats;

#ifndef SYROF_BENCH_ROBOTS
#define SYROF_BENCH_ROBOTS 32  // bench_m4_runtime_swarm_strongest_4 sets 4: the assignment's swarm
#endif
constexpr uint16_t kRobots = SYROF_BENCH_ROBOTS;
static_assert(kRobots >= 2 && kRobots <= 32, "the grid and the bench's world hold 2 to 32 robots");
constexpr int64_t kRunSeconds = 4;
constexpr int64_t kRoundNs = registry::kDefaultRadioRoundNs;
constexpr int64_t kWorldPeriodNs = registry::kImuPeriodNs;
constexpr size_t kQueriesBytes = 7168;
// A round's frames from every other robot, with room to spare.
constexpr size_t kRxBytes = 2 * kRobots * drivers::kMaxWireBytes;

// What one run measures, over every robot.
struct RunStats {
  StepStats state;
  StepStats kalman_plain;    // IMU predict and flow only
  StepStats kalman_sweep;    // with a UWB sweep's range updates (or its screen)
  StepStats kalman_fix;      // a sweep placed the robot by least squares, no outlier drawn
  StepStats kalman_fix_outlier;  // the same for a sweep with an outlier
  StepStats kalman_unused;   // a sweep that changed nothing: a fix refused (every subset solved), or no range
  StepStats round_ordinary;
  StepStats round_epoch;     // an epoch started: LDMap, the app's newRound
  StepStats new_round;       // the app's newRound alone
  StepStats round_epoch_robot0;  // robot 0's epoch starts (the firmware's app, in the first run)
  StepStats new_round_robot0;
  StepStats motion;
  StepStats radio_step;      // one activation: every frame queued (31 at 32 robots)
  StepStats radio_frame;     // one ReceivedBeacon frame: its bytes through the decoder + ReceiveBytes
  uint32_t epochs = 0;
  uint32_t cooperative = 0;
  uint32_t overflow = 0;
  uint32_t malformed = 0;
  uint32_t received = 0;
  uint32_t safety_interventions = 0;
  uint32_t moved = 0;        // robots that ended over 5 cm from where they started
  StepStats input_miss;      // robot 0: syrofAppInput of a name not in its table (the worst one)
  StepStats input_charge;    // robot 0: syrofAppInput("charge")
  int input_miss_status = SYROF_APP_OK;  // what those calls answered
  int input_charge_status = SYROF_APP_OK;
};

RunStats* stats = nullptr;  // the current run's

// The private input tables a run gives its robots (RobotConfig::app_inputs).
enum class Inputs : uint8_t {
  kNone,         // no inputs: syrofAppInput answers SYROF_APP_NO_SUCH_INPUT
  kLongest,      // 16 names of 63 bytes, the first 62 shared: the worst table to search
  kCharge,       // `charge` alone, each robot its own value
  kChargeLast,   // 15 such names, then `charge`
};

constexpr size_t kNameBytes = SYROF_APP_MAX_PARAMETER_NAME_LENGTH;  // 63
// A name of kNameBytes bytes: kNameBytes - 1 shared bytes, then `last`.
struct LongName {
  char text[kNameBytes + 1];
};
LongName MakeLongName(char last) {
  LongName name{};
  for (size_t i = 0; i + 1 < kNameBytes; ++i) name.text[i] = static_cast<char>('a' + i % 26);
  name.text[kNameBytes - 1] = last;
  return name;
}
// Table names 'A'..'P' last; the probe's miss ends with 'Z'.
std::array<LongName, SYROF_APP_MAX_INPUTS> long_names;
const LongName missing_name = MakeLongName('Z');

// Each robot's own charge: distinct, fixed (no generator to seed).
double ChargeOf(uint16_t id) { return 100.0 + static_cast<double>((id * 919u + 123u) % 1000u); }

// Fills `table` with robot `id`'s inputs; returns how many.
size_t FillInputs(Inputs inputs, uint16_t id, std::array<app::Parameter, SYROF_APP_MAX_INPUTS>& table) {
  size_t size = 0;
  const size_t longest = inputs == Inputs::kLongest ? SYROF_APP_MAX_INPUTS
                         : inputs == Inputs::kChargeLast ? SYROF_APP_MAX_INPUTS - 1
                                                         : 0;
  for (; size < longest; ++size) table[size] = {long_names[size].text, static_cast<double>(size)};
  if (inputs == Inputs::kCharge || inputs == Inputs::kChargeLast) table[size++] = {"charge", ChargeOf(id)};
  return size;
}

// A C app of the bench's own, run once on robot 0 after its app's init
// (CAbiApp makes the robot the current platform for it, as for any C app):
// times syrofAppInput calls, each as the app makes it.
uint8_t ProbeInit(const syrof_app_info* /*info*/) {
  double value = 0;
  uint64_t begin = board::cycle_counter_read();
  stats->input_miss_status = syrofAppInput(missing_name.text, &value);
  stats->input_miss.Add(board::cycle_counter_read() - begin);
  begin = board::cycle_counter_read();
  stats->input_charge_status = syrofAppInput("charge", &value);
  stats->input_charge.Add(board::cycle_counter_read() - begin);
  return 0;
}
uint8_t ProbeNewRound(syrof_car_command* /*command*/, const syrof_ldmap* /*map*/, uint8_t state, uint32_t /*ms*/) {
  return state;
}
uint8_t ProbeEndOfRound(const syrof_ldmap* /*map*/, uint8_t state, uint32_t /*ms*/) { return state; }
const syrof_app_descriptor probe_descriptor = {SYROF_APP_ABI_VERSION, "input_probe", &ProbeInit, &ProbeNewRound,
                                               &ProbeEndOfRound};

// Times the app's newRound; everything else passes through.
class TimedApp final : public app::App {
 public:
  // `also`: a second series the counts go to as well (robot 0's), or nullptr.
  // `probe`: after the app's init, time syrofAppInput (robot 0's).
  TimedApp(app::App& inner, StepStats* also, bool probe) : inner_(inner), also_(also), probe_(probe) {}
  const char* name() const override { return inner_.name(); }
  app::CallStatus Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) override {
    const app::CallStatus status = inner_.Init(info, platform, global_state);
    if (probe_) {
      app::CAbiApp probe(probe_descriptor);
      uint8_t probe_state = 0;
      (void)probe.Init(info, platform, probe_state);
    }
    return status;
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                           uint32_t clock_ms) override {
    const uint64_t begin = board::cycle_counter_read();
    const app::CallStatus status = inner_.NewRound(command, ldmap, global_state, clock_ms);
    const uint64_t instructions = board::cycle_counter_read() - begin;
    stats->new_round.Add(instructions);
    if (also_ != nullptr) also_->Add(instructions);
    return status;
  }
  app::CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) override {
    return inner_.EndOfRound(ldmap, global_state, clock_ms);
  }

 private:
  app::App& inner_;
  StepStats* also_;
  bool probe_;
};

struct Air {
  uint8_t bytes[kRobots][drivers::kMaxWireBytes];
  size_t length[kRobots];
};

// Robot -> air: the beacon's wire bytes in a ReceivedBeacon frame, as the
// radio (nRF51822) hands it to every receiver's UART.
class AirRadio final : public runtime::Radio {
 public:
  AirRadio(Air& air, uint16_t self) : air_(air), self_(self) {}
  void Broadcast(const wire::Beacon& beacon) override {
    uint8_t beacon_bytes[wire::kMaxBeaconBytes];
    const auto size = wire::Encode(beacon, kRobots, beacon_bytes);
    if (!size.ok()) return;
    const auto frame = drivers::EncodeFrame(
        drivers::MakeReceivedBeacon(sequence_++, -60, std::span<const uint8_t>(beacon_bytes, size.value())),
        air_.bytes[self_]);
    air_.length[self_] = frame.ok() ? frame.value() : 0;
  }

 private:
  Air& air_;
  uint16_t self_;
  uint8_t sequence_ = 0;
};

struct RobotSlot;

// The firmware image's radio-link task (robot_image.cpp, RadioTask::Step):
// every queued byte through the streaming decoder, each ReceivedBeacon frame
// to Robot::ReceiveBytes. Also times each frame.
class RadioTask final : public os::Task {
 public:
  explicit RadioTask(RobotSlot& slot) : slot_(slot) {}
  void Step(int64_t now_ns) override;

 private:
  RobotSlot& slot_;
};

// The robot's body and sensors (not measured): integrates the drive command
// over the world period, then lets the sensor bank publish what is due.
class WorldTask final : public os::Task {
 public:
  explicit WorldTask(RobotSlot& slot) : slot_(slot) {}
  void Step(int64_t now_ns) override;

 private:
  RobotSlot& slot_;
};

void Observe(void* context, os::TaskId task, const os::TaskConfig& config, uint64_t instructions, int64_t now_ns);

struct RobotSlot {
  RobotSlot(os::SimScheduler& scheduler, uint16_t id, Air& air)
      : self(id), sim_port(scheduler, "robot"), port(sim_port, &Observe, this), broker(port), radio(air, id),
        radio_task(*this), world_task(*this) {}

  uint16_t self;
  os::SimPort sim_port;
  bench::MeasuredPort port;
  pubsub::StaticBroker<8, 12> broker;
  lab::sensors::SensorPublishers publishers;
  std::unique_ptr<lab::sensors::SensorBank> bank;
  pubsub::Subscriber<motion::DriveCommand> drive;
  AirRadio radio;
  std::array<wire::Beacon, runtime::Robot::kReceiveBanks * kRobots> receive_storage{};
  alignas(16) unsigned char queries_memory[kQueriesBytes];
  std::unique_ptr<app::App> inner_app;
  std::unique_ptr<app::App> app;
  std::unique_ptr<runtime::Robot> robot;
  std::array<app::Parameter, SYROF_APP_MAX_INPUTS> inputs{};
  double start_x_m = 0, start_y_m = 0;
  drivers::FrameDecoder decoder;
  uint8_t rx[kRxBytes];
  size_t rx_length = 0;
  RadioTask radio_task;
  os::TaskId radio_task_id = 0;
  WorldTask world_task;
  motion::DriveCommand command{};
  lab::sensors::TrueState truth{};
  // For classifying the next steps.
  uint32_t new_rounds = 0;
  uint32_t fixes = 0;
  uint32_t ranges = 0;
  bool sweep_pending = false;
  bool outlier_pending = false;
};

void RadioTask::Step(int64_t /*now_ns*/) {
  RobotSlot& slot = slot_;
  uint64_t mark = board::cycle_counter_read();
  for (size_t i = 0; i < slot.rx_length; ++i) {
    if (slot.decoder.Push(slot.rx[i]) != drivers::DecodeEvent::kFrame) continue;
    const drivers::Frame& frame = slot.decoder.frame();
    if (frame.kind == drivers::FrameKind::kReceivedBeacon) {
      slot.robot->ReceiveBytes(std::span<const uint8_t>(frame.beacon.data(), frame.beacon_length));
    }
    const uint64_t now = board::cycle_counter_read();
    stats->radio_frame.Add(now - mark);
    mark = now;
  }
  slot.rx_length = 0;
}

void WorldTask::Step(int64_t now_ns) {
  RobotSlot& slot = slot_;
  motion::DriveCommand latest{};
  if (slot.drive.TakeLatest(latest)) slot.command = latest;
  lab::sensors::TrueState& truth = slot.truth;
  const double dt = static_cast<double>(kWorldPeriodNs) * 1e-9;
  double vx = 0, vy = 0, yaw_rate = 0;
  if (slot.command.kind == motion::DriveKind::kOmni) {
    vx = slot.command.vx_mps;
    vy = slot.command.vy_mps;
    yaw_rate = slot.command.yaw_rate_radps;
  } else {
    const double v = 0.5 * (slot.command.left_mps + slot.command.right_mps);
    yaw_rate = (slot.command.right_mps - slot.command.left_mps) / motion::ControllerConfig{}.limits.wheel_base_m;
    vx = v * std::cos(truth.heading_rad);
    vy = v * std::sin(truth.heading_rad);
  }
  if (now_ns > 0) {
    truth.ax_mps2 = (vx - truth.vx_mps) / dt;
    truth.ay_mps2 = (vy - truth.vy_mps) / dt;
    truth.x_m = std::clamp(truth.x_m + vx * dt, 0.1, 3.9);
    truth.y_m = std::clamp(truth.y_m + vy * dt, 0.1, 3.9);
    truth.heading_rad = std::remainder(truth.heading_rad + yaw_rate * dt, 2 * std::numbers::pi);
  }
  truth.vx_mps = vx;
  truth.vy_mps = vy;
  truth.yaw_rate_radps = yaw_rate;
  const uint64_t outliers = slot.bank->uwb_outliers();
  slot.bank->Sample(now_ns, truth, slot.publishers);
  // The DWM1000 model sweeps every kUwbPeriodNs from 0.
  if (now_ns % registry::kUwbPeriodNs == 0) slot.sweep_pending = true;
  if (slot.bank->uwb_outliers() != outliers) slot.outlier_pending = true;
}

void Observe(void* context, os::TaskId /*task*/, const os::TaskConfig& config, uint64_t instructions,
             int64_t /*now_ns*/) {
  RobotSlot& slot = *static_cast<RobotSlot*>(context);
  const auto is = [&](const char* name) { return std::strcmp(config.name, name) == 0; };
  if (is("estimation.state")) {
    stats->state.Add(instructions);
  } else if (is("estimation.kalman")) {
    const estimation::EstimatorCounters& counters = slot.robot->estimator().counters();
    const uint32_t ranges = counters.ranges_fused + counters.ranges_rejected;
    if (!slot.sweep_pending) {
      stats->kalman_plain.Add(instructions);
    } else if (counters.fixes != slot.fixes) {
      (slot.outlier_pending ? stats->kalman_fix_outlier : stats->kalman_fix).Add(instructions);
    } else if (ranges != slot.ranges) {
      stats->kalman_sweep.Add(instructions);
    } else {
      stats->kalman_unused.Add(instructions);
    }
    slot.sweep_pending = false;
    slot.outlier_pending = false;
    slot.fixes = counters.fixes;
    slot.ranges = ranges;
  } else if (is("runtime.round")) {
    const uint32_t new_rounds = slot.robot->counters().new_rounds;
    if (new_rounds != slot.new_rounds) {
      stats->round_epoch.Add(instructions);
      if (slot.self == 0) stats->round_epoch_robot0.Add(instructions);
      ++stats->epochs;
      if (slot.robot->ldmap().mode == wire::Mode::kCooperative) ++stats->cooperative;
    } else {
      stats->round_ordinary.Add(instructions);
    }
    slot.new_rounds = new_rounds;
  } else if (is("runtime.motion")) {
    stats->motion.Add(instructions);
  } else if (is("firmware.radio")) {
    stats->radio_step.Add(instructions);
  }
}

// Mid-round: every beacon of the round just ended reaches every other robot.
class ChannelTask final : public os::Task {
 public:
  ChannelTask(Air& air, RobotSlot** slots) : air_(air), slots_(slots) {}
  void Step(int64_t /*now_ns*/) override {
    for (uint16_t sender = 0; sender < kRobots; ++sender) {
      if (air_.length[sender] == 0) continue;
      for (uint16_t receiver = 0; receiver < kRobots; ++receiver) {
        RobotSlot& slot = *slots_[receiver];
        if (receiver == sender || slot.rx_length + air_.length[sender] > kRxBytes) continue;
        std::copy(air_.bytes[sender], air_.bytes[sender] + air_.length[sender], slot.rx + slot.rx_length);
        slot.rx_length += air_.length[sender];
      }
      air_.length[sender] = 0;
    }
    for (uint16_t receiver = 0; receiver < kRobots; ++receiver) {
      if (slots_[receiver]->rx_length > 0) slots_[receiver]->port.Notify(slots_[receiver]->radio_task_id);
    }
  }

 private:
  Air& air_;
  RobotSlot** slots_;
};

struct RunSpec {
  const char* label;
  const char* app;        // lab/apps' built-in app of every robot
  bool firmware_app;      // robot 0 runs the firmware image's built-in C app instead
  motion::DriveKind kind;
  bool firmware_app_everywhere = false;  // every robot runs it (an app whose globals may be shared)
  Inputs inputs = Inputs::kNone;
};

bool Run(const RunSpec& spec, RunStats& result) {
  stats = &result;
  auto scheduler = std::make_unique<os::SimScheduler>(kRobots * 8 + 4);
  auto air = std::make_unique<Air>();
  std::array<std::unique_ptr<RobotSlot>, kRobots> owned;
  RobotSlot* slots[kRobots];
  for (uint16_t id = 0; id < kRobots; ++id) {
    owned[id] = std::make_unique<RobotSlot>(*scheduler, id, *air);
    slots[id] = owned[id].get();
  }
  bool ok = true;
  for (uint16_t id = 0; id < kRobots && ok; ++id) {
    RobotSlot& slot = *slots[id];
    // An 8 x 4 grid, 0.42 m apart, facing +x.
    slot.truth.x_m = 0.53 + 0.42 * (id % 8);
    slot.truth.y_m = 1.37 + 0.42 * (id / 8);
    lab::sensors::SensorBankConfig sensors;
    slot.bank = std::make_unique<lab::sensors::SensorBank>(sensors, 1000u + id);
    if (slot.publishers.Advertise(slot.broker) != pubsub::BrokerError::kOk) ok = false;

    slot.start_x_m = slot.truth.x_m;
    slot.start_y_m = slot.truth.y_m;
    if (spec.firmware_app && (id == 0 || spec.firmware_app_everywhere)) {
      slot.inner_app = std::make_unique<app::CAbiApp>(*syrof_app_entry());
    } else {
      slot.inner_app = lab::apps::MakeBuiltinApp(spec.app, {});
    }
    if (!slot.inner_app) return false;
    const bool probe = id == 0 && spec.firmware_app_everywhere;
    slot.app = std::make_unique<TimedApp>(*slot.inner_app, id == 0 ? &result.new_round_robot0 : nullptr, probe);
    syrof_queries_workspace* workspace = nullptr;
    if (syrof_queries_workspace_size() > kQueriesBytes ||
        syrof_queries_workspace_init(slot.queries_memory, kQueriesBytes, &workspace) != SYROF_QUERIES_OK) {
      std::printf("queries workspace too small\n");
      return false;
    }
    runtime::RobotConfig config;
    config.sync = sync::SyncConfig::ForSwarm(kRobots, id);
    config.queries_workspace = workspace;
    config.motion.kind = spec.kind;
    config.safety.arena_width_m = 4;
    config.safety.arena_height_m = 4;
    config.initial_pose.x_m = static_cast<float>(slot.truth.x_m);
    config.initial_pose.y_m = static_cast<float>(slot.truth.y_m);
    config.initial_pose.position_sigma_m = 0.7f;
    config.app_inputs = std::span<const app::Parameter>(slot.inputs.data(), FillInputs(spec.inputs, id, slot.inputs));
    slot.robot = std::make_unique<runtime::Robot>(config, *slot.app, slot.radio, slot.receive_storage);
    if (const runtime::RobotSetupError error = slot.robot->Attach(slot.port, slot.broker);
        error != runtime::RobotSetupError::kOk) {
      std::printf("robot %u: %s\n", unsigned{id}, runtime::ToString(error));
      return false;
    }
    // The world's own tasks go to the SimPort directly: not measured.
    const auto world = slot.sim_port.AddTask(
        slot.world_task, {"world", os::Trigger::periodic(kWorldPeriodNs), registry::kSensorTaskPriority});
    const auto radio =
        slot.port.AddTask(slot.radio_task, {"firmware.radio", os::Trigger::notified(), registry::kRadioDeliveryPriority});
    if (!world.ok() || !radio.ok() ||
        slot.drive.Subscribe(slot.broker, motion::kDriveTopic, world.value()) != pubsub::BrokerError::kOk) {
      std::printf("robot %u: world tasks\n", unsigned{id});
      return false;
    }
    slot.radio_task_id = radio.value();
  }
  os::SimPort channel_port(*scheduler, "channel");
  ChannelTask channel(*air, slots);
  ok = ok && channel_port.AddTask(channel, {"channel", os::Trigger::periodic(kRoundNs, kRoundNs / 2),
                                            registry::kRadioDeliveryPriority + 1})
                 .ok();
  for (uint16_t id = 0; id < kRobots && ok; ++id) ok = slots[id]->port.Start() == os::PortError::kOk;
  ok = ok && channel_port.Start() == os::PortError::kOk;
  if (ok) scheduler->RunFor(kRunSeconds * 1'000'000'000);
  for (uint16_t id = 0; id < kRobots; ++id) {
    const runtime::RobotCounters& counters = slots[id]->robot->counters();
    result.overflow += counters.beacons_overflow;
    result.malformed += counters.beacons_malformed;
    result.received += counters.beacons_received;
    result.safety_interventions += counters.safety_interventions;
    const RobotSlot& slot = *slots[id];
    if (std::hypot(slot.truth.x_m - slot.start_x_m, slot.truth.y_m - slot.start_y_m) > 0.05) ++result.moved;
    if (slots[id]->robot->app_faulted()) {
      std::printf("  robot %u: the app faulted\n", unsigned{id});
      ok = false;
    }
  }
  (void)channel_port.Stop();
  for (uint16_t id = 0; id < kRobots; ++id) (void)slots[id]->port.Stop();
  return ok;
}

void Print(const char* what, const StepStats& step) {
  if (step.count == 0) {
    std::printf("  %-50s        -  (not observed)\n", what);
    return;
  }
  std::printf("  %-50s %8llu worst %8llu mean %6llu steps\n", what, static_cast<unsigned long long>(step.worst),
              static_cast<unsigned long long>(step.mean()), static_cast<unsigned long long>(step.count));
}

}  // namespace

int main() {
  board::cycle_counter_start();
  for (size_t i = 0; i < long_names.size(); ++i) long_names[i] = MakeLongName(static_cast<char>('A' + i));
#ifdef SYROF_BENCH_STRONGEST_INPUTS
  const RunSpec runs[] = {
      {"strongest on every robot, no inputs (every charge 0)", "circle", true, motion::DriveKind::kOmni, true,
       Inputs::kNone},
      {"strongest on every robot, 16 inputs of 63-byte names (no charge: every charge 0)", "circle", true,
       motion::DriveKind::kOmni, true, Inputs::kLongest},
      {"strongest on every robot, input charge alone", "circle", true, motion::DriveKind::kOmni, true,
       Inputs::kCharge},
      {"strongest on every robot, 15 inputs of 63-byte names, then charge", "circle", true, motion::DriveKind::kOmni,
       true, Inputs::kChargeLast},
  };
#else
  const RunSpec runs[] = {
      {"firmware built-in app (C circle) on robot 0, lab circle on the others", "circle", true,
       motion::DriveKind::kOmni},
      {"circle, omni", "circle", false, motion::DriveKind::kOmni},
      {"gather, omni", "gather", false, motion::DriveKind::kOmni},
      {"leader_follow, omni", "leader_follow", false, motion::DriveKind::kOmni},
      {"gather, rover", "gather", false, motion::DriveKind::kWheels},
  };
#endif
  std::printf("robot tasks on Cortex-M4 soft-float, %u robots, %lld s per run; instructions per step, worst and mean "
              "over every robot's steps (sizeof(Robot) %u bytes)\n",
              unsigned{kRobots}, static_cast<long long>(kRunSeconds), static_cast<unsigned>(sizeof(runtime::Robot)));
  bool ok = true;
  for (const RunSpec& spec : runs) {
    RunStats result;
    const bool run_ok = Run(spec, result);
    ok = ok && run_ok;
    std::printf("== %s%s\n", spec.label, run_ok ? "" : " (FAILED)");
    Print("estimation.state (sensor conversion)", result.state);
    Print("estimation.kalman, predict + flow", result.kalman_plain);
    Print("estimation.kalman, with a UWB sweep", result.kalman_sweep);
    Print("estimation.kalman, least-squares fix", result.kalman_fix);
    Print("estimation.kalman, fix of a sweep with an outlier", result.kalman_fix_outlier);
    Print("estimation.kalman, sweep refused (fix failed)", result.kalman_unused);
    Print("runtime.motion (controller + safety filter)", result.motion);
    Print("runtime.round, ordinary round", result.round_ordinary);
    Print("runtime.round, epoch start (with newRound)", result.round_epoch);
    Print("  of which the app's newRound", result.new_round);
    Print("runtime.round, epoch start, robot 0 only", result.round_epoch_robot0);
    Print("  of which the app's newRound", result.new_round_robot0);
    char radio_label[64];
    std::snprintf(radio_label, sizeof radio_label, "firmware.radio, one activation (%u frames)",
                  unsigned(kRobots - 1));
    Print(radio_label, result.radio_step);
    Print("firmware.radio, one beacon frame", result.radio_frame);
    if (spec.firmware_app_everywhere) {
      // The probe's calls answered as the table says, or the counts are of something else.
      const bool has_charge = spec.inputs == Inputs::kCharge || spec.inputs == Inputs::kChargeLast;
      const bool answered = result.input_miss.count == 1 && result.input_miss_status == SYROF_APP_NO_SUCH_INPUT &&
                            result.input_charge_status == (has_charge ? SYROF_APP_OK : SYROF_APP_NO_SUCH_INPUT);
      Print("syrofAppInput, a 63-byte name not in the table", result.input_miss);
      Print(has_charge ? "syrofAppInput(\"charge\"), found" : "syrofAppInput(\"charge\"), not in the table",
            result.input_charge);
      if (!answered) {
        std::printf("  the input probe's calls did not answer as the table says (FAILED)\n");
        ok = false;
      }
    }
    std::printf("  epochs started %u (COOPERATIVE %u), beacons received %u, overflow %u, malformed %u, "
                "safety interventions %u, robots moved %u\n",
                unsigned(result.epochs), unsigned(result.cooperative), unsigned(result.received),
                unsigned(result.overflow), unsigned(result.malformed), unsigned(result.safety_interventions),
                unsigned(result.moved));
    if (result.cooperative == 0 || result.malformed != 0) ok = false;
  }
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
