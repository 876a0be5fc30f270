#include "demo.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <ostream>
#include <random>

#include "syrof/os/sim_port.h"
#include "syrof/pubsub/topic.h"
#include "syrof/wire/beacon_codec.h"
#include "syrof/wire/fixed_point.h"

namespace syrof::lab::demo {
namespace {

// ---- Topics: one definition each, with units -------------------------------

/// The robot's pose; in the demo, ground truth from a scripted circle (the
/// estimator's output takes its place when the estimation issue lands).
struct Pose {
  int64_t time_ns;
  float x_m, y_m;      // arena frame, metres
  float heading_rad;   // counter-clockwise from +x
  float vx_m_s, vy_m_s;
};

/// Bytes the radio received in one frame.
struct RadioFrame {
  uint8_t length;
  std::array<uint8_t, wire::kMaxBeaconBytes> bytes;
};

/// A beacon that decoded, with when it arrived.
struct NeighbourHeard {
  int64_t time_ns;
  wire::Beacon beacon;
};

constexpr pubsub::Topic<Pose> kPoseTopic{1, "pose"};
constexpr pubsub::Topic<RadioFrame> kRadioRxTopic{2, "radio_rx"};
constexpr pubsub::Topic<NeighbourHeard> kNeighbourTopic{3, "neighbour"};

// Task priorities and rates in one place (higher runs first at an instant).
constexpr uint8_t kMotionPriority = 3;
constexpr uint8_t kBeaconTxPriority = 2;
constexpr uint8_t kBeaconRxPriority = 1;
constexpr uint8_t kNeighbourTablePriority = 0;
constexpr int kTasksPerRobot = 4;

double Seconds(int64_t ns) { return static_cast<double>(ns) * 1e-9; }
int RoundOf(int64_t ns) { return static_cast<int>(ns / kRadioRoundNs); }

class Robot;

// ---- The radio channel ----------------------------------------------------

/// Delivers each broadcast to every other robot unless a seeded draw loses
/// it. Delivery is at the instant of sending; the receiver's radio driver
/// publishes the frame on its own broker.
class Channel {
 public:
  Channel(double loss, uint32_t seed) : loss_(loss), random_(seed) {}
  void Attach(Robot& robot) { robots_.push_back(&robot); }
  void Broadcast(int sender, std::span<const uint8_t> bytes);
  /// A frame from outside the swarm (another radio's bytes), heard by all.
  void Inject(std::span<const uint8_t> bytes);

 private:
  double loss_;
  std::mt19937 random_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::vector<Robot*> robots_;
};

// ---- One robot: its port, broker and tasks --------------------------------

/// Where robot `id` of `robots` is at `time_ns`: each follows its own circle,
/// alternate robots in opposite directions.
Pose ScriptedPose(int id, int robots, int64_t time_ns) {
  const double phase = 2.0 * std::numbers::pi * id / robots;
  const double centre_x = 2.0 + 1.2 * std::cos(phase);
  const double centre_y = 2.0 + 1.2 * std::sin(phase);
  const double radius = 0.3 + 0.05 * id;
  const double angular_speed = (id % 2 == 0 ? 1.0 : -1.0) * 0.8;  // rad/s
  const double angle = angular_speed * Seconds(time_ns);
  Pose pose{};
  pose.time_ns = time_ns;
  pose.x_m = static_cast<float>(centre_x + radius * std::cos(angle));
  pose.y_m = static_cast<float>(centre_y + radius * std::sin(angle));
  pose.vx_m_s = static_cast<float>(-radius * angular_speed * std::sin(angle));
  pose.vy_m_s = static_cast<float>(radius * angular_speed * std::cos(angle));
  pose.heading_rad = std::atan2(pose.vy_m_s, pose.vx_m_s);
  return pose;
}

/// Moves the robot along its scripted circle and publishes its pose.
class MotionTask final : public os::Task {
 public:
  MotionTask(int id, int robots) : id_(id), robots_(robots) {}
  void Step(int64_t now_ns) override { (void)pose_out.Publish(ScriptedPose(id_, robots_, now_ns)); }
  pubsub::Publisher<Pose> pose_out;

 private:
  int id_;
  int robots_;
};

/// Every radio round: the latest pose into a beacon, encoded, broadcast.
class BeaconTxTask final : public os::Task {
 public:
  BeaconTxTask(int id, Channel& channel, std::ostream& out) : id_(id), channel_(channel), out_(out) {}
  void Step(int64_t now_ns) override;
  pubsub::Subscriber<Pose> pose_in;
  int sent = 0;

 private:
  int id_;
  Channel& channel_;
  std::ostream& out_;
  Pose pose_{};
};

/// Decodes every frame the radio received; publishes the beacons that decode.
class BeaconRxTask final : public os::Task {
 public:
  explicit BeaconRxTask(RobotReport& report, std::ostream& out, int id) : report_(report), out_(out), id_(id) {}
  void Step(int64_t now_ns) override {
    RadioFrame frame{};
    while (frames_in.Take(frame)) {
      const auto beacon = wire::Decode(std::span(frame.bytes.data(), frame.length), kDemoSwarmSize);
      if (!beacon) {
        ++report_.frames_rejected;
        report_.rejection_reasons.emplace_back(wire::ToString(beacon.error()));
        fmt::print(out_, "  t={:.3f} s  robot {} rejects a {}-byte frame: {}\n", Seconds(now_ns), id_,
                   frame.length, wire::ToString(beacon.error()));
        continue;
      }
      (void)heard_out.Publish(NeighbourHeard{now_ns, beacon.value()});
    }
  }
  pubsub::Subscriber<RadioFrame, 8> frames_in;
  pubsub::Publisher<NeighbourHeard> heard_out;

 private:
  RobotReport& report_;
  std::ostream& out_;
  int id_;
};

/// Keeps the neighbour table: who was heard in which round, and where. Each
/// position heard is compared with where the sender truly was when it sent
/// (beacons arrive in the round they are sent).
class NeighbourTableTask final : public os::Task {
 public:
  NeighbourTableTask(RobotReport& report, int robots) : report_(report), robots_(robots) {}
  void Step(int64_t) override {
    NeighbourHeard heard{};
    while (heard_in.Take(heard)) {
      ++report_.beacons_received;
      const Pose truth = ScriptedPose(heard.beacon.robot_id, robots_, heard.time_ns);
      const double error_m = std::hypot(wire::ToMetres(heard.beacon.x_mm) - truth.x_m,
                                        wire::ToMetres(heard.beacon.y_mm) - truth.y_m);
      report_.largest_position_error_m = std::max(report_.largest_position_error_m, error_m);
      const int round = RoundOf(heard.time_ns);
      if (static_cast<int>(heard_by_round.size()) <= round) heard_by_round.resize(round + 1, 0);
      heard_by_round[round] |= 1u << heard.beacon.robot_id;
      last_heard[heard.beacon.robot_id] = heard.beacon;
    }
  }
  pubsub::Subscriber<NeighbourHeard, 8> heard_in;
  std::vector<uint32_t> heard_by_round;  // bit j: robot j heard in that round
  std::array<wire::Beacon, kMaxDemoRobots> last_heard{};

 private:
  RobotReport& report_;
  int robots_;
};

class Robot {
 public:
  Robot(int id, int robots, os::SimScheduler& scheduler, Channel& channel, std::ostream& out)
      : id_(id),
        name_(fmt::format("robot {}", id)),
        port_(scheduler, name_.c_str()),
        broker_(port_),
        motion_(id, robots),
        beacon_tx_(id, channel, out),
        beacon_rx_(report, out, id),
        neighbours_(report, robots) {}

  /// Declares the tasks and wires the topics (start-up; nothing after this
  /// allocates). Returns false, printing why, on any error.
  bool Wire(std::ostream& out) {
    const auto motion = port_.AddTask(motion_, {"motion", os::Trigger::periodic(kMotionPeriodNs), kMotionPriority});
    const auto tx = port_.AddTask(beacon_tx_, {"beacon_tx", os::Trigger::periodic(kRadioRoundNs), kBeaconTxPriority});
    const auto rx = port_.AddTask(beacon_rx_, {"beacon_rx", os::Trigger::notified(), kBeaconRxPriority});
    const auto table = port_.AddTask(neighbours_, {"neighbours", os::Trigger::notified(), kNeighbourTablePriority});
    if (!motion || !tx || !rx || !table) {
      fmt::print(out, "robot {}: cannot add its tasks\n", id_);
      return false;
    }
    const pubsub::BrokerError errors[] = {
        motion_.pose_out.Advertise(broker_, kPoseTopic),
        radio_rx_out_.Advertise(broker_, kRadioRxTopic),
        beacon_rx_.heard_out.Advertise(broker_, kNeighbourTopic),
        beacon_tx_.pose_in.Subscribe(broker_, kPoseTopic, tx.value()),
        beacon_rx_.frames_in.Subscribe(broker_, kRadioRxTopic, rx.value()),
        neighbours_.heard_in.Subscribe(broker_, kNeighbourTopic, table.value()),
    };
    for (const pubsub::BrokerError error : errors) {
      if (error != pubsub::BrokerError::kOk) {
        fmt::print(out, "robot {}: broker error: {}\n", id_, pubsub::ToString(error));
        return false;
      }
    }
    return port_.Start() == os::PortError::kOk;
  }

  /// The radio driver's side: a frame arrived.
  void Receive(std::span<const uint8_t> bytes) {
    RadioFrame frame{};
    frame.length = static_cast<uint8_t>(std::min(bytes.size(), frame.bytes.size()));
    std::copy_n(bytes.begin(), frame.length, frame.bytes.begin());
    (void)radio_rx_out_.Publish(frame);
  }

  int id() const { return id_; }
  int beacons_sent() const { return beacon_tx_.sent; }
  const NeighbourTableTask& neighbours() const { return neighbours_; }
  RobotReport report;

 private:
  int id_;
  std::string name_;
  os::SimPort port_;
  pubsub::StaticBroker<3, 3> broker_;
  MotionTask motion_;
  BeaconTxTask beacon_tx_;
  BeaconRxTask beacon_rx_;
  NeighbourTableTask neighbours_;
  pubsub::Publisher<RadioFrame> radio_rx_out_;
};

void Channel::Broadcast(int sender, std::span<const uint8_t> bytes) {
  for (Robot* robot : robots_) {
    if (robot->id() == sender) continue;
    if (uniform_(random_) < loss_) {
      ++robot->report.beacons_lost;
      continue;
    }
    robot->Receive(bytes);
  }
}

void Channel::Inject(std::span<const uint8_t> bytes) {
  for (Robot* robot : robots_) robot->Receive(bytes);
}

std::string Hex(std::span<const uint8_t> bytes) {
  std::string text;
  for (const uint8_t byte : bytes) text += fmt::format("{:02x} ", byte);
  if (!text.empty()) text.pop_back();
  return text;
}

void BeaconTxTask::Step(int64_t now_ns) {
  (void)pose_in.TakeLatest(pose_);  // keeps the previous pose if none is new
  const int round = RoundOf(now_ns);
  wire::Beacon beacon;
  beacon.robot_id = static_cast<uint16_t>(id_);
  beacon.epoch = static_cast<uint16_t>(round / 20);  // one "maneuver" per second
  beacon.phase = wire::Phase::kProgress;
  beacon.mode = wire::Mode::kCooperative;
  beacon.x_mm = wire::ToMillimetres(pose_.x_m);
  beacon.y_mm = wire::ToMillimetres(pose_.y_m);
  beacon.heading_mrad = wire::ToMilliradians(pose_.heading_rad);
  beacon.vx_mm_s = wire::ToMillimetresPerSecond(pose_.vx_m_s);
  beacon.vy_mm_s = wire::ToMillimetresPerSecond(pose_.vy_m_s);
  const std::array<uint8_t, 3> payload{'h', 'i', static_cast<uint8_t>('0' + id_)};
  (void)beacon.SetPayload(payload);

  std::array<uint8_t, wire::kMaxBeaconBytes> bytes{};
  const auto size = wire::Encode(beacon, kDemoSwarmSize, bytes);
  if (!size) {
    fmt::print(out_, "  robot {} cannot encode its beacon: {}\n", id_, wire::ToString(size.error()));
    return;
  }
  if (sent == 0 && id_ == 0) {
    fmt::print(out_, "robot 0's first beacon, {} bytes on the wire:\n  {}\n", size.value(),
               Hex(std::span(bytes.data(), size.value())));
    fmt::print(out_, "  = robot {} epoch {} {} {} at ({:.3f}, {:.3f}) m heading {:.3f} rad, payload \"hi0\"\n\n",
               beacon.robot_id, beacon.epoch, wire::ToString(beacon.phase), wire::ToString(beacon.mode),
               wire::ToMetres(beacon.x_mm), wire::ToMetres(beacon.y_mm), wire::ToRadians(beacon.heading_mrad));
  }
  ++sent;
  channel_.Broadcast(id_, std::span(bytes.data(), size.value()));
}

// Injects malformed frames halfway through: what a radio may pick up from
// another swarm running an older format, or a frame cut short.
class ForeignRadioTask final : public os::Task {
 public:
  explicit ForeignRadioTask(Channel& channel, std::ostream& out) : channel_(channel), out_(out) {}
  void Step(int64_t now_ns) override {
    if (done_) return;
    done_ = true;
    fmt::print(out_, "  t={:.3f} s  a foreign radio sends a beacon of format version 2, then a truncated one:\n",
               Seconds(now_ns));
    std::array<uint8_t, wire::kMaxBeaconBytes> bytes{};
    wire::Beacon beacon;
    beacon.robot_id = 1;
    const size_t size = wire::Encode(beacon, kDemoSwarmSize, bytes).value();
    bytes[0] = 2;
    channel_.Inject(std::span(bytes.data(), size));
    bytes[0] = wire::kBeaconVersion;
    channel_.Inject(std::span(bytes.data(), size - 5));
  }

 private:
  Channel& channel_;
  std::ostream& out_;
  bool done_ = false;
};

}  // namespace

std::string Validate(const DemoOptions& options) {
  if (options.robots < 2 || options.robots > kMaxDemoRobots) {
    return fmt::format("--robots must be 2 .. {}, not {}", kMaxDemoRobots, options.robots);
  }
  if (!(options.seconds > 0.0) || options.seconds > 3600.0) {
    return fmt::format("--seconds must be above 0 and at most 3600, not {}", options.seconds);
  }
  if (!(options.loss >= 0.0 && options.loss <= 1.0)) {
    return fmt::format("--loss must be a probability in 0 .. 1, not {}", options.loss);
  }
  return {};
}

DemoReport RunDemo(const DemoOptions& options, std::ostream& out) {
  SYROF_CHECK(Validate(options).empty());
  const auto end_ns = static_cast<int64_t>(std::llround(options.seconds * 1e9));

  os::SimScheduler scheduler(static_cast<size_t>(options.robots * kTasksPerRobot + 1));
  Channel channel(options.loss, options.seed);
  std::vector<std::unique_ptr<Robot>> robots;
  for (int id = 0; id < options.robots; ++id) {
    robots.push_back(std::make_unique<Robot>(id, options.robots, scheduler, channel, out));
    channel.Attach(*robots.back());
  }

  fmt::print(out, "SyROF foundation demo: {} robots, {:.2f} s of virtual time, {:.0f}% beacon loss, seed {}\n",
             options.robots, options.seconds, options.loss * 100.0, options.seed);
  fmt::print(out,
             "Each robot runs 4 tasks on its own simulation port and broker:\n"
             "  motion      every {} ms  publishes pose\n"
             "  beacon_tx   every {} ms  takes the latest pose, encodes a beacon, broadcasts it\n"
             "  beacon_rx   notified     decodes received frames, publishes neighbour beacons\n"
             "  neighbours  notified     keeps the neighbour table\n\n",
             kMotionPeriodNs / 1'000'000, kRadioRoundNs / 1'000'000);

  for (auto& robot : robots) {
    if (!robot->Wire(out)) return {};
  }
  os::SimPort outside(scheduler, "foreign radio");
  ForeignRadioTask foreign(channel, out);
  (void)outside.AddTask(foreign, {"foreign", os::Trigger::periodic(end_ns, end_ns / 2 + 1), 0});
  (void)outside.Start();

  scheduler.RunUntil(end_ns);

  DemoReport report;
  report.radio_rounds = RoundOf(end_ns) + 1;
  report.beacon_bytes = static_cast<int>(wire::EncodedSize(kDemoSwarmSize));
  report.steps_run = scheduler.steps_run();

  for (auto& robot : robots) {
    robot->report.beacons_sent = robot->beacons_sent();
    report.robots.push_back(robot->report);
  }

  if (options.show_rounds) {
    fmt::print(out, "\nround  time    who heard whom this round ('.' = beacon lost)\n");
    for (int round = 0; round < report.radio_rounds; ++round) {
      std::string line = fmt::format("{:5}  {:.2f}s ", round, Seconds(round * kRadioRoundNs));
      for (const auto& robot : robots) {
        const auto& heard = robot->neighbours().heard_by_round;
        const uint32_t bits = round < static_cast<int>(heard.size()) ? heard[round] : 0;
        line += fmt::format("  r{}<", robot->id());
        for (int other = 0; other < options.robots; ++other) {
          if (other == robot->id()) continue;
          line += (bits >> other) & 1u ? static_cast<char>('0' + other) : '.';
        }
      }
      fmt::print(out, "{}\n", line);
    }
  }

  fmt::print(out, "\nrobot  sent  received  lost  rejected  worst error  last heard of each neighbour (x, y in m)\n");
  for (const auto& robot : robots) {
    const RobotReport& r = robot->report;
    std::string last;
    for (int other = 0; other < options.robots; ++other) {
      if (other == robot->id()) continue;
      const wire::Beacon& beacon = robot->neighbours().last_heard[other];
      last += fmt::format(" r{}({:.3f}, {:.3f})", other, wire::ToMetres(beacon.x_mm), wire::ToMetres(beacon.y_mm));
    }
    fmt::print(out, "{:5}  {:4}  {:8}  {:4}  {:8}  {:8.2f} mm {}\n", robot->id(), robot->beacons_sent(),
               r.beacons_received, r.beacons_lost, r.frames_rejected, r.largest_position_error_m * 1000.0, last);
  }
  fmt::print(out, "\n{} radio rounds, beacons of {} bytes (swarm of up to {}), {} task steps in virtual time.\n",
             report.radio_rounds, report.beacon_bytes, kDemoSwarmSize, report.steps_run);
  return report;
}

}  // namespace syrof::lab::demo
