#include "syrof/lab/sim/round_recorder.h"

#include <algorithm>
#include <cmath>

#include "syrof/base/check.h"
#include "syrof/lab/sim/robot_config.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/sync/synchronizer.h"

namespace syrof::lab::sim {

metrics::CollectorConfig CollectorConfigFor(const scenario::Scenario& scenario) {
  return metrics::CollectorConfig{static_cast<uint16_t>(scenario.robots.size()),
                                  std::llround(scenario.timing.radio_round_s * 1e9),
                                  static_cast<uint16_t>(scenario.timing.silence_rounds), ActivationConfigFor(scenario)};
}

void OrderByTime(std::span<replay::Event> events) {
  std::stable_sort(events.begin(), events.end(),
                   [](const replay::Event& a, const replay::Event& b) { return a.time_ns < b.time_ns; });
}

RoundRecorder::RoundRecorder(const scenario::Scenario& scenario, const metrics::CollectorConfig& config)
    : scenario_(scenario), collector_(config), goal_monitor_(scenario.goal) {
  if (scenario.channel.model == world::ChannelModel::kScripted) {
    scripted_lost_ = scenario.channel.lost;
    std::sort(scripted_lost_.begin(), scripted_lost_.end());
    scripted_lost_.erase(std::unique(scripted_lost_.begin(), scripted_lost_.end()), scripted_lost_.end());
  }
}

std::span<const replay::Event> RoundRecorder::WithLostBeacons(const RecordedRound& round) {
  while (next_lost_ < scripted_lost_.size() && scripted_lost_[next_lost_].round < round.round) ++next_lost_;
  if (next_lost_ == scripted_lost_.size() || scripted_lost_[next_lost_].round != round.round) return round.events;
  round_events_.clear();
  const int64_t sent_ns = round.round * CollectorConfigFor(scenario_).radio_round_ns;
  auto running = [&](uint16_t id) -> const replay::RobotFrame* {
    const auto frame = std::lower_bound(round.frames.begin(), round.frames.end(), id,
                                        [](const replay::RobotFrame& f, uint16_t wanted) { return f.id < wanted; });
    return frame != round.frames.end() && frame->id == id && frame->presence == replay::Presence::kRunning ? &*frame
                                                                                                        : nullptr;
  };
  for (; next_lost_ < scripted_lost_.size() && scripted_lost_[next_lost_].round == round.round; ++next_lost_) {
    if (round_events_.size() >= kMostLostBeaconEvents) continue;
    const world::LostBeacon& lost = scripted_lost_[next_lost_];
    const replay::RobotFrame* sender = running(lost.from);
    if (sender == nullptr || running(lost.to) == nullptr) continue;  // nothing was sent, or nobody listened
    replay::Event event;
    event.kind = replay::EventKind::kBeaconLost;
    event.robot = lost.from;
    event.other = lost.to;
    event.epoch = sender->epoch;
    event.mode = sender->mode;
    event.time_ns = std::min(sent_ns, round.time_ns);
    round_events_.push_back(event);
  }
  round_events_.insert(round_events_.end(), round.events.begin(), round.events.end());
  return round_events_;
}

void RoundRecorder::NameApp(std::string name) {
  SYROF_CHECK(!replay_.has_value() && sinks_.empty());
  app_name_ = std::move(name);
}

replay::Header RoundRecorder::Header() const {
  replay::Header header = ReplayHeader(scenario_);
  header.app_name = app_name();
  return header;
}

void RoundRecorder::OpenReplay(std::ostream& out) {
  SYROF_CHECK(!replay_.has_value());
  replay_.emplace(out, Header());
}

void RoundRecorder::AddSink(replay::RoundSink* sink) {
  SYROF_CHECK(sink != nullptr && !finished_);
  sinks_.push_back(sink);
  sink->OnHeader(Header());
}

void RoundRecorder::OnEpochStart(uint16_t robot, int64_t round, int64_t time_ns, const sync::LDMap& ldmap) {
  collector_.OnEpochStart(robot, round, time_ns, ldmap);
  if (!any_epoch_ || sync::EpochDifference(ldmap.epoch, newest_epoch_) > 0) {
    any_epoch_ = true;
    newest_epoch_ = ldmap.epoch;
    epoch_sample_ = ldmap.epoch;
  }
}

void RoundRecorder::RecordRound(const RecordedRound& round) {
  collector_.OnRoundPhases(round.phase_boundaries_ns);
  collector_.OnRoundEnd(round.round, round.robots);
  if (!goal_monitor_.empty()) {
    const std::vector<goals::RobotPose> running = round.running_poses();
    const double time_s = static_cast<double>(round.time_ns) * 1e-9;
    goal_monitor_.OnRound(time_s, running);
    if (epoch_sample_) goal_monitor_.OnEpoch(*epoch_sample_, time_s, running);
  }
  epoch_sample_.reset();
  if (!replaying()) return;
  std::stable_sort(round.maps.begin(), round.maps.end(),
                   [](const replay::RobotMap& a, const replay::RobotMap& b) { return a.robot < b.robot; });
  const auto index = static_cast<uint32_t>(round.round);
  const std::span<const replay::Event> events = WithLostBeacons(round);
  if (replay_) replay_->WriteRound(index, round.time_ns, round.frames, events, round.maps);
  for (replay::RoundSink* sink : sinks_) sink->OnRound(index, round.time_ns, round.frames, events, round.maps);
}

void RoundRecorder::FinishReplay(bool complete) {
  if (finished_) return;
  finished_ = true;
  if (replay_) replay_->Finish();
  for (replay::RoundSink* sink : sinks_) sink->OnFinish(complete);
}

std::optional<Error> RoundRecorder::replay_error() const {
  if (!replay_ || replay_->ok()) return std::nullopt;
  return replay_->error();
}

metrics::RunFacts RoundRecorder::Facts(const RunEnd& end, const WorldPlayer& player, const world::World& world) {
  metrics::RunFacts facts = ScenarioFacts(scenario_, world);
  facts.sim_seconds = end.sim_seconds;
  facts.wall_seconds = end.wall_seconds;
  facts.radio_rounds = end.radio_rounds;
  if (goal_monitor_.empty()) {
    facts.goal = BuiltinGoal(scenario_, player.FinalPoses());
    facts.goal.app = app_name();  // the app that was judged, whose checker it was or not
  } else {
    facts.goal = DeclaredGoal(app_name(), goal_monitor_.Finish(end.sim_seconds, player.RunningPoses()));
  }
  return facts;
}

void RoundRecorder::OnAppState(uint16_t robot, int64_t round, metrics::AgreementTracker::Call call, uint16_t epoch,
                               bool cooperative, uint64_t map_fingerprint, uint8_t state) {
  if (!agreement_) agreement_.emplace();
  agreement_->OnAppState(robot, round, call, epoch, cooperative, map_fingerprint, state);
}

metrics::Metrics RoundRecorder::Finish(const metrics::RunFacts& facts) const {
  metrics::Metrics result = collector_.Finish(facts);
  if (agreement_) result.agreement = agreement_->Finish();
  return result;
}

void RoundRecorder::AddToDigest(base::StateDigest& digest) const {
  collector_.AddToDigest(digest);
  digest.AddValue(agreement_.has_value());
  if (agreement_) agreement_->AddToDigest(digest);
  goal_monitor_.AddToDigest(digest);
  digest.AddValue(epoch_sample_.has_value());
  digest.AddValue(epoch_sample_.value_or(0));
}

int64_t RoundRecorder::PropertyBreaks() const {
  return collector_.PropertyBreaks() + (agreement_ ? agreement_->disagreeing_calls() : 0);
}

}  // namespace syrof::lab::sim
