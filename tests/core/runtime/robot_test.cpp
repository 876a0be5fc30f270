// The robot runtime on the simulation port: three robots whose radios hear
// each other perfectly (or not at all), apps that record their callbacks.
#include "syrof/runtime/robot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "syrof/app/c_abi_app.h"
#include "syrof/estimation/topics.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "syrof/registry/tasks.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::runtime {
namespace {

constexpr int64_t kRoundNs = 50'000'000;
constexpr uint16_t kRobots = 3;

// Records every callback; moves robot `self` to a point in each epoch and
// sends its epoch number as payload.
class RecordingApp final : public app::App {
 public:
  const char* name() const override { return "recording"; }
  app::CallStatus Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) override {
    info_ = info;
    platform_ = &platform;
    ++init_calls;
    global_state = 7;
    if (fault_on_init) return app::CallStatus::Fault(app::Verdict::kLoadFailed, "no such library");
    return app::CallStatus::Ok();
  }
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                           uint32_t clock_ms) override {
    EXPECT_EQ(command.kind, SYROF_COMMAND_STOP);
    maps.emplace_back(ldmap.members, ldmap.members + ldmap.member_count);
    modes.push_back(ldmap.mode);
    epochs.push_back(ldmap.epoch);
    clocks.push_back(clock_ms);
    states.push_back(global_state);
    const uint8_t payload[2] = {static_cast<uint8_t>(ldmap.epoch), 0xAB};
    EXPECT_EQ(platform_->SendMessageData(payload), SYROF_APP_OK);
    const uint8_t too_long[10] = {};
    EXPECT_EQ(platform_->SendMessageData(too_long), SYROF_APP_PAYLOAD_TOO_LONG);
    command.kind = SYROF_COMMAND_MOVE_TO;
    command.x_m = 1.0f;
    command.y_m = 1.0f;
    command.speed_mps = 0.2f;
    if (nan_target) command.x_m = std::numeric_limits<float>::quiet_NaN();
    global_state = static_cast<uint8_t>(global_state + 1);
    if (fault_on_new_round == maps.size()) return app::CallStatus::Fault(app::Verdict::kCrashed, "SIGSEGV");
    return app::CallStatus::Ok();
  }
  app::CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& /*global_state*/, uint32_t) override {
    end_epochs.push_back(ldmap.epoch);
    if (fault_on_end_of_round == end_epochs.size()) return app::CallStatus::Fault(app::Verdict::kTimeout, "cpu");
    return app::CallStatus::Ok();
  }

  // What to break: the n-th call (counting from 1) of a callback faults.
  bool fault_on_init = false;
  size_t fault_on_new_round = 0;
  size_t fault_on_end_of_round = 0;
  bool nan_target = false;  // newRound returns a MOVE_TO to x = NaN
  int init_calls = 0;

  syrof_app_info info_{};
  app::Platform* platform_ = nullptr;
  std::vector<std::vector<syrof_member_state>> maps;
  std::vector<uint8_t> modes;
  std::vector<uint16_t> epochs;
  std::vector<uint32_t> clocks;
  std::vector<uint8_t> states;
  std::vector<uint16_t> end_epochs;
};

// Records what the robots report.
class RecordingObserver final : public RobotObserver {
 public:
  struct Fault {
    uint16_t robot;
    int64_t now_ns;
    app::Callback callback;
    uint16_t epoch;
    app::CallStatus status;
  };
  struct Report {
    uint16_t robot;
    uint16_t epoch;
    std::string what;
  };
  void OnEpochStart(uint16_t, int64_t, const sync::LDMap&) override {}
  void OnMembership(uint16_t robot, int64_t, const wire::MemberSet& removed, const wire::MemberSet&) override {
    for (const uint16_t member : removed) removals.emplace_back(robot, member);
  }
  void OnBecameJoiner(uint16_t, int64_t) override {}
  void OnAppFault(uint16_t robot, int64_t now_ns, app::Callback callback, uint16_t epoch,
                  const app::CallStatus& status) override {
    faults.push_back({robot, now_ns, callback, epoch, status});
  }
  void OnInvalidCommand(uint16_t robot, int64_t, uint16_t epoch, const app::CommandCheck& check) override {
    std::array<char, 64> text{};
    invalid_commands.push_back({robot, epoch, app::Describe(check, text.data(), text.size())});
  }
  void OnPayloadRefused(uint16_t robot, int64_t, uint16_t epoch, size_t length) override {
    refused_payloads.push_back({robot, epoch, std::to_string(length)});
  }

  std::vector<Fault> faults;
  std::vector<Report> invalid_commands;
  std::vector<Report> refused_payloads;
  std::vector<std::pair<uint16_t, uint16_t>> removals;  // (robot, removed member)
};

class Swarm;

// Delivers each broadcast as bytes to every other robot unless cut off.
class TestRadio final : public Radio {
 public:
  TestRadio(Swarm& swarm, uint16_t id) : swarm_(swarm), id_(id) {}
  void Broadcast(const wire::Beacon& beacon) override;

 private:
  Swarm& swarm_;
  uint16_t id_;
};

struct TestRobot {
  TestRobot(os::SimScheduler& scheduler, const RobotConfig& config, app::App& app, Swarm& swarm)
      : port(scheduler, "robot"), broker(port), radio(swarm, config.sync.self_id), robot(config, app, radio, storage) {}
  os::SimPort port;
  pubsub::StaticBroker<8, 12> broker;
  // The sensor topics exist but stay silent: the estimator predicts from the
  // known start pose.
  pubsub::Publisher<estimation::ImuReading> imu;
  pubsub::Publisher<estimation::FlowReading> flow;
  pubsub::Publisher<estimation::UwbReading> uwb;
  TestRadio radio;
  std::array<wire::Beacon, Robot::kReceiveBanks * kRobots> storage{};  // a round's worth per bank
  Robot robot;
};

class Swarm {
 public:
  explicit Swarm(std::vector<app::App*> apps, RobotObserver* observer = nullptr,
                 const sync::ActivationConfig& activation = {})
      : scheduler_(64), air_(scheduler_, "air"), delivery_(*this) {
    EXPECT_TRUE(air_.AddTask(delivery_, {"air.delivery", os::Trigger::periodic(kRoundNs, kRoundNs),
                                         registry::kRadioDeliveryPriority})
                    .ok());
    EXPECT_EQ(air_.Start(), os::PortError::kOk);
    for (uint16_t id = 0; id < kRobots; ++id) {
      RobotConfig config;
      config.sync = sync::SyncConfig::ForSwarm(kRobots, id);
      config.radio_round_ns = kRoundNs;
      config.maneuver_rounds = 4;
      config.initial_pose.x_m = 0.5f + static_cast<float>(id);
      config.initial_pose.y_m = 0.5f;
      config.activation = activation;
      robots_.push_back(std::make_unique<TestRobot>(scheduler_, config, *apps[id], *this));
    }
    for (auto& robot : robots_) {
      EXPECT_EQ(robot->imu.Advertise(robot->broker, estimation::kImuTopic), pubsub::BrokerError::kOk);
      EXPECT_EQ(robot->flow.Advertise(robot->broker, estimation::kFlowTopic), pubsub::BrokerError::kOk);
      EXPECT_EQ(robot->uwb.Advertise(robot->broker, estimation::kUwbTopic), pubsub::BrokerError::kOk);
      robot->robot.set_observer(observer);
      EXPECT_EQ(robot->robot.Attach(robot->port, robot->broker), RobotSetupError::kOk);
    }
    for (auto& robot : robots_) EXPECT_EQ(robot->port.Start(), os::PortError::kOk);
  }

  // A beacon broadcast at the end of a round travels during the next one.
  void Send(uint16_t from, const wire::Beacon& beacon) {
    Frame& frame = pending_[from];
    const auto size = wire::Encode(beacon, kRobots, frame.bytes);
    ASSERT_TRUE(size.ok());
    frame.size = size.value();
  }

  // Runs at each round's end, before the round tasks (priority order).
  void Deliver() {
    for (uint16_t from = 0; from < kRobots; ++from) {
      Frame& frame = pending_[from];
      if (frame.size == 0) continue;
      for (uint16_t to = 0; to < kRobots; ++to) {
        if (to == from || silenced[to] || silenced[from]) continue;
        robots_[to]->robot.ReceiveBytes(std::span<const uint8_t>(frame.bytes.data(), frame.size));
      }
      frame.size = 0;
    }
  }

  void RunFor(int64_t duration_ns) { scheduler_.RunFor(duration_ns); }
  Robot& robot(uint16_t id) { return robots_[id]->robot; }
  std::array<bool, kRobots> silenced{};

 private:
  struct Frame {
    std::array<uint8_t, wire::kMaxBeaconBytes> bytes{};
    size_t size = 0;
  };
  class DeliveryTask final : public os::Task {
   public:
    explicit DeliveryTask(Swarm& swarm) : swarm_(swarm) {}
    void Step(int64_t) override { swarm_.Deliver(); }

   private:
    Swarm& swarm_;
  };

  os::SimScheduler scheduler_;
  os::SimPort air_;
  DeliveryTask delivery_;
  std::array<Frame, kRobots> pending_{};
  std::vector<std::unique_ptr<TestRobot>> robots_;
};

void TestRadio::Broadcast(const wire::Beacon& beacon) { swarm_.Send(id_, beacon); }

TEST(RobotTest, InitReceivesTheRobotsFacts) {
  RecordingApp a, b, c;
  Swarm swarm({&a, &b, &c});

  EXPECT_EQ(b.info_.abi_version, SYROF_APP_ABI_VERSION);
  EXPECT_EQ(b.info_.self_id, 1);
  EXPECT_EQ(b.info_.swarm_size, kRobots);
  EXPECT_EQ(b.info_.radio_round_ms, 50u);
  EXPECT_EQ(b.info_.maneuver_ms, 200u);
  EXPECT_EQ(swarm.robot(1).global_state(), 7);
}

TEST(RobotTest, EveryRobotStartsEveryEpochCooperativeWithTheSameMap) {
  RecordingApp a, b, c;
  Swarm swarm({&a, &b, &c});

  swarm.RunFor(5'000'000'000);

  ASSERT_GE(a.maps.size(), 10u);
  for (const RecordingApp* app : {&b, &c}) {
    ASSERT_EQ(app->maps.size(), a.maps.size());
    for (size_t epoch = 0; epoch < a.maps.size(); ++epoch) {
      ASSERT_EQ(app->maps[epoch].size(), kRobots);
      EXPECT_EQ(app->modes[epoch], SYROF_MODE_COOPERATIVE);
      EXPECT_EQ(app->epochs[epoch], a.epochs[epoch]);
      EXPECT_EQ(app->clocks[epoch], a.clocks[epoch]);
      for (size_t i = 0; i < kRobots; ++i) {
        EXPECT_EQ(app->maps[epoch][i].id, i);
        EXPECT_EQ(app->maps[epoch][i].x_mm, a.maps[epoch][i].x_mm);
        EXPECT_EQ(app->maps[epoch][i].payload_length, a.maps[epoch][i].payload_length);
      }
    }
  }
}

TEST(RobotTest, PayloadFromNewRoundArrivesInTheNextMap) {
  RecordingApp a, b, c;
  Swarm swarm({&a, &b, &c});

  swarm.RunFor(3'000'000'000);

  ASSERT_GE(a.maps.size(), 3u);
  EXPECT_EQ(a.maps[0][2].payload_length, 0);  // the initial map: nothing sent yet
  const syrof_member_state& later = a.maps[2][2];
  EXPECT_EQ(later.payload_length, 2);
  EXPECT_EQ(later.payload[0], static_cast<uint8_t>(a.epochs[1]));
  EXPECT_EQ(later.payload[1], 0xAB);
  EXPECT_EQ(swarm.robot(0).counters().payloads_refused, a.maps.size());
}

TEST(RobotTest, EndOfRoundFollowsEachManeuverAndGlobalStateThreads) {
  RecordingApp a, b, c;
  Swarm swarm({&a, &b, &c});

  swarm.RunFor(3'000'000'000);

  ASSERT_GE(a.end_epochs.size(), 2u);
  for (size_t i = 0; i < a.end_epochs.size(); ++i) EXPECT_EQ(a.end_epochs[i], a.epochs[i]);
  for (size_t i = 0; i < a.states.size(); ++i) EXPECT_EQ(a.states[i], 7 + i);
  // The maneuver lasts maneuver_rounds: consecutive newRound calls are at
  // least that far apart, plus WAIT and K vote rounds.
  for (size_t i = 1; i < a.clocks.size(); ++i) EXPECT_GE(a.clocks[i] - a.clocks[i - 1], 200u + 3 * 50u);
}

TEST(RobotTest, UnderRoundRobinOneRobotAnEpochGetsNewRoundAndEndOfRound) {
  RecordingApp a, b, c;
  sync::ActivationConfig activation;
  activation.model = sync::ActivationModel::kSsync;
  activation.schedule = sync::ActivationSchedule::kRoundRobin;
  Swarm swarm({&a, &b, &c}, nullptr, activation);

  swarm.RunFor(4'000'000'000);

  std::vector<uint16_t> all;
  for (const RecordingApp* app : {&a, &b, &c}) {
    // endOfRound only after its own newRound (the last maneuver may still run).
    ASSERT_LE(app->end_epochs.size(), app->epochs.size());
    for (size_t i = 0; i < app->end_epochs.size(); ++i) EXPECT_EQ(app->end_epochs[i], app->epochs[i]);
    all.insert(all.end(), app->epochs.begin(), app->epochs.end());
  }
  std::sort(all.begin(), all.end());
  ASSERT_GE(all.size(), 4u);
  // Each epoch went to exactly one robot: the member at epoch mod 3.
  for (size_t i = 1; i < all.size(); ++i) EXPECT_EQ(all[i], all[i - 1] + 1);
  for (const uint16_t epoch : a.epochs) EXPECT_EQ(epoch % 3, 0);
  for (const uint16_t epoch : b.epochs) EXPECT_EQ(epoch % 3, 1);
  uint32_t inactive = 0;
  for (uint16_t id = 0; id < 3; ++id) inactive += swarm.robot(id).counters().inactive_epochs;
  EXPECT_EQ(inactive, 2 * all.size());
}

TEST(RobotTest, CommandGoesToTheControllerAndStopsWhenTheManeuverEnds) {
  RecordingApp a, b, c;
  Swarm swarm({&a, &b, &c});

  swarm.RunFor(1'000'000'000);
  bool saw_move = false;
  bool saw_stop_after = false;
  for (int i = 0; i < 40; ++i) {
    swarm.RunFor(kRoundNs);
    const uint8_t kind = swarm.robot(0).command().kind;
    if (kind == SYROF_COMMAND_MOVE_TO) saw_move = true;
    if (saw_move && kind == SYROF_COMMAND_STOP) saw_stop_after = true;
  }

  EXPECT_TRUE(saw_move);
  EXPECT_TRUE(saw_stop_after);
}

TEST(RobotTest, SilencedRobotIsRemovedAndTheOthersGoOn) {
  RecordingApp a, b, c;
  Swarm swarm({&a, &b, &c});
  swarm.RunFor(1'000'000'000);

  swarm.silenced[2] = true;
  swarm.RunFor(4'000'000'000);

  const sync::SyncState& state = swarm.robot(0).sync_state();
  EXPECT_FALSE(state.members.test(2));
  EXPECT_EQ(a.maps.back().size(), 2u);
  EXPECT_EQ(a.modes.back(), SYROF_MODE_COOPERATIVE);  // 2 of 3 is a majority
}

TEST(RobotTest, MalformedFramesAreCountedAndDropped) {
  RecordingApp a, b, c;
  Swarm swarm({&a, &b, &c});
  const std::array<uint8_t, 5> garbage{1, 2, 3, 4, 5};

  swarm.robot(0).ReceiveBytes(garbage);
  swarm.RunFor(1'000'000'000);

  EXPECT_EQ(swarm.robot(0).counters().beacons_malformed, 1u);
  EXPECT_GE(a.maps.size(), 1u);
}

// ---- Apps that fail ---------------------------------------------------------

TEST(RobotAppFaultTest, ARobotWhoseNewRoundFaultedStopsAndTheOthersRemoveIt) {
  // Arrange: robot 2's third newRound crashes.
  RecordingApp a, b, c;
  c.fault_on_new_round = 3;
  RecordingObserver observer;
  Swarm swarm({&a, &b, &c}, &observer);

  // Act
  swarm.RunFor(3'000'000'000);
  const uint32_t beacons_at_fault = swarm.robot(2).counters().beacons_sent;
  const size_t calls_at_fault = c.maps.size() + c.end_epochs.size();
  swarm.RunFor(4'000'000'000);

  // Assert: reported once, with the epoch and the verdict.
  ASSERT_EQ(observer.faults.size(), 1u);
  const RecordingObserver::Fault& fault = observer.faults[0];
  EXPECT_EQ(fault.robot, 2);
  EXPECT_EQ(fault.callback, app::Callback::kNewRound);
  EXPECT_EQ(fault.epoch, c.epochs[2]);
  EXPECT_EQ(fault.status.verdict(), app::Verdict::kCrashed);
  EXPECT_STREQ(fault.status.detail(), "SIGSEGV");
  // No more calls, no more beacons, STOP.
  EXPECT_EQ(c.maps.size(), 3u);
  EXPECT_EQ(c.maps.size() + c.end_epochs.size(), calls_at_fault);
  EXPECT_EQ(swarm.robot(2).counters().beacons_sent, beacons_at_fault);
  EXPECT_TRUE(swarm.robot(2).app_faulted());
  EXPECT_EQ(swarm.robot(2).command().kind, SYROF_COMMAND_STOP);
  // The others' failure detectors removed it and they go on.
  EXPECT_FALSE(swarm.robot(0).sync_state().members.test(2));
  EXPECT_FALSE(swarm.robot(1).sync_state().members.test(2));
  EXPECT_EQ(a.maps.back().size(), 2u);
  EXPECT_GT(a.maps.size(), 4u);
}

TEST(RobotAppFaultTest, AnInitFaultLeavesARobotThatNeverBeacons) {
  RecordingApp a, b, c;
  c.fault_on_init = true;
  RecordingObserver observer;
  Swarm swarm({&a, &b, &c}, &observer);

  swarm.RunFor(4'000'000'000);

  ASSERT_EQ(observer.faults.size(), 1u);
  EXPECT_EQ(observer.faults[0].robot, 2);
  EXPECT_EQ(observer.faults[0].callback, app::Callback::kInit);
  EXPECT_EQ(observer.faults[0].epoch, 0);
  EXPECT_EQ(observer.faults[0].status.verdict(), app::Verdict::kLoadFailed);
  EXPECT_EQ(c.init_calls, 1);
  EXPECT_TRUE(c.maps.empty());
  EXPECT_EQ(swarm.robot(2).counters().beacons_sent, 0u);
  EXPECT_FALSE(swarm.robot(0).sync_state().members.test(2));
}

TEST(RobotAppFaultTest, AnEndOfRoundFaultStopsTheRobotBeforeItsNextEpoch) {
  RecordingApp a, b, c;
  c.fault_on_end_of_round = 2;
  RecordingObserver observer;
  Swarm swarm({&a, &b, &c}, &observer);

  swarm.RunFor(5'000'000'000);

  ASSERT_EQ(observer.faults.size(), 1u);
  EXPECT_EQ(observer.faults[0].callback, app::Callback::kEndOfRound);
  EXPECT_EQ(observer.faults[0].epoch, c.end_epochs[1]);
  EXPECT_EQ(observer.faults[0].status.verdict(), app::Verdict::kTimeout);
  EXPECT_EQ(c.maps.size(), 2u);  // no newRound after the fault
  EXPECT_EQ(c.end_epochs.size(), 2u);
  EXPECT_FALSE(swarm.robot(0).sync_state().members.test(2));
}

TEST(RobotAppFaultTest, AnInvalidCommandIsCountedReportedAndReplacedByStop) {
  RecordingApp a, b, c;
  a.nan_target = true;
  RecordingObserver observer;
  Swarm swarm({&a, &b, &c}, &observer);
  swarm.RunFor(1'000'000'000);
  bool saw_move = false;

  for (int i = 0; i < 40; ++i) {
    swarm.RunFor(kRoundNs);
    if (swarm.robot(0).command().kind != SYROF_COMMAND_STOP) saw_move = true;
  }

  EXPECT_FALSE(saw_move);
  ASSERT_FALSE(a.maps.empty());
  EXPECT_EQ(swarm.robot(0).counters().invalid_commands, a.maps.size());
  EXPECT_EQ(swarm.robot(1).counters().invalid_commands, 0u);
  ASSERT_EQ(observer.invalid_commands.size(), a.maps.size());
  EXPECT_EQ(observer.invalid_commands[0].robot, 0);
  EXPECT_EQ(observer.invalid_commands[0].epoch, a.epochs[0]);
  EXPECT_EQ(observer.invalid_commands[0].what, "MOVE_TO x_m is not finite");
  EXPECT_TRUE(observer.faults.empty());  // an invalid command is no fault: the app goes on
}

TEST(RobotAppFaultTest, ARefusedPayloadIsCountedAndReportedWithItsEpoch) {
  // RecordingApp sends 10 bytes in every newRound.
  RecordingApp a, b, c;
  RecordingObserver observer;
  Swarm swarm({&a, &b, &c}, &observer);

  swarm.RunFor(3'000'000'000);

  ASSERT_FALSE(a.maps.empty());
  EXPECT_EQ(swarm.robot(0).counters().payloads_refused, a.maps.size());
  ASSERT_EQ(observer.refused_payloads.size(), a.maps.size() + b.maps.size() + c.maps.size());
  EXPECT_EQ(observer.refused_payloads[0].epoch, a.epochs[0]);
  EXPECT_EQ(observer.refused_payloads[0].what, "10");
}

// ---- A C app through the ABI ---------------------------------------------

// A C app has only globals; the fixture resets them before each test, so the
// counts are this test's alone (also under --gtest_repeat).
uint8_t c_init_calls = 0;
uint8_t c_new_rounds = 0;
int c_send_status = -1;

class CAppRobotTest : public ::testing::Test {
 protected:
  void SetUp() override {
    c_init_calls = 0;
    c_new_rounds = 0;
    c_send_status = -1;
  }
};

uint8_t CInit(const syrof_app_info* info) {
  ++c_init_calls;
  return static_cast<uint8_t>(info->self_id);
}
uint8_t CNewRound(syrof_car_command* command, const syrof_ldmap* ldmap, uint8_t global_state, uint32_t) {
  ++c_new_rounds;
  const uint8_t payload[3] = {1, 2, static_cast<uint8_t>(ldmap->self_id)};
  c_send_status = sendMessageData(payload, sizeof payload);
  command->kind = SYROF_COMMAND_STOP;
  return global_state;
}
uint8_t CEndOfRound(const syrof_ldmap*, uint8_t global_state, uint32_t) { return global_state; }

const syrof_app_descriptor kCApp = {SYROF_APP_ABI_VERSION, "c_test", CInit, CNewRound, CEndOfRound};

TEST_F(CAppRobotTest, CAppsSendOnTheirOwnRobot) {
  app::CAbiApp a(kCApp), b(kCApp), c(kCApp);
  Swarm swarm({&a, &b, &c});

  swarm.RunFor(3'000'000'000);

  EXPECT_EQ(c_init_calls, 3);
  EXPECT_GE(c_new_rounds, 6);
  EXPECT_EQ(c_send_status, SYROF_APP_OK);
  EXPECT_EQ(swarm.robot(2).global_state(), 2);
  const sync::LDMap& map = swarm.robot(0).ldmap();
  for (uint16_t id = 0; id < kRobots; ++id) {
    EXPECT_EQ(map.snapshots[id].payload_length, 3);
    EXPECT_EQ(map.snapshots[id].payload[2], id);
  }
  EXPECT_EQ(sendMessageData(nullptr, 0), SYROF_APP_NOT_RUNNING);  // outside a callback
}

}  // namespace
}  // namespace syrof::runtime
