#include "syrof/firmware/swarm/swarm_host.h"

#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "syrof/firmware/swarm/guest_clock.h"
#include "syrof/firmware/swarm/image_app.h"
#include "syrof/firmware/swarm/world_grid.h"
#include "syrof/lab/metrics/collector.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/run_parts.h"

namespace syrof::firmware::swarm {

namespace metrics = lab::metrics;
namespace replay = lab::replay;

namespace {

// Writes what the socket takes now, keeps the rest (a robot that stopped
// reading must not stall the world).
void Flush(int fd, std::vector<uint8_t>& pending) {
  while (fd >= 0 && !pending.empty()) {
    const ssize_t written = send(fd, pending.data(), pending.size(), MSG_DONTWAIT);
    if (written <= 0) return;
    pending.erase(pending.begin(), pending.begin() + written);
  }
}

// Host nanoseconds per world nanosecond: the mean of the running robots'
// measured clock rates (GuestClockRate), 1 before any was measured.
// Paused, crashed and not yet joined robots do not count, nor a joiner
// before its first ten beacons (its rate starts at 1 and settles over them).
double HostPerWorld(const std::vector<Robot>& swarm, const lab::sim::WorldPlayer& player) {
  double sum = 0;
  int counted = 0;
  for (uint16_t i = 0; i < swarm.size(); ++i) {
    if (!player.running(i) || swarm[i].beacon_ns.size() < 10) continue;
    sum += swarm[i].clock_rate.host_per_guest();
    ++counted;
  }
  return counted == 0 ? 1.0 : sum / counted;
}

// The activation as the robots run it (their boot words carry it,
// qemu_launcher.cpp), so the metrics count active starts as the lab's do.
metrics::CollectorConfig SwarmCollectorConfig(const lab::scenario::Scenario& scenario, uint16_t robots,
                                              int64_t period_ns) {
  metrics::CollectorConfig config;
  config.robots = robots;
  config.radio_round_ns = period_ns;
  config.activation = lab::sim::ActivationConfigFor(scenario);
  return config;
}

// How the firmware's rounds are recorded (remote_world.h): a drive goes to
// the world as its bytes arrive, whatever the robot's lifecycle; a round is
// recorded as it ends on the world's time, from the world then; the console
// lines carry no heading.
lab::sim::RemoteRules FirmwareRules() {
  lab::sim::RemoteRules rules;
  rules.drives = lab::sim::RemoteRules::Drives::kEveryRobot;
  rules.boundary_truths = false;
  rules.reports_heading = false;
  return rules;
}

}  // namespace

void SwarmHost::SensorLinks::TakeDrives(const std::function<void(uint16_t, const motion::DriveCommand&)>& apply) {
  for (const auto& [robot, drive] : drives_) apply(robot, drive);
  drives_.clear();
}

lab::sensors::ReadingSink* SwarmHost::SensorLinks::Readings(uint16_t id) {
  Robot& robot = swarm_[id];
  return robot.sensor < 0 ? nullptr : &robot.feed;
}

SwarmHost::SwarmHost(const Options& options, const lab::scenario::Scenario& scenario,
                     std::span<lab::replay::RoundSink* const> sinks)
    : options_(options),
      scenario_(scenario),
      robots_(static_cast<uint16_t>(options.robots)),
      swarm_(robots_),
      launcher_(options_, scenario_),
      fault_outcomes_(robots_),
      loop_(scenario_, SwarmCollectorConfig(scenario_, robots_, period_ns_), FirmwareRules()),
      links_(swarm_),
      activation_check_(lab::sim::ActivationConfigFor(scenario_), robots_),
      next_round_ns_(period_ns_),
      open_consoles_(robots_),
      host_([this](const swarm::HostAction& action, int64_t at_ns) { return OnHostAction(action, at_ns); }),
      channel_(options_, scenario_, swarm_, loop_.player()),
      stress_(options.stress, int64_t{options.seconds} * 1'000'000'000, robots_) {
  sinks_.assign(sinks.begin(), sinks.end());
  if (options.icount_shift < 0) {
    for (Robot& robot : swarm_) robot.clock_rate = swarm::GuestClockRate::OnHostClock();
  }
}
bool SwarmHost::OnHostAction(const swarm::HostAction& action, int64_t at_ns) {
  const bool done = DoHostAction(action, at_ns, options_, swarm_[action.robot], open_consoles_);
  if (done && action.kind == swarm::HostAction::Kind::kSwitchOn) {
    swarm_[action.robot].switched_on_at = swarm::SwitchOn{at_ns / period_ns_, world_clock_ns_};
  }
  // Switching on the robots present at start is no join.
  const bool initial = action.kind == swarm::HostAction::Kind::kSwitchOn &&
                       scenario_.robots[action.robot].present_at_start;
  if (!initial) fault_outcomes_.OnAction(action, at_ns);
  return done;
}

bool SwarmHost::OpenSockets() {
  if (!launcher_.OpenSockets()) return false;
  for (uint16_t i = 0; i < robots_; ++i) {
    swarm_[i].log.open(options_.out + "/robot_" + std::to_string(i) + ".log");
  }
  if (!options_.base_station.empty()) channel_.base_station().listener = launcher_.ListenBeside(options_.base_station);
  return true;
}

bool SwarmHost::LaunchRobots() {
  timing_ = options_.icount_shift < 0 ? "host clock (no -icount)"
                                      : "-icount shift=" + std::to_string(options_.icount_shift);
  start_ns_ = HostNs();
  if (!launcher_.Launch(swarm_, kBootTimeoutMs)) return false;
  if (!WaitUntilHeld() || !NameImageApp()) {
    launcher_.KillAll(swarm_);
    return false;
  }
  return true;
}

// The app the images said they run on their held lines is the run's app:
// the replay's header and metrics.json name it (the recorder's NameApp,
// before its header goes anywhere). A scenario that names another app is
// told on standard error, in one line, and the run goes on with the
// image's app (docs/firmware.md, "The emulated swarm").
bool SwarmHost::NameImageApp() {
  std::vector<std::string> apps;
  for (const Robot& robot : swarm_) apps.push_back(robot.app);
  const ImageAppOrError app = OneImageApp(apps);
  if (!app.ok()) {
    std::fprintf(stderr, "syrof-firmware-swarm: %s\n", app.error->ToString().c_str());
    return false;
  }
  image_app_ = *app.app;
  loop_.recorder().NameApp(image_app_);
  if (const std::optional<std::string> warning = AppMismatchWarning(scenario_.app.name, image_app_, options_.image)) {
    std::fprintf(stderr, "%s\n", warning->c_str());
  }
  return true;
}

// Reads the consoles until every image has printed `held` (its robot built,
// its clock not started).
bool SwarmHost::WaitUntilHeld() {
  const int64_t give_up_ns = HostNs() + int64_t{kBootTimeoutMs} * 1'000'000;
  // A robot whose line before its held one did not parse (printed by
  // OnConsoleLine) is given up on at once, not after the timeout.
  const auto garbled = [](const Robot& robot) { return !robot.held && robot.bad_lines > 0; };
  for (;;) {
    const auto held = std::count_if(swarm_.begin(), swarm_.end(), [](const Robot& robot) { return robot.held; });
    if (held == robots_) return true;
    if (std::any_of(swarm_.begin(), swarm_.end(), garbled)) break;
    const int64_t now = WaitForLinks();
    if (now > give_up_ns) break;
    for (uint16_t i = 0; i < robots_; ++i) ReadConsole(i, now);
  }
  for (uint16_t i = 0; i < robots_; ++i) {
    if (garbled(swarm_[i])) {
      std::fprintf(stderr, "syrof-firmware-swarm: robot %u's image wrote a line the host cannot read (above) before "
                   "its `held` line (robot_%u.log)\n", static_cast<unsigned>(i), static_cast<unsigned>(i));
    } else if (!swarm_[i].held) {
      std::fprintf(stderr, "syrof-firmware-swarm: robot %u's image did not say `held` within %d s (robot_%u.log)\n",
                   static_cast<unsigned>(i), kBootTimeoutMs / 1000, static_cast<unsigned>(i));
    }
  }
  return false;
}

void SwarmHost::StartWorld() {
  for (lab::replay::RoundSink* sink : sinks_) loop_.recorder().AddSink(sink);
  replay_file_.open(options_.out + "/replay", std::ios::binary);
  loop_.recorder().OpenReplay(replay_file_);
  all_started_ns_ = HostNs();
  // With -icount a loaded host stretches the guests' time (1.3x for 4
  // robots on 2 busy cores, more for 8): three times the run, then give up.
  deadline_ns_ = all_started_ns_ + (3 * options_.seconds + 30) * int64_t{1'000'000'000};
  channel_.base_station().Serve();  // a base station already waiting hears the first beacons too
  loop_.player().StartPresentRobots(host_);
}

bool SwarmHost::Running() const { return open_consoles_ > 0 && HostNs() < deadline_ns_; }

void SwarmHost::Step() {
  if (!ended_ && world_ns_ >= int64_t{options_.seconds} * 1'000'000'000) {
    EndPausedAndHeld(swarm_, loop_.player(), open_consoles_);
    EndStress();
    ended_ = true;
  }
  const int64_t now = WaitForLinks();
  AdvanceWorld(now);
  PlayStress();
  for (Robot& robot : swarm_) Flush(robot.sensor, robot.sensor_out);
  channel_.Deliver(now);
  for (uint16_t i = 0; i < robots_; ++i) {
    ReadSensorLink(i);
    channel_.ReadRadio(i, fds_[3 * i].revents, now, world_clock_ns_, host_per_world_);
    ReadConsole(i, now);
  }
  channel_.base_station().Serve();
  // Round ends on the host's clock: every robot's latest report.
  while (world_ns_ >= next_round_ns_) RecordRound(now);
}

// Polls every robot's links until one has input, the next delivery is due
// or half a physics step passed (at most 10 ms); returns the host time after.
int64_t SwarmHost::WaitForLinks() {
  fds_.clear();
  for (const Robot& robot : swarm_) {
    fds_.push_back({robot.radio, POLLIN, 0});
    fds_.push_back({robot.console, POLLIN, 0});
    fds_.push_back({robot.sensor, POLLIN, 0});
  }
  const int64_t now_before = HostNs();
  int64_t next_event_ns = now_before + kPhysicsNs / 2;
  if (const std::optional<int64_t> due_ns = channel_.next_due_ns()) next_event_ns = std::min(next_event_ns, *due_ns);
  const int wait_ms = static_cast<int>(std::max<int64_t>(0, (next_event_ns - now_before) / 1'000'000));
  poll(fds_.data(), fds_.size(), std::min(wait_ms, 10));
  return HostNs();
}

void SwarmHost::AdvanceWorld(int64_t now) {
  // The world follows the host's clock slowed to the robots' mean clock
  // rate (GuestClockRate, from the times they print; exactly 1 on the
  // host's clock), so a robot gets a second of readings per second of its
  // own time (docs/firmware.md, "How readings are timed").
  host_per_world_ = HostPerWorld(swarm_, loop_.player());
  world_clock_ns_ += static_cast<double>(now - (last_loop_ns_ == 0 ? all_started_ns_ : last_loop_ns_)) / host_per_world_;
  last_loop_ns_ = now;
  // The world's steps due by now (RemoteWorld::StepInstant: faults, the
  // drives that arrived, bodies, contacts, each robot's readings due at the
  // step's instant into its feed), then the frames to each sensor link. No
  // boundary truths are kept (FirmwareRules), so the instant's round is 0.
  while (static_cast<double>(world_ns_ + kPhysicsNs) <= world_clock_ns_) {
    world_ns_ += kPhysicsNs;
    loop_.StepInstant({world_ns_, world_ns_, static_cast<double>(kPhysicsNs) * 1e-9, 0}, host_, links_);
  }
  for (Robot& robot : swarm_) {
    robot.sensor_out.insert(robot.sensor_out.end(), robot.feed.bytes().begin(), robot.feed.bytes().end());
    robot.feed.clear();
  }
}

// --stress: the stalls due by the world's time (stress_player.h). The host
// is one thread, so a world stall is this host sleeping for its length.
void SwarmHost::PlayStress() {
  if (ended_) return;
  const int64_t world_stall_ns = stress_.Play(
      world_ns_,
      [this](uint16_t i) { return loop_.player().running(i) && swarm_[i].switched_on && swarm_[i].qemu.started(); },
      [this](uint16_t i, bool stop) { swarm_[i].qemu.Signal(stop ? SIGSTOP : SIGCONT); });
  if (world_stall_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(world_stall_ns));
}

// No qemu stays stopped by the stress past the run's end.
void SwarmHost::EndStress() {
  stress_.EndAll([this](uint16_t i) { return loop_.player().running(i) && swarm_[i].qemu.started(); },
                 [this](uint16_t i, bool stop) { swarm_[i].qemu.Signal(stop ? SIGSTOP : SIGCONT); });
}

void SwarmHost::ReadSensorLink(uint16_t i) {
  Robot& robot = swarm_[i];
  if (robot.sensor < 0 || (fds_[3 * i + 2].revents & (POLLIN | POLLHUP)) == 0) return;
  uint8_t buffer[4096];
  const ssize_t count = read(robot.sensor, buffer, sizeof buffer);
  if (count <= 0) {
    close(robot.sensor);
    robot.sensor = -1;
  }
  for (ssize_t k = 0; k < count; ++k) {
    if (auto drive = robot.feed.PushFromRobot(buffer[k], world_ns_)) links_.Arrived(i, *drive);
  }
}

void SwarmHost::ReadConsole(uint16_t i, int64_t now) {
  Robot& robot = swarm_[i];
  if (robot.console < 0 || (fds_[3 * i + 1].revents & (POLLIN | POLLHUP)) == 0) return;
  uint8_t buffer[4096];
  const ssize_t count = read(robot.console, buffer, sizeof buffer);
  if (count <= 0) {
    close(robot.console);
    robot.console = -1;
    --open_consoles_;
    return;
  }
  robot.pending_line.append(reinterpret_cast<const char*>(buffer), static_cast<size_t>(count));
  size_t newline;
  while ((newline = robot.pending_line.find('\n')) != std::string::npos) {
    const std::string line = robot.pending_line.substr(0, newline);
    robot.pending_line.erase(0, newline + 1);
    OnConsoleLine(i, line, now);
  }
}

void SwarmHost::OnConsoleLine(uint16_t i, const std::string& line, int64_t now) {
  Robot& robot = swarm_[i];
  robot.log << line << '\n';
  ++robot.lines;
  if (line.rfind("status ", 0) == 0) robot.last_status = line;
  const swarm::ConsoleLine parsed = swarm::ParseConsoleLine(line, robots_);
  if (const auto* held = std::get_if<swarm::HeldLine>(&parsed); held != nullptr && held->robot != i) {
    ++robot.bad_lines;
    std::fprintf(stderr, "robot %u console: its held line says id=%u\n  %s\n", static_cast<unsigned>(i),
                 static_cast<unsigned>(held->robot), line.c_str());
  } else if (held != nullptr) {
    robot.held = true;
    robot.app = held->app;
  } else if (const auto* error = std::get_if<swarm::LineError>(&parsed)) {
    ++robot.bad_lines;
    std::fprintf(stderr, "robot %u console, column %zu: %s\n  %s\n", static_cast<unsigned>(i), error->column,
                 error->what.c_str(), line.c_str());
  } else if (const auto* round_line = std::get_if<swarm::RoundLine>(&parsed)) {
    robot.latest = *round_line;
    robot.latest_ns = now;
    robot.clock_rate.OnGuestTime(now, round_line->t_ms * 1'000'000);
    fault_outcomes_.OnRoundLine(*round_line, world_ns_);
  } else if (const auto* epoch_line = std::get_if<swarm::EpochLine>(&parsed)) {
    OnEpochLine(*epoch_line, now);
  }
}

void SwarmHost::OnEpochLine(const swarm::EpochLine& epoch_line, int64_t now) {
  loop_.recorder().OnEpochStart(epoch_line.robot, round_, world_ns_, epoch_line.map);
  activation_check_.OnEpochLine(epoch_line);
  fault_outcomes_.OnEpochLine(epoch_line, world_ns_);
  read_.events.push_back(replay::Event{replay::EventKind::kEpochStart, epoch_line.robot, replay::kNoRobot,
                                      epoch_line.map.epoch, static_cast<uint8_t>(epoch_line.map.mode), world_ns_});
  if (std::none_of(read_.maps.begin(), read_.maps.end(),
                   [&](const replay::RobotMap& entry) { return entry.robot == epoch_line.robot; })) {
    read_.maps.push_back(replay::RobotMap{epoch_line.robot, lab::sim::ToEpochMap(epoch_line.map)});
  }
  if (epoch_line.map.mode == syrof::wire::Mode::kCooperative) {
    std::vector<uint16_t>& starters = cooperative_starters_[epoch_line.map.epoch];
    starters.push_back(epoch_line.robot);
    if (starters.size() == robots_ && !all_cooperative_s_) {
      all_cooperative_s_ = static_cast<double>(now - all_started_ns_) * 1e-9;
    }
  }
}

// The round ending at next_round_ns_ on the world's time, from every
// robot's latest report at host time `now` (ReportedState), with the epoch
// starts read since the round before and each member's round boundary, to
// the world loop: metrics, the goal, the replay (the world now stands for
// the round's end, none of its events later than it: FirmwareRules).
void SwarmHost::RecordRound(int64_t now) {
  for (uint16_t i = 0; i < robots_; ++i) {
    const lab::sim::RemoteRobotState state = ReportedState(i, now);
    loop_.NoteRound(i, state);
    // Its round boundary, if it is a member (as RemoteWorld counts one: running and reporting).
    const int64_t boundary_ns = swarm_[i].last_boundary_ns;
    const bool member = loop_.player().running(i) && state.reporting && state.status == 0;
    if (member && boundary_ns > 0) read_.phase_boundaries_ns.push_back(boundary_ns - all_started_ns_);
    // Its boundary of this round for the round-start skew: its beacon of
    // the round as it reached the host, every robot's on the host's clock.
    if (const std::optional<int64_t> boundary = TakeBoundary(swarm_[i].boundary_ns_of_round, round_)) {
      read_.activations_ns.push_back(*boundary);
    }
  }
  loop_.RecordRound(round_, (round_ + 1) * period_ns_, read_);
  read_ = {};
  ++round_;
  next_round_ns_ += period_ns_;
}

// Robot `i`'s newest console report as the world loop reads it. It is
// reporting while its newest report is younger than three rounds on the
// robots' clock (a robot the player runs shows absent before its first
// report, qemu starting up, and after its reports stop). The report line
// has no heading (FirmwareRules: the replay shows the true one).
lab::sim::RemoteRobotState SwarmHost::ReportedState(uint16_t i, int64_t now) const {
  const Robot& robot = swarm_[i];
  lab::sim::RemoteRobotState state;
  if (!robot.latest) {
    state.reporting = false;
    return state;
  }
  const RoundLine& line = *robot.latest;
  state.reported = true;
  state.status = line.member ? 0 : 1;
  state.phase = static_cast<uint8_t>(line.phase);
  state.epoch_mode = static_cast<uint8_t>(line.mode);
  state.estimate_valid = line.estimate_valid;
  state.epoch = line.epoch;
  state.est_x_m = line.x_m;
  state.est_y_m = line.y_m;
  state.reporting = static_cast<double>(now - robot.latest_ns) < 3 * static_cast<double>(period_ns_) * host_per_world_;
  return state;
}

}  // namespace syrof::firmware::swarm
