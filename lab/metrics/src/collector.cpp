#include "syrof/lab/metrics/collector.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "syrof/sync/synchronizer.h"
#include "syrof/sync/state_digest.h"

namespace syrof::lab::metrics {

namespace {

std::optional<double> Mean(int64_t sum, int64_t samples) {
  if (samples == 0) return std::nullopt;
  return static_cast<double>(sum) / static_cast<double>(samples);
}

}  // namespace

namespace {
constexpr int64_t kFineBinNs = 1'000;       // 1 us
constexpr int64_t kFineLimitNs = 2'000'000; // fine bins below 2 ms
constexpr int64_t kCoarseBinNs = 100'000;   // 100 us
constexpr size_t kFineBins = kFineLimitNs / kFineBinNs;
}  // namespace

void Collector::SkewTotals::Add(uint16_t epoch, int64_t skew_rounds, int64_t skew_ns) {
  ++epochs;
  sum_rounds += skew_rounds;
  sum_ns += skew_ns;
  max_ns = std::max(max_ns, skew_ns);
  if (skew_rounds > 0) ++with_skew;
  // Strictly greater: ties keep the epoch closed first.
  if (!has_max || skew_rounds > max_rounds) {
    has_max = true;
    max_rounds = skew_rounds;
    max_epoch = epoch;
  }
  const size_t last_bin = kSkewHistogramBins - 1;
  const size_t bin = skew_rounds >= static_cast<int64_t>(last_bin) ? last_bin : static_cast<size_t>(skew_rounds);
  ++histogram[bin];
}

void Collector::PhaseHistogram::Add(int64_t error_ns, int64_t count) {
  size_t bin = 0;
  if (error_ns < kFineLimitNs) {
    bin = static_cast<size_t>(error_ns / kFineBinNs);
  } else {
    bin = kFineBins + static_cast<size_t>((error_ns - kFineLimitNs) / kCoarseBinNs);
  }
  if (bin >= bins.size()) bin = bins.size() - 1;
  bins[bin] += count;
  samples += count;
  max_ns = std::max(max_ns, error_ns);
}

void Collector::PhaseHistogram::Clear() {
  std::fill(bins.begin(), bins.end(), 0);
  samples = 0;
  max_ns = 0;
}

// A percentile is the upper edge of the bin holding it (never above max).
PhaseErrorStats Collector::PhaseHistogram::Stats() const {
  PhaseErrorStats stats;
  stats.samples = samples;
  stats.max_ms = static_cast<double>(max_ns) * 1e-6;
  if (samples == 0) return stats;
  const auto percentile = [&](double fraction) {
    const auto wanted = static_cast<int64_t>(std::ceil(fraction * static_cast<double>(samples)));
    int64_t seen = 0;
    for (size_t bin = 0; bin < bins.size(); ++bin) {
      seen += bins[bin];
      if (seen >= wanted) {
        const int64_t edge = bin < kFineBins ? static_cast<int64_t>(bin + 1) * kFineBinNs
                                             : kFineLimitNs + static_cast<int64_t>(bin - kFineBins + 1) * kCoarseBinNs;
        return static_cast<double>(std::min(edge, max_ns)) * 1e-6;
      }
    }
    return stats.max_ms;
  };
  stats.p50_ms = percentile(0.5);
  stats.p99_ms = percentile(0.99);
  return stats;
}

void Collector::OnRoundPhases(std::span<const int64_t> boundaries_ns) {
  const int64_t round_ns = config_.radio_round_ns;
  const int64_t index = phase_round_index_++;
  if (boundaries_ns.size() < 2 || round_ns <= 0) return;
  ++phase_rounds_;
  // Each boundary's place in the round, in [0, round): a pair's difference
  // modulo the round is then one subtraction and one fold, the same number
  // as (a - b) mod round, without a division per pair.
  phase_residues_.resize(boundaries_ns.size());
  for (size_t a = 0; a < boundaries_ns.size(); ++a) {
    int64_t residue = boundaries_ns[a] % round_ns;
    if (residue < 0) residue += round_ns;
    phase_residues_[a] = residue;
  }
  // The histograms count pairs, so pairs with equal residues are counted
  // together: sorted, the residues form runs of equal values; a run of m
  // holds m(m-1)/2 pairs of error 0, and two runs of m and n hold m * n
  // pairs of one error. The counts, the largest error and so the bytes are
  // those of the N^2/2 pairs one by one, at the cost of the distinct values'
  // pairs (one, with the shared clock and the robots aligned: 1000 robots
  // were 500,000 pairs a round, twice, on the thread mode's serial path).
  std::sort(phase_residues_.begin(), phase_residues_.end());
  phase_groups_.clear();
  for (const int64_t residue : phase_residues_) {
    if (phase_groups_.empty() || phase_groups_.back().residue_ns != residue) {
      phase_groups_.push_back(PhaseGroup{residue, 0});
    }
    ++phase_groups_.back().count;
  }
  const auto pair_error = [round_ns](int64_t residue_a, int64_t residue_b) {
    int64_t d = residue_a - residue_b;
    if (d < 0) d += round_ns;
    return std::min(d, round_ns - d);
  };
  // Calls add(error, pairs) for every run and every two runs.
  const auto for_each_pair = [&](auto add) {
    for (size_t a = 0; a < phase_groups_.size(); ++a) {
      const int64_t count_a = phase_groups_[a].count;
      if (count_a > 1) add(int64_t{0}, count_a * (count_a - 1) / 2);
      for (size_t b = a + 1; b < phase_groups_.size(); ++b) {
        add(pair_error(phase_groups_[a].residue_ns, phase_groups_[b].residue_ns), count_a * phase_groups_[b].count);
      }
    }
  };
  int64_t worst = 0;
  for_each_pair([&](int64_t error, int64_t pairs) {
    worst = std::max(worst, error);
    phase_run_.Add(error, pairs);
  });
  if (worst > kPhaseThresholdNs) {
    phase_converged_.reset();
    phase_residual_.Clear();
    return;
  }
  if (!phase_converged_) phase_converged_ = index;
  for_each_pair([&](int64_t error, int64_t pairs) { phase_residual_.Add(error, pairs); });
}

void Collector::MixedModeTotals::Add(const EpochRecord& record) {
  if (!record.any_cooperative || !record.any_autonomous) return;
  ++epochs;
  robot_epochs += record.starts;
}

Collector::Collector(const CollectorConfig& config)
    : config_(config),
      tracks_(std::min<size_t>(config.robots, wire::kMaxSwarmSize)),
      robot_interventions_(tracks_.size(), 0),
      robot_starts_(tracks_.size(), 0),
      inactive_run_(tracks_.size(), 0),
      async_cycles_(tracks_.size()),
      robot_cooperative_starts_(tracks_.size(), 0) {
  // Errors reach half a round at most.
  const int64_t half_round_ns = std::max<int64_t>(config.radio_round_ns / 2, kFineLimitNs);
  const size_t bins = kFineBins + static_cast<size_t>((half_round_ns - kFineLimitNs) / kCoarseBinNs) + 2;
  phase_run_.bins.assign(bins, 0);
  phase_residual_.bins.assign(bins, 0);
}

void Collector::OnSafetyIntervention(int64_t time_ns, uint16_t robot, std::optional<uint16_t> other) {
  if (!Known(robot) || (other.has_value() && !Known(*other))) {
    ++ignored_observations_;
    return;
  }
  ++interventions_;
  ++robot_interventions_[robot];
  if (first_interventions_.size() < kMaxListedInterventions) {
    first_interventions_.push_back(SafetyIntervention{time_ns, robot, other});
  }
}

void Collector::OnSafetyPrecaution(uint16_t robot, std::optional<uint16_t> other) {
  if (!Known(robot) || (other.has_value() && !Known(*other))) {
    ++ignored_observations_;
    return;
  }
  ++precautions_;
}

void Collector::OnJoinWait(uint16_t robot, int64_t time_ns) {
  if (!Known(robot)) {
    ++ignored_observations_;
    return;
  }
  ++join_waits_;
  joiner_waits_.push_back(JoinWait{robot, time_ns, std::nullopt});
}

void Collector::OnJoinWaitEnd(uint16_t robot, int64_t time_ns) {
  for (auto wait = joiner_waits_.rbegin(); wait != joiner_waits_.rend(); ++wait) {
    if (wait->robot == robot && !wait->joined_ns) {
      wait->joined_ns = time_ns;
      return;
    }
  }
  ++ignored_observations_;
}

bool Collector::Known(uint16_t robot) const { return robot < tracks_.size(); }

Collector::EpochRecord* Collector::FindRecord(uint16_t epoch) {
  for (EpochRecord& record : open_epochs_) {
    if (record.epoch == epoch) return &record;
  }
  return nullptr;
}

// A record stays open while a robot could still start its epoch (collector.h,
// kRecordGraceRounds); closing it measures its skew and mode agreement.
void Collector::CloseRecords(int64_t round, std::span<const RobotRound> robots) {
  if (open_epochs_.empty()) return;
  for (const RobotRound& robot : robots) {
    if (!Known(robot.id) || !robot.sync_member) continue;
    const bool able = robot.running || (robot.paused && tracks_[robot.id].paused_rounds < config_.silence_rounds);
    if (!able) continue;
    EpochRecord* record = FindRecord(static_cast<uint16_t>(robot.epoch + 1));
    if (record != nullptr) record->last_able_round = round;
  }
  const auto closed = [round](const EpochRecord& record) {
    return round - record.last_able_round >= kRecordGraceRounds;
  };
  for (const EpochRecord& record : open_epochs_) {
    if (!closed(record)) continue;
    skews_.Add(record.epoch, record.last_round - record.first_round, record.last_ns - record.first_ns);
    mixed_.Add(record);
  }
  std::erase_if(open_epochs_, closed);
}

int64_t Collector::OfflineRounds(const RobotTrack& track, int64_t after, int64_t until) const {
  int64_t rounds = 0;
  for (const auto& [start, end] : track.offline) {
    const int64_t from = std::max(start, after);
    const int64_t to = std::min(end, until);
    if (to > from) rounds += to - from;
  }
  return rounds;
}

void Collector::OnEpochStart(uint16_t robot, int64_t round, const sync::LDMap& ldmap) {
  OnEpochStart(robot, round, (round + 1) * config_.radio_round_ns, ldmap);
}

void Collector::OnEpochStart(uint16_t robot, int64_t round, int64_t time_ns, const sync::LDMap& ldmap) {
  if (!Known(robot)) {
    ++ignored_observations_;
    return;
  }
  ++epoch_starts_;
  ++robot_starts_[robot];
  if (config_.activation.model != sync::ActivationModel::kFsync) {
    bool active = false;
    if (config_.activation.model == sync::ActivationModel::kSsync) {
      active = sync::IsActive(config_.activation, ldmap.epoch, ldmap.members, robot);
    } else {
      const sync::AsyncTracker::Step step = async_cycles_[robot].OnEpochStart(config_.activation, ldmap.epoch, robot);
      active = step.looks;
      move_epochs_ += step.moves ? 1 : 0;
      stale_move_epochs_ += step.moves && step.look_epoch != ldmap.epoch ? 1 : 0;
      cuts_ += step.looks && step.cycle.cut ? 1 : 0;
    }
    if (active) {
      ++active_starts_;
      inactive_run_[robot] = 0;
    } else {
      ++inactive_starts_;
      longest_inactive_run_ = std::max(longest_inactive_run_, ++inactive_run_[robot]);
    }
  }
  const bool cooperative = ldmap.mode == wire::Mode::kCooperative;
  if (cooperative) {
    ++cooperative_starts_;
    ++robot_cooperative_starts_[robot];
  }

  const uint16_t epoch = ldmap.epoch;
  EpochRecord* record = FindRecord(epoch);
  if (record == nullptr) {
    ++epochs_started_;
    EpochRecord opened;
    opened.epoch = epoch;
    opened.first_round = round;
    opened.last_round = round;
    opened.first_ns = time_ns;
    opened.last_ns = time_ns;
    opened.last_able_round = round;
    open_epochs_.push_back(std::move(opened));
    record = &open_epochs_.back();
  } else {
    if (record->starters.test(robot)) ++repeated_starts_;
    record->first_round = std::min(record->first_round, round);
    record->last_round = std::max(record->last_round, round);
    record->first_ns = std::min(record->first_ns, time_ns);
    record->last_ns = std::max(record->last_ns, time_ns);
  }
  record->starters.set(robot);
  ++record->starts;
  (cooperative ? record->any_cooperative : record->any_autonomous) = true;

  if (!cooperative) return;
  if (record->first_cooperative == nullptr) {
    record->first_cooperative = std::make_unique<sync::LDMap>(ldmap);
    record->first_cooperative_robot = robot;
    ++cooperative_epochs_;
  } else if (!record->first_cooperative->SameKnowledge(ldmap)) {
    ++violations_;
    if (first_violations_.size() < kMaxListedViolations) {
      first_violations_.push_back(Violation{epoch, robot, round, record->first_cooperative_robot});
    }
  }
}

void Collector::OnMembership(uint16_t observer, int64_t round, const wire::MemberSet& removed,
                             const wire::MemberSet& joined) {
  if (!Known(observer)) {
    ++ignored_observations_;
    return;
  }
  for (const uint16_t subject : removed) {
    if (!Known(subject)) {
      ++ignored_observations_;
      continue;
    }
    ++removals_;
    RobotTrack& track = tracks_[subject];
    if (!track.removed) {
      track.removed = true;
      ++robots_removed_;
    }
    if (track.running) {
      ++removals_of_running_;
    } else if (track.stopped_round >= 0) {
      // Rounds the observer itself was stopped (paused) are not silence it
      // heard: its failure detector did not run.
      const int64_t offline = OfflineRounds(tracks_[observer], track.stopped_round, round);
      const int64_t latency = std::max<int64_t>(0, round - track.stopped_round - offline);
      ++removal_latency_samples_;
      removal_latency_sum_rounds_ += latency;
      removal_latency_max_rounds_ = std::max(removal_latency_max_rounds_, latency);
    }
  }
  for (const uint16_t subject : joined) {
    if (!Known(subject)) {
      ++ignored_observations_;
      continue;
    }
    ++joins_;
    RobotTrack& track = tracks_[subject];
    if (!track.joined) {
      track.joined = true;
      ++robots_joined_;
    }
  }
}

void Collector::OnRoundEnd(int64_t round, std::span<const RobotRound> robots) {
  ++rounds_observed_;
  bool any_cooperative = false;
  bool any_autonomous = false;
  for (const RobotRound& robot : robots) {
    if (!Known(robot.id)) {
      ++ignored_observations_;
      continue;
    }
    RobotTrack& track = tracks_[robot.id];
    const bool member = robot.running && robot.member;

    track.paused_rounds = robot.paused ? track.paused_rounds + 1 : 0;
    if (robot.running) {
      if (!track.offline.empty() && track.offline.back().second < 0) track.offline.back().second = round;
      track.running = true;
      track.stopped_round = -1;
      if (!member && track.joining_since < 0) {
        track.joining_since = round;
      } else if (member && track.joining_since >= 0) {
        const int64_t latency = round - track.joining_since;
        ++join_latency_samples_;
        join_latency_sum_rounds_ += latency;
        join_latency_max_rounds_ = std::max(join_latency_max_rounds_, latency);
        track.joining_since = -1;
      }
    } else {
      if (track.running) {
        track.stopped_round = round;
        track.offline.emplace_back(round, -1);
      }
      track.running = false;
      track.joining_since = -1;
    }

    if (member) {
      if (robot.epoch_mode == wire::Mode::kCooperative) {
        any_cooperative = true;
      } else {
        any_autonomous = true;
      }
    }

    if (robot.running && robot.estimate_valid) {
      const double dx_m = robot.est_x_m - robot.true_x_m;
      const double dy_m = robot.est_y_m - robot.true_y_m;
      const double squared_m2 = dx_m * dx_m + dy_m * dy_m;
      if (!std::isfinite(squared_m2)) {
        ++non_finite_estimates_;
      } else {
        ++estimate_samples_;
        squared_error_sum_m2_ += squared_m2;
        const double error_m = std::sqrt(squared_m2);
        if (estimate_samples_ == 1 || error_m > max_error_m_) {
          max_error_m_ = error_m;
          max_error_robot_ = robot.id;
          max_error_round_ = round;
        }
      }
    }
  }

  CloseRecords(round, robots);

  if (any_cooperative && any_autonomous) {
    ++disagreement_run_rounds_;
    ++disagreement_rounds_;
    max_disagreement_rounds_ = std::max(max_disagreement_rounds_, disagreement_run_rounds_);
  } else {
    disagreement_run_rounds_ = 0;
  }
}

void Collector::OnCollision(int64_t time_ns, uint16_t a, uint16_t b) {
  if (!Known(a) || !Known(b) || a == b) {
    ++ignored_observations_;
    return;
  }
  if (b < a) std::swap(a, b);
  ++collisions_;
  for (const uint16_t robot : {a, b}) {
    if (!tracks_[robot].collided) {
      tracks_[robot].collided = true;
      ++robots_collided_;
    }
  }
  if (first_collisions_.size() < kMaxListedCollisions) {
    first_collisions_.push_back(CollisionEvent{time_ns, a, b});
  }
}

void Collector::OnWallContact(int64_t time_ns, uint16_t robot) {
  if (!Known(robot)) {
    ++ignored_observations_;
    return;
  }
  ++wall_contacts_;
  if (!tracks_[robot].touched_wall) {
    tracks_[robot].touched_wall = true;
    ++robots_touched_wall_;
  }
  if (first_wall_contacts_.size() < kMaxListedWallContacts) {
    first_wall_contacts_.push_back(WallContactEvent{time_ns, robot});
  }
}

void Collector::OnAppFault(const AppFault& fault) {
  if (!Known(fault.robot)) {
    ++ignored_observations_;
    return;
  }
  if (tracks_[fault.robot].app_faulted) return;
  tracks_[fault.robot].app_faulted = true;
  app_faults_.push_back(fault);
}

namespace {

void Count(AppIncidents& incidents, uint16_t robot, uint16_t epoch, std::string_view what) {
  ++incidents.count;
  if (!incidents.first) incidents.first = AppIncident{robot, epoch, std::string(what)};
}

}  // namespace

void Collector::OnInvalidCommand(uint16_t robot, uint16_t epoch, std::string_view what) {
  if (!Known(robot)) {
    ++ignored_observations_;
    return;
  }
  Count(invalid_commands_, robot, epoch, what);
}

void Collector::OnPayloadRefused(uint16_t robot, uint16_t epoch, std::string_view what) {
  if (!Known(robot)) {
    ++ignored_observations_;
    return;
  }
  Count(payloads_refused_, robot, epoch, what);
}

Metrics Collector::Finish(const RunFacts& facts) const {
  Metrics metrics;
  metrics.scenario = facts.scenario;
  metrics.app.name = facts.app_name;
  metrics.app.source = facts.app_source;
  metrics.app.sandbox = facts.app_sandbox;
  metrics.app.faults = app_faults_;
  metrics.app.invalid_commands = invalid_commands_;
  metrics.app.payload_refused = payloads_refused_;
  metrics.seed = facts.seed;
  metrics.robots = facts.robots;
  metrics.sim_seconds = facts.sim_seconds;
  metrics.wall_seconds = facts.wall_seconds;
  metrics.radio_rounds = facts.radio_rounds;
  metrics.radio_round_ns = config_.radio_round_ns;
  metrics.epochs_started = epochs_started_;
  metrics.epoch_starts = epoch_starts_;
  metrics.goal = facts.goal;
  if (config_.activation.model != sync::ActivationModel::kFsync) {
    ActivationMetrics& activation = metrics.activation.emplace();
    activation.model = sync::ToString(config_.activation.model);
    activation.schedule = sync::ToString(config_.activation.schedule);
    if (config_.activation.model == sync::ActivationModel::kSsync &&
        config_.activation.schedule == sync::ActivationSchedule::kRandom) {
      activation.fair_within = config_.activation.fair_within;
    }
    activation.active_starts = active_starts_;
    activation.inactive_starts = inactive_starts_;
    activation.fair_within_achieved = longest_inactive_run_ + 1;
    if (config_.activation.model == sync::ActivationModel::kAsync) {
      AsyncActivationMetrics& async = activation.async.emplace();
      async.max_delay_epochs = config_.activation.max_delay_epochs;
      async.min_move_m = config_.activation.min_move_mm / 1000.0;
      async.move_epochs = move_epochs_;
      async.stale_move_epochs = stale_move_epochs_;
      async.moves_cut = cuts_;
    }
  }

  // Epochs still open are measured as they stand, in the order they opened.
  SkewTotals skews = skews_;
  MixedModeTotals mixed = mixed_;
  for (const EpochRecord& record : open_epochs_) {
    skews.Add(record.epoch, record.last_round - record.first_round, record.last_ns - record.first_ns);
    mixed.Add(record);
  }
  SynchronyMetrics& synchrony = metrics.synchrony;
  synchrony.epochs_measured = skews.epochs;
  synchrony.max_start_skew_rounds = skews.max_rounds;
  if (skews.has_max) synchrony.max_skew_epoch = skews.max_epoch;
  synchrony.mean_start_skew_rounds = Mean(skews.sum_rounds, skews.epochs);
  synchrony.epochs_with_skew = skews.with_skew;
  synchrony.skew_histogram = skews.histogram;
  synchrony.stale_starts = stale_starts_;
  synchrony.max_start_skew_ms = static_cast<double>(skews.max_ns) * 1e-6;
  if (skews.epochs > 0) synchrony.mean_start_skew_ms = static_cast<double>(skews.sum_ns) * 1e-6 / static_cast<double>(skews.epochs);

  RoundPhaseMetrics& phase = metrics.round_phase;
  phase.threshold_ms = static_cast<double>(kPhaseThresholdNs) * 1e-6;
  phase.rounds_measured = phase_rounds_;
  phase.run = phase_run_.Stats();
  if (phase_converged_) {
    // The end of the round that began the stretch (OnRoundPhases is called
    // at every round end from the first).
    phase.converged_s =
        static_cast<double>(*phase_converged_ + 1) * static_cast<double>(config_.radio_round_ns) * 1e-9;
    phase.residual = phase_residual_.Stats();
  }
  synchrony.repeated_starts = repeated_starts_;

  CommonKnowledgeMetrics& knowledge = metrics.common_knowledge;
  knowledge.violations = violations_;
  knowledge.first_violations = first_violations_;
  knowledge.cooperative_starts = cooperative_starts_;
  knowledge.autonomous_starts = epoch_starts_ - cooperative_starts_;
  if (epoch_starts_ > 0) {
    knowledge.cooperative_fraction =
        static_cast<double>(cooperative_starts_) / static_cast<double>(epoch_starts_);
  }
  knowledge.cooperative_epochs = cooperative_epochs_;
  knowledge.unchecked_cooperative_starts = unchecked_cooperative_starts_;
  knowledge.max_mode_disagreement_rounds = max_disagreement_rounds_;
  knowledge.mixed_mode_epochs = mixed.epochs;
  knowledge.mixed_mode_robot_epochs = mixed.robot_epochs;
  knowledge.starts_by_robot = robot_starts_;
  knowledge.cooperative_starts_by_robot = robot_cooperative_starts_;
  knowledge.mode_disagreement_rounds = disagreement_rounds_;

  metrics.collisions.count = collisions_;
  metrics.collisions.min_separation_m = facts.min_separation_m;
  metrics.collisions.robots_involved = robots_collided_;
  metrics.collisions.pairs = first_collisions_;

  metrics.walls.contacts = wall_contacts_;
  metrics.walls.robots_involved = robots_touched_wall_;
  metrics.walls.first_contacts = first_wall_contacts_;
  metrics.safety.enabled = facts.safety_enabled;
  metrics.safety.interventions = interventions_;
  metrics.safety.precautions = precautions_;
  for (size_t robot = 0; robot < robot_interventions_.size(); ++robot) {
    if (robot_interventions_[robot] == 0) continue;
    ++metrics.safety.robots_involved;
    metrics.safety.per_robot.push_back(
        RobotInterventions{static_cast<uint16_t>(robot), robot_interventions_[robot]});
  }
  metrics.safety.first = first_interventions_;
  metrics.safety.join_waits = join_waits_;
  metrics.safety.joiner_waits = joiner_waits_;

  EstimationMetrics& estimation = metrics.estimation;
  estimation.samples = estimate_samples_;
  estimation.non_finite_samples = non_finite_estimates_;
  if (estimate_samples_ > 0) {
    estimation.position_rmse_m = std::sqrt(squared_error_sum_m2_ / static_cast<double>(estimate_samples_));
    estimation.max_error_m = max_error_m_;
    estimation.max_error_robot = max_error_robot_;
    estimation.max_error_round = max_error_round_;
  }

  MembershipMetrics& membership = metrics.membership;
  membership.removals = removals_;
  membership.joins = joins_;
  membership.robots_removed = robots_removed_;
  membership.robots_joined = robots_joined_;
  membership.removals_of_running_robots = removals_of_running_;
  if (removal_latency_samples_ > 0) membership.max_removal_latency_rounds = removal_latency_max_rounds_;
  membership.mean_removal_latency_rounds = Mean(removal_latency_sum_rounds_, removal_latency_samples_);
  membership.completed_joins = join_latency_samples_;
  if (join_latency_samples_ > 0) membership.max_join_latency_rounds = join_latency_max_rounds_;
  membership.mean_join_latency_rounds = Mean(join_latency_sum_rounds_, join_latency_samples_);

  metrics.diagnostics.rounds_observed = rounds_observed_;
  metrics.diagnostics.ignored_observations = ignored_observations_;
  return metrics;
}

void Collector::AddToDigest(base::StateDigest& digest) const {
  for (const EpochRecord& record : open_epochs_) {
    digest.AddValue(record.epoch);
    digest.AddValue(record.first_round);
    digest.AddValue(record.last_able_round);
    wire::AddToDigest(digest, record.starters);
    digest.AddValue(record.any_cooperative);
    digest.AddValue(record.any_autonomous);
    digest.AddValue(record.first_cooperative_robot);
    digest.AddValue(record.first_cooperative != nullptr);
    if (record.first_cooperative) sync::AddToDigest(digest, *record.first_cooperative, tracks_.size());
  }
  for (const RobotTrack& track : tracks_) {
    digest.AddValue(track.running);
    digest.AddValue(track.collided);
  }
}

}  // namespace syrof::lab::metrics
