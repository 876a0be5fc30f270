#include "robot_fleet.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>

#include "syrof/process/fd.h"
#include "syrof/registry/tasks.h"
#include "syrof/sim_dds/participant.h"

namespace syrof::sim_dds {

RobotFleet::RobotFleet(const SwarmOptions& options, std::string robot_binary, uint64_t run_id, uint32_t domain_id,
                       const lab::sim::RemoteWorld& loop, std::ostream& log, std::vector<int>& pids)
    : options_(options),
      robot_binary_(std::move(robot_binary)),
      loop_(loop),
      log_(log),
      pids_(pids),
      robots_(loop.player().robot_count()) {
  robot_options_.scenario_path = options.scenario_path;
  robot_options_.overrides = options.overrides;
  robot_options_.run_id = run_id;
  robot_options_.domain_id = domain_id;
  robot_options_.interface = options.interface;
  robot_options_.log_directory = (std::filesystem::path(options.out_dir) / "robots").string();
  robot_options_.parent_pid = getpid();
  robot_options_.realtime = options.realtime;
  // The robot's main thread is its hardware: it passes the world's readings
  // to the sensor drivers and the drive back (WorldLink), so it starts at
  // the drivers' priority, and a joiner's start-up is not starved either.
  if (options.realtime && CanUseFifoScheduling()) {
    fifo_priority_ = sched_get_priority_min(SCHED_FIFO) + registry::kSensorTaskPriority;
  }
  robot_options_.align_rounds = options.align_rounds;
  robot_options_.realtime_start = options.realtime_start;
  robot_options_.stress = options.stress;  // the late samples are the robots' to play (RadioOptionsFor, WorldLink)
}

bool RobotFleet::Spawn(uint16_t id) {
  robot_options_.robot = id;
  robot_options_.clock_offset_us =
      id < options_.robot_clock_offsets_us.size() ? options_.robot_clock_offsets_us[id] : 0;
  const SwarmOptions::RobotNetwork* network =
      id < options_.robot_networks.size() ? &options_.robot_networks[id] : nullptr;
  robot_options_.interface =
      network != nullptr && !network->interface.empty() ? network->interface : options_.interface;
  process::Fd netns;
  if (network != nullptr && !network->netns_path.empty()) {
    netns.Reset(open(network->netns_path.c_str(), O_RDONLY | O_CLOEXEC));
    if (!netns.valid()) {
      spawn_error_ = "robot " + std::to_string(id) + ": cannot open its network namespace " + network->netns_path +
                     ": " + std::strerror(errno);
      return false;
    }
  }
  process::Command command;
  command.argv = RobotArguments(robot_options_);
  command.argv.insert(command.argv.begin(), robot_binary_);
  command.inherit_environment = true;
  command.descriptors = {{1, 1}, {2, 2}};
  command.own_process_group = true;
  command.die_with_parent = true;
  command.network_namespace = netns.get();
  command.fifo_priority = fifo_priority_;
  Slot& r = robots_[id];
  r.process = process::Spawn(command);
  if (!r.process.started()) {
    spawn_error_ = "robot " + std::to_string(id) + ": cannot start " + robot_binary_ + ": " +
                   std::strerror(r.process.start_error());
    return false;
  }
  pids_.push_back(r.process.pid());
  if (quota_ != nullptr && !quota_->Add(r.process.pid())) {
    log_ << "syrof swarm: robot " << id << " could not join " << quota_->path() << "\n";
  }
  return true;
}

void RobotFleet::Reap(uint16_t id, bool block) {
  Slot& r = robots_[id];
  if (!r.process.started() || r.process.reaped()) return;
  const std::optional<process::ExitStatus> status =
      block ? r.process.Reap() : r.process.Wait(std::chrono::milliseconds(0));
  if (!status) return;
  if (status->exited()) r.exit = status->code;
  if (status->signaled()) r.exit = -status->signal;
  r.cpu_seconds = status->cpu_seconds;
}

bool RobotFleet::AnyEnded() const {
  return std::any_of(robots_.begin(), robots_.end(), [](const Slot& r) { return r.process.reaped(); });
}

bool RobotFleet::AllReaped() const {
  return std::all_of(robots_.begin(), robots_.end(),
                     [](const Slot& r) { return !r.process.started() || r.process.reaped(); });
}

void RobotFleet::EndAll() {
  for (Slot& r : robots_) {
    if (!r.process.reaped()) r.process.KillGroup();
  }
  for (uint16_t id = 0; id < robots_.size(); ++id) Reap(id, true);
}

std::vector<double> RobotFleet::cpu_seconds() const {
  std::vector<double> seconds;
  for (const Slot& r : robots_) seconds.push_back(r.cpu_seconds);
  return seconds;
}

std::vector<std::optional<int>> RobotFleet::exits() const {
  std::vector<std::optional<int>> exits;
  for (const Slot& r : robots_) exits.push_back(r.exit);
  return exits;
}

bool RobotFleet::StartRobot(uint16_t id, int64_t /*world_ns*/, bool resume) {
  Slot& r = robots_[id];
  if (resume) {
    r.process.Signal(SIGCONT);
    return true;
  }
  if (r.process.started() || Spawn(id)) return true;
  log_ << "syrof swarm: " << spawn_error_ << "\n";  // the player counts it crashed
  return false;
}

void RobotFleet::StopRobot(uint16_t id, int64_t /*world_ns*/, lab::sim::StopReason reason) {
  process::Child& robot = robots_[id].process;
  if (reason == lab::sim::StopReason::kCrash) robot.Kill();
  if (reason == lab::sim::StopReason::kPause) robot.Signal(SIGSTOP);
}

}  // namespace syrof::sim_dds
