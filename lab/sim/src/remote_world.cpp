#include "syrof/lab/sim/remote_world.h"

#include <algorithm>

#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/run_parts.h"

namespace syrof::lab::sim {

RemoteWorld::RemoteWorld(const scenario::Scenario& scenario, const metrics::CollectorConfig& config,
                         RemoteRules rules)
    : size_(static_cast<uint16_t>(scenario.robots.size())),
      rules_(rules),
      world_(scenario.arena, Bodies(scenario), scenario.seed),
      recorder_(scenario, config),
      player_(scenario, world_, recorder_.collector()),
      robots_(size_),
      robot_rounds_(size_),
      frames_(size_) {
  for (uint16_t id = 0; id < size_; ++id) {
    banks_.push_back(std::make_unique<sensors::SensorBank>(SensorConfigFor(scenario, scenario.robots[id]),
                                                           SensorSeed(scenario.seed, id)));
  }
}

RemoteWorld::~RemoteWorld() = default;

EventStamp RemoteWorld::Stamp(uint16_t id) const {
  const RemoteRobotState& r = robots_[id];
  if (!r.reported) return {};
  return EventStamp{r.epoch, static_cast<wire::Mode>(r.epoch_mode)};
}

void RemoteWorld::StepInstant(const Instant& instant, RobotRuntime& runtime, RemoteLinks& links) {
  player_.PlayFaults(instant.faults_ns, runtime);
  links.TakeDrives([this](uint16_t id, const motion::DriveCommand& command) {
    if (id >= size_) return;
    if (rules_.drives == RemoteRules::Drives::kEveryRobot || player_.running(id)) world_.SetDrive(id, command);
  });
  world_.Step(instant.now_ns, instant.step_s);
  player_.TakeContacts(runtime);
  for (uint16_t id = 0; id < size_; ++id) {
    if (!player_.running(id)) continue;
    sensors::ReadingSink* sink = links.Readings(id);
    if (sink != nullptr) banks_[id]->Sample(instant.now_ns, world_.true_state(id), *sink);
  }
  if (rules_.boundary_truths) KeepBoundaryTruths(instant.now_ns, instant.round);
}

void RemoteWorld::KeepBoundaryTruths(int64_t now_ns, int64_t round) {
  while (next_truth_ <= round) {
    BoundaryTruth truth;
    truth.time_ns = now_ns;
    for (uint16_t id = 0; id < size_; ++id) {
      truth.bodies.push_back(world_.state(id));
      truth.presence.push_back(player_.presence(id));
    }
    truth.events = player_.TakeEvents();
    truths_[next_truth_++] = std::move(truth);
  }
}

void RemoteWorld::RecordRound(int64_t round, int64_t time_ns_without_truth, RemoteRound& read) {
  const auto truth_it = truths_.find(round);
  const BoundaryTruth* truth = truth_it != truths_.end() ? &truth_it->second : nullptr;
  const int64_t round_time_ns = truth != nullptr ? truth->time_ns : time_ns_without_truth;
  if (read.activations_ns.size() >= 2) {
    const auto [low, high] = std::minmax_element(read.activations_ns.begin(), read.activations_ns.end());
    skews_ns_.push_back(*high - *low);
  }
  BuildFrames(truth, round_time_ns);
  std::vector<replay::Event>& events = read.events;
  if (truth != nullptr) events.insert(events.begin(), truth->events.begin(), truth->events.end());
  if (!rules_.boundary_truths) {
    // The world now stands for the boundary: its events up to now belong to
    // the round, none later than the round's time.
    const std::vector<replay::Event> world_events = player_.TakeEvents();
    events.insert(events.begin(), world_events.begin(), world_events.end());
    for (replay::Event& event : events) event.time_ns = std::min(event.time_ns, round_time_ns);
  }
  OrderByTime(events);
  // The running robots' true positions, for the goal checks: at the recorded boundary, or now.
  auto running_poses = [&] {
    return truth != nullptr ? player_.RunningPoses(truth->presence, truth->bodies) : player_.RunningPoses();
  };
  recorder_.RecordRound(RecordedRound{round, round_time_ns, robot_rounds_, read.phase_boundaries_ns, frames_, events,
                                      read.maps, running_poses});
  if (truth != nullptr) truths_.erase(truth_it);
}

// The round's RobotRound (for the collector) and RobotFrame (for the
// replay) of every robot, from its newest report and the boundary's truth
// (or the world now, when the boundary has none).
void RemoteWorld::BuildFrames(const BoundaryTruth* truth, int64_t round_time_ns) {
  for (uint16_t id = 0; id < size_; ++id) {
    const RemoteRobotState& last = robots_[id];
    const replay::Presence presence = truth != nullptr ? truth->presence[id] : player_.presence(id);
    const world::BodyState body = truth != nullptr ? truth->bodies[id] : world_.state(id);
    metrics::RobotRound& rr = robot_rounds_[id];
    rr = metrics::RobotRound{};
    rr.id = id;
    rr.running = presence == replay::Presence::kRunning && !player_.app_faulted(id) && last.reporting;
    rr.sync_member = last.reported && last.status == 0;
    rr.member = rr.running && rr.sync_member;
    rr.paused = presence == replay::Presence::kPaused;
    rr.epoch = last.epoch;
    rr.epoch_mode = static_cast<wire::Mode>(last.epoch_mode);
    rr.phase = static_cast<wire::Phase>(last.phase);
    rr.estimate_valid = rr.running && last.estimate_valid && round_time_ns >= player_.scored_from_ns(id);
    rr.true_x_m = body.x_m;
    rr.true_y_m = body.y_m;
    rr.est_x_m = last.est_x_m;
    rr.est_y_m = last.est_y_m;
    replay::RobotFrame& f = frames_[id];
    f.id = id;
    f.presence = player_.app_faulted(id) && presence != replay::Presence::kAbsent ? replay::Presence::kCrashed : presence;
    // A running robot whose reports stopped (or never came: qemu starting up) shows as absent.
    if (f.presence == replay::Presence::kRunning && !last.reporting) f.presence = replay::Presence::kAbsent;
    f.status = last.reported ? last.status : 1;
    f.phase = last.phase;
    f.mode = last.epoch_mode;
    f.epoch = last.epoch;
    f.true_x_m = static_cast<float>(body.x_m);
    f.true_y_m = static_cast<float>(body.y_m);
    f.true_heading_rad = static_cast<float>(body.heading_rad);
    f.est_x_m = static_cast<float>(last.est_x_m);
    f.est_y_m = static_cast<float>(last.est_y_m);
    f.est_heading_rad = rules_.reports_heading ? last.est_heading_rad : f.true_heading_rad;
  }
}

metrics::Metrics RemoteWorld::Finish(const RunEnd& end) {
  return Finish(recorder_.Facts(end, player_, world_));
}

metrics::Metrics RemoteWorld::Finish(const metrics::RunFacts& facts) {
  metrics::Metrics metrics = recorder_.Finish(facts);
  metrics.round_start_skew = skew();
  return metrics;
}

}  // namespace syrof::lab::sim
