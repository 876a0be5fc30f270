#include "syrof/lab/sim/world_player.h"

#include <algorithm>
#include <cmath>

#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/run_parts.h"

namespace syrof::lab::sim {

const char* ToString(Lifecycle lifecycle) {
  switch (lifecycle) {
    case Lifecycle::kAbsent: return "absent";
    case Lifecycle::kWaitingToJoin: return "waiting to join";
    case Lifecycle::kRunning: return "running";
    case Lifecycle::kPaused: return "paused";
    case Lifecycle::kCrashed: return "crashed";
  }
  return "?";
}

replay::Presence ToPresence(Lifecycle lifecycle) {
  switch (lifecycle) {
    case Lifecycle::kAbsent:
    case Lifecycle::kWaitingToJoin: return replay::Presence::kAbsent;
    case Lifecycle::kRunning: return replay::Presence::kRunning;
    case Lifecycle::kPaused: return replay::Presence::kPaused;
    case Lifecycle::kCrashed: return replay::Presence::kCrashed;
  }
  return replay::Presence::kAbsent;
}

WorldPlayer::WorldPlayer(const scenario::Scenario& scenario, world::World& world, metrics::Collector& collector)
    : scenario_(scenario),
      world_(world),
      collector_(collector),
      faults_(scenario.faults, static_cast<int64_t>(std::llround(scenario.timing.radio_round_s * 1e9))) {
  robots_.resize(scenario.robots.size());
}

void WorldPlayer::StartPresentRobots(RobotRuntime& runtime) {
  for (uint16_t id = 0; id < robots_.size(); ++id) {
    if (scenario_.robots[id].present_at_start && robots_[id].lifecycle == Lifecycle::kAbsent) {
      Start(id, 0, false, runtime);
    }
  }
}

void WorldPlayer::Event(replay::EventKind kind, int64_t now_ns, uint16_t id, const RobotRuntime& runtime,
                        uint16_t other) {
  const EventStamp stamp = id < robots_.size() ? runtime.Stamp(id) : EventStamp{};
  replay::Event event{};
  event.kind = kind;
  event.robot = id;
  event.other = other;
  event.epoch = stamp.epoch;
  event.mode = static_cast<uint8_t>(stamp.mode);
  event.time_ns = now_ns;
  events_.push_back(event);
}

void WorldPlayer::Start(uint16_t id, int64_t now_ns, bool resume, RobotRuntime& runtime) {
  Robot& robot = robots_[id];
  if (robot.app_faulted || !runtime.StartRobot(id, now_ns, resume)) {
    // Its app failed in init (or it could not be started): the body
    // arrives and stays an obstacle.
    robot.lifecycle = Lifecycle::kCrashed;
    world_.SetPresence(id, world::BodyPresence::kStopped);
    return;
  }
  robot.lifecycle = Lifecycle::kRunning;
  robot.scored_from_ns = now_ns + kEstimationWarmupNs;
  world_.SetPresence(id, world::BodyPresence::kActive);
}

void WorldPlayer::Stop(uint16_t id, int64_t now_ns, StopReason reason, Lifecycle after, RobotRuntime& runtime) {
  Robot& robot = robots_[id];
  if (robot.lifecycle == Lifecycle::kRunning || robot.lifecycle == Lifecycle::kPaused) {
    runtime.StopRobot(id, now_ns, reason);
    world_.SetPresence(id, world::BodyPresence::kStopped);
  }
  robot.lifecycle = after;
}

// A joiner's start disc is clear when every other body in the arena is
// farther than both radii, the safety margin, what a robot at the swarm's
// speed limit covers in two radio rounds (the joiner's first presence beacon
// reaches the others' filters after one or two rounds) and the distance the
// other body, at its speed now, needs to stop on the filter's braking curve
// (v^2 / a: half the weakest deceleration, docs/safety.md). Without that
// last term a robot driving at 0.45 m/s found a joiner switched on 7.5 cm
// beyond its disc and could not stop (crowd_200_short, seed 2).
bool WorldPlayer::StartDiscClear(uint16_t id) const {
  const scenario::RobotSpec& spec = scenario_.robots[id];
  const motion::SafetyConfig safety = SafetyConfigFor(scenario_);
  const double reach_m = safety.margin_m + safety.others_max_speed_mps * 2.0 * scenario_.timing.radio_round_s;
  for (uint16_t other = 0; other < world_.size(); ++other) {
    if (other == id || world_.presence(other) == world::BodyPresence::kAbsent) continue;
    const world::BodyState& body = world_.state(other);
    const double squared_speed = body.vx_mps * body.vx_mps + body.vy_mps * body.vy_mps;
    const double stopping_m =
        squared_speed / safety.others_braking_mps2 + 2.0 * safety.others_lag_s * std::sqrt(squared_speed);
    const double clearance_m = world_.body_radius_m(id) + world_.body_radius_m(other) + reach_m + stopping_m;
    if (std::hypot(body.x_m - spec.x_m, body.y_m - spec.y_m) < clearance_m) return false;
  }
  return true;
}

// With safety on, a joiner whose start disc is occupied waits (JOIN_WAIT)
// and is switched on at the first physics step that finds it clear.
void WorldPlayer::Join(uint16_t id, int64_t now_ns, RobotRuntime& runtime) {
  if (scenario_.safety && !StartDiscClear(id)) {
    robots_[id].lifecycle = Lifecycle::kWaitingToJoin;
    waiting_.push_back(id);
    collector_.OnJoinWait(id, now_ns);
    Event(replay::EventKind::kJoinWait, now_ns, id, runtime);
    return;
  }
  Start(id, now_ns, false, runtime);
  Event(replay::EventKind::kJoin, now_ns, id, runtime);
}

void WorldPlayer::PlayFaults(int64_t now_ns, RobotRuntime& runtime) {
  // Waiting joiners first, in the order they became due; one that crashed
  // while it waited is no longer waiting.
  for (auto it = waiting_.begin(); it != waiting_.end();) {
    const uint16_t id = *it;
    if (robots_[id].lifecycle != Lifecycle::kWaitingToJoin) {
      it = waiting_.erase(it);
    } else if (StartDiscClear(id)) {
      collector_.OnJoinWaitEnd(id, now_ns);
      Start(id, now_ns, false, runtime);
      Event(replay::EventKind::kJoin, now_ns, id, runtime);
      it = waiting_.erase(it);
    } else {
      ++it;
    }
  }
  for (const FaultAction& action : faults_.Due(now_ns)) {
    const uint16_t id = action.robot;
    if (id >= robots_.size()) continue;
    const Lifecycle now = robots_[id].lifecycle;
    switch (action.kind) {
      case FaultAction::Kind::kCrash:
        if (now == Lifecycle::kCrashed) break;
        Stop(id, now_ns, StopReason::kCrash, Lifecycle::kCrashed, runtime);
        Event(replay::EventKind::kCrash, now_ns, id, runtime);
        break;
      case FaultAction::Kind::kPause:
        if (now != Lifecycle::kRunning) break;
        Stop(id, now_ns, StopReason::kPause, Lifecycle::kPaused, runtime);
        Event(replay::EventKind::kPause, now_ns, id, runtime);
        break;
      case FaultAction::Kind::kJoin:
        if (now != Lifecycle::kAbsent) break;
        Join(id, now_ns, runtime);
        break;
      case FaultAction::Kind::kResume:
        if (now != Lifecycle::kPaused) break;
        Start(id, now_ns, true, runtime);
        Event(replay::EventKind::kResume, now_ns, id, runtime);
        break;
    }
  }
}

void WorldPlayer::TakeContacts(const RobotRuntime& runtime) {
  for (const world::Contact& contact : world_.new_contacts()) {
    collector_.OnCollision(contact.time_ns, contact.a, contact.b);
    Event(replay::EventKind::kCollision, contact.time_ns, contact.a, runtime, contact.b);
  }
  for (const world::WallContact& contact : world_.new_wall_contacts()) {
    collector_.OnWallContact(contact.time_ns, contact.robot);
    Event(replay::EventKind::kWallContact, contact.time_ns, contact.robot, runtime);
  }
}

void WorldPlayer::AppFaulted(uint16_t id, int64_t now_ns, RobotRuntime& runtime) {
  Robot& robot = robots_[id];
  robot.app_faulted = true;
  if (robot.lifecycle == Lifecycle::kRunning || robot.lifecycle == Lifecycle::kPaused) {
    Stop(id, now_ns, StopReason::kAppFault, Lifecycle::kCrashed, runtime);
  }
}

std::vector<goals::RobotPose> WorldPlayer::RunningPoses() const {
  return RunningPosesOf([this](uint16_t id) { return presence(id); },
                        [this](uint16_t id) -> const world::BodyState& { return world_.state(id); });
}

std::vector<goals::RobotPose> WorldPlayer::RunningPoses(std::span<const replay::Presence> presence,
                                                        std::span<const world::BodyState> bodies) const {
  return RunningPosesOf([&](uint16_t id) { return presence[id]; },
                        [&](uint16_t id) -> const world::BodyState& { return bodies[id]; });
}

template <typename PresenceOf, typename BodyOf>
std::vector<goals::RobotPose> WorldPlayer::RunningPosesOf(PresenceOf presence_of, BodyOf body_of) const {
  std::vector<goals::RobotPose> poses;
  for (uint16_t id = 0; id < robots_.size(); ++id) {
    if (presence_of(id) != replay::Presence::kRunning || robots_[id].app_faulted) continue;
    const world::BodyState& body = body_of(id);
    poses.push_back(goals::RobotPose{id, body.x_m, body.y_m, world_.body_radius_m(id)});
  }
  return poses;
}

std::vector<apps::GoalPose> WorldPlayer::FinalPoses() const {
  std::vector<apps::GoalPose> poses;
  for (uint16_t id = 0; id < robots_.size(); ++id) {
    const world::BodyState& body = world_.state(id);
    poses.push_back(apps::GoalPose{id, body.x_m, body.y_m, body.heading_rad,
                                   running(id) && !robots_[id].app_faulted, world_.body_radius_m(id)});
  }
  return poses;
}

std::vector<replay::Event> WorldPlayer::TakeEvents() {
  std::vector<replay::Event> taken;
  taken.swap(events_);
  return taken;
}

}  // namespace syrof::lab::sim
