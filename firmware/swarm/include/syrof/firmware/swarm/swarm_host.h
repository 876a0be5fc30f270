// syrof-firmware-swarm's host, the world side (SwarmHost below), holding
// the launcher (qemu_launcher.h) and the channel (beacon_channel.h).
#pragma once

#include <poll.h>

#include <cstdint>
#include <fstream>
#include <map>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "syrof/firmware/swarm/activation_check.h"
#include "syrof/firmware/swarm/beacon_channel.h"
#include "syrof/firmware/swarm/console_lines.h"
#include "syrof/firmware/swarm/fault_outcomes.h"
#include "syrof/firmware/swarm/fault_player.h"
#include "syrof/firmware/swarm/firmware_metrics.h"
#include "syrof/firmware/swarm/qemu_launcher.h"
#include "syrof/firmware/swarm/stress_player.h"
#include "syrof/firmware/swarm/swarm_options.h"
#include "syrof/firmware/swarm/swarm_robot.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/remote_world.h"
#include "syrof/registry/tasks.h"

namespace syrof::firmware::swarm {

// The result of a run's last checks: the lab's metrics, the firmware's own
// figures (firmware-swarm.json) and the summary's extra words.
struct RunResult {
  bool ok = true;
  lab::metrics::Metrics metrics;
  FirmwareMetrics report;
  std::string replay_problem;
};

// One run of the emulated swarm, its world side: an adapter on
// lab::sim::RemoteWorld, the world loop every runtime outside the lab shares
// (the world, the scenario's faults, the sensors, the recorder). The host
// supplies what is the firmware's: the world's clock (the host's, slowed to
// the robots' mean clock rate), the sensor links (SensorLinks below: readings
// out, drives back), the console reports read into each round, and its own
// figures (fault outcomes, firmware-swarm.json). Its rules (RemoteRules):
// every drive is taken as it arrives, a round is recorded from the world as
// it ends (no boundary truths), the console lines carry no heading, and a
// robot counts as running only while its console reports are fresh. It
// holds the launcher (qemu_launcher.h) and the channel (beacon_channel.h).
// main() calls, in order: OpenSockets, LaunchRobots, StartWorld, Step until
// Running() is false, Finish.
class SwarmHost {
 public:
  // `sinks` read the rounds as the replay gets them (the live page; as
  // sim_dds::SwarmOptions::sinks): the header in StartWorld (it names the
  // app the images said they run), a round at each round's end, the end in
  // Finish. Each outlives the host.
  SwarmHost(const Options& options, const lab::scenario::Scenario& scenario,
            std::span<lab::replay::RoundSink* const> sinks = {});
  SwarmHost(const SwarmHost&) = delete;
  SwarmHost& operator=(const SwarmHost&) = delete;

  // The socket directory, each robot's three listeners and its console log.
  bool OpenSockets();
  // One qemu per robot, joiners too, its sockets accepted, until every
  // image says it is held and which app it runs (the run's app from then
  // on; a scenario naming another gets one warning line on standard error,
  // image_app.h); false (every qemu killed) when one did not connect or say
  // so within kBootTimeoutMs, or its held line did not parse.
  bool LaunchRobots();
  // The replay and the sinks get their header, naming the images' app; the
  // world's clock starts; the player switches on the robots present at
  // start, at one instant.
  void StartWorld();
  // Whether a console is still open and the deadline has not passed.
  bool Running() const;
  // One pass of the host loop: the world's steps due, the deliveries due,
  // every robot's links, the rounds ended.
  void Step();
  // The checks and the output files; the exit status.
  int Finish();

 private:
  bool OnHostAction(const swarm::HostAction& action, int64_t at_ns);
  bool WaitUntilHeld();
  bool NameImageApp();
  int64_t WaitForLinks();
  void AdvanceWorld(int64_t now);
  void PlayStress();
  void EndStress();
  void ReadSensorLink(uint16_t i);
  void ReadConsole(uint16_t i, int64_t now);
  void OnConsoleLine(uint16_t i, const std::string& line, int64_t now);
  void OnEpochLine(const swarm::EpochLine& epoch_line, int64_t now);
  void RecordRound(int64_t now);
  lab::sim::RemoteRobotState ReportedState(uint16_t i, int64_t now) const;
  bool ReapRobots();
  lab::metrics::Metrics CollectMetrics(double wall_s);
  void ReadReplayBack(RunResult& result);
  void CheckEstimation(RunResult& result) const;
  void WriteMetrics(RunResult& result) const;
  void WriteBeacons(RunResult& result) const;
  void FillReport(RunResult& result) const;
  void WriteReport(RunResult& result) const;
  void PrintSummary(const RunResult& result) const;

  // The sensor links as the world loop's links: each robot's readings into
  // its feed (nowhere once its link closed), and the drives its bytes
  // completed, in the order they arrived, taken at the next instant.
  class SensorLinks final : public lab::sim::RemoteLinks {
   public:
    explicit SensorLinks(std::vector<Robot>& swarm) : swarm_(swarm) {}
    void Arrived(uint16_t robot, const motion::DriveCommand& drive) { drives_.push_back({robot, drive}); }
    void TakeDrives(const std::function<void(uint16_t, const motion::DriveCommand&)>& apply) override;
    lab::sensors::ReadingSink* Readings(uint16_t id) override;

   private:
    std::vector<Robot>& swarm_;
    std::vector<std::pair<uint16_t, motion::DriveCommand>> drives_;
  };

  static constexpr int64_t kPhysicsNs = syrof::registry::kImuPeriodNs;
  // From launching the qemu instances until every image is held.
  static constexpr int kBootTimeoutMs = 30'000;
  const Options options_;
  const lab::scenario::Scenario scenario_;
  const uint16_t robots_;
  const int64_t period_ns_ = syrof::registry::kDefaultRadioRoundNs;
  std::vector<Robot> swarm_;
  // The qemu instances and their sockets; their sockets and folder go on
  // every way out (a launch that failed too).
  QemuLauncher launcher_;
  std::string timing_;
  int64_t start_ns_ = 0;
  int64_t all_started_ns_ = 0;
  int64_t deadline_ns_ = 0;
  // Whether the robots handled the scenario's faults.
  swarm::FaultOutcomes fault_outcomes_;
  // The world, its faults and lifecycle (the lab's rules, done to qemu),
  // the sensors, and the metrics, goal checks and replay, as every runtime
  // outside the lab has them; on the host's clock from all_started_ns_.
  lab::sim::RemoteWorld loop_;
  SensorLinks links_;
  // Whether each robot looked when its activation schedule says it does.
  swarm::ActivationCheck activation_check_;
  int64_t world_ns_ = 0;       // the world's time, stepped in kPhysicsNs
  double world_clock_ns_ = 0;  // where the world's time should be now
  int64_t last_loop_ns_ = 0;
  double host_per_world_ = 1;  // this pass's HostPerWorld
  std::ofstream replay_file_;
  std::vector<lab::replay::RoundSink*> sinks_;  // added to the recorder in StartWorld
  std::string image_app_;                       // the app the images said they run
  lab::sim::RemoteRound read_;  // the round in progress: its epoch starts and maps
  // Every COOPERATIVE epoch start, to find the first epoch all robots started so.
  std::map<uint16_t, std::vector<uint16_t>> cooperative_starters_;
  std::optional<double> all_cooperative_s_;
  int64_t round_ = 0;
  int64_t next_round_ns_;  // on the world's time
  int open_consoles_;
  swarm::HostActions host_;  // the player's starts and stops, done to qemu
  // The beacons between the robots, and the base station's.
  BeaconChannel channel_;
  // --stress: the stalls played on the qemu instances and this host.
  swarm::StressPlayer stress_;
  std::vector<pollfd> fds_;
  bool ended_ = false;  // EndPausedAndHeld was done
};

}  // namespace syrof::firmware::swarm
