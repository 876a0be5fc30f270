// metrics.json. The field order here is the order docs/metrics.md documents;
// ordered_json keeps it, so the file reads the same from run to run.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "syrof/lab/metrics/metrics.h"

namespace syrof::lab::metrics {

namespace {

using Json = nlohmann::ordered_json;

Json FiniteOrNull(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

Json FiniteOrNull(const std::optional<double>& value) {
  return value.has_value() ? FiniteOrNull(*value) : Json(nullptr);
}

template <typename Integer>
Json IntegerOrNull(const std::optional<Integer>& value) {
  return value.has_value() ? Json(*value) : Json(nullptr);
}

double Seconds(int64_t time_ns) { return static_cast<double>(time_ns) / 1e9; }

// The radio round a contact time falls in; null when the round length is unknown.
Json RoundOf(int64_t time_ns, int64_t radio_round_ns) {
  if (radio_round_ns <= 0) return Json(nullptr);
  return Json(time_ns / radio_round_ns);
}

Json GoalJson(const GoalResult& goal) {
  Json json;
  json["app"] = goal.app;
  json["reached"] = goal.reached;
  json["error_m"] = FiniteOrNull(goal.error_m);
  json["detail"] = goal.detail;
  json["source"] = goal.source;
  json["checks"] = Json::array();
  for (const GoalCheckResult& check : goal.checks) {
    Json entry;
    entry["name"] = check.name;
    entry["check"] = check.check;
    entry["when"] = check.when;
    entry["passed"] = check.passed;
    entry["value"] = FiniteOrNull(check.value);
    entry["limit"] = FiniteOrNull(check.limit);
    entry["unit"] = check.unit;
    entry["reason"] = check.reason;
    entry["samples"] = check.samples;
    entry["deadline_s"] = FiniteOrNull(check.deadline_s);
    entry["held_from_epoch"] = IntegerOrNull(check.held_from_epoch);
    entry["held_from_s"] = FiniteOrNull(check.held_from_s);
    json["checks"].push_back(entry);
  }
  return json;
}

Json IncidentsJson(const AppIncidents& incidents) {
  Json json;
  json["count"] = incidents.count;
  if (incidents.first) {
    Json first;
    first["robot"] = incidents.first->robot;
    first["epoch"] = incidents.first->epoch;
    first["what"] = incidents.first->what;
    json["first"] = first;
  } else {
    json["first"] = nullptr;
  }
  return json;
}

Json AppJson(const AppMetrics& app) {
  Json json;
  json["name"] = app.name;
  json["source"] = app.source;
  json["faults"] = Json::array();
  for (const AppFault& fault : app.faults) {
    Json entry;
    entry["robot"] = fault.robot;
    entry["callback"] = fault.callback;
    entry["epoch"] = fault.epoch;
    entry["time_s"] = Seconds(fault.time_ns);
    entry["verdict"] = fault.verdict;
    entry["detail"] = fault.detail;
    json["faults"].push_back(entry);
  }
  json["invalid_commands"] = IncidentsJson(app.invalid_commands);
  json["payload_refused"] = IncidentsJson(app.payload_refused);
  json["sandbox"] = app.sandbox ? Json(*app.sandbox) : Json(nullptr);
  return json;
}

Json SynchronyJson(const SynchronyMetrics& synchrony) {
  Json json;
  json["max_start_skew_rounds"] = synchrony.max_start_skew_rounds;
  json["max_skew_epoch"] = IntegerOrNull(synchrony.max_skew_epoch);
  json["mean_start_skew_rounds"] = FiniteOrNull(synchrony.mean_start_skew_rounds);
  json["epochs_measured"] = synchrony.epochs_measured;
  json["epochs_with_skew"] = synchrony.epochs_with_skew;
  json["skew_histogram"] = Json::array();
  for (const int64_t epochs : synchrony.skew_histogram) json["skew_histogram"].push_back(epochs);
  json["stale_starts"] = synchrony.stale_starts;
  json["repeated_starts"] = synchrony.repeated_starts;
  json["max_start_skew_ms"] = FiniteOrNull(synchrony.max_start_skew_ms);
  json["mean_start_skew_ms"] = FiniteOrNull(synchrony.mean_start_skew_ms);
  return json;
}

Json PhaseStatsJson(const PhaseErrorStats& stats) {
  Json json;
  json["samples"] = stats.samples;
  json["p50_ms"] = FiniteOrNull(stats.p50_ms);
  json["p99_ms"] = FiniteOrNull(stats.p99_ms);
  json["max_ms"] = FiniteOrNull(stats.max_ms);
  return json;
}

Json RoundPhaseJson(const RoundPhaseMetrics& phase) {
  Json json;
  json["threshold_ms"] = FiniteOrNull(phase.threshold_ms);
  json["rounds_measured"] = phase.rounds_measured;
  json["converged_s"] = FiniteOrNull(phase.converged_s);
  json["run"] = PhaseStatsJson(phase.run);
  json["residual"] = PhaseStatsJson(phase.residual);
  return json;
}

Json CommonKnowledgeJson(const CommonKnowledgeMetrics& knowledge) {
  Json json;
  json["violations"] = knowledge.violations;
  json["first_violations"] = Json::array();
  for (const Violation& violation : knowledge.first_violations) {
    Json entry;
    entry["epoch"] = violation.epoch;
    entry["robot"] = violation.robot;
    entry["round"] = violation.round;
    entry["first_robot"] = violation.first_robot;
    json["first_violations"].push_back(entry);
  }
  json["cooperative_fraction"] = FiniteOrNull(knowledge.cooperative_fraction);
  json["cooperative_starts"] = knowledge.cooperative_starts;
  json["autonomous_starts"] = knowledge.autonomous_starts;
  json["cooperative_epochs"] = knowledge.cooperative_epochs;
  json["unchecked_cooperative_starts"] = knowledge.unchecked_cooperative_starts;
  json["max_mode_disagreement_rounds"] = knowledge.max_mode_disagreement_rounds;
  json["mode_disagreement_rounds"] = knowledge.mode_disagreement_rounds;
  json["mixed_mode_epochs"] = knowledge.mixed_mode_epochs;
  json["mixed_mode_robot_epochs"] = knowledge.mixed_mode_robot_epochs;
  json["starts_by_robot"] = knowledge.starts_by_robot;
  json["cooperative_starts_by_robot"] = knowledge.cooperative_starts_by_robot;
  return json;
}

Json ActivationJson(const ActivationMetrics& activation) {
  Json json;
  json["model"] = activation.model;
  json["schedule"] = activation.schedule;
  json["fair_within"] = activation.fair_within ? Json(*activation.fair_within) : Json(nullptr);
  json["active_starts"] = activation.active_starts;
  json["inactive_starts"] = activation.inactive_starts;
  json["fair_within_achieved"] = activation.fair_within_achieved;
  if (activation.async) {
    const AsyncActivationMetrics& async = *activation.async;
    json["max_delay_epochs"] = async.max_delay_epochs;
    json["min_move_m"] = async.min_move_m;
    json["move_epochs"] = async.move_epochs;
    json["stale_move_epochs"] = async.stale_move_epochs;
    json["moves_cut"] = async.moves_cut;
  }
  return json;
}

Json AgreementJson(const std::optional<AgreementMetrics>& measured) {
  if (!measured) return Json(nullptr);
  const AgreementMetrics& agreement = *measured;
  Json json;
  json["cooperative_epochs"] = agreement.cooperative_epochs;
  json["agreed_epochs"] = agreement.agreed_epochs;
  json["agreed_fraction"] = FiniteOrNull(agreement.agreed_fraction);
  json["split_epochs"] = agreement.split_epochs;
  json["new_round_calls"] = agreement.new_round_calls;
  json["end_of_round_calls"] = agreement.end_of_round_calls;
  json["disagreeing_calls"] = agreement.disagreeing_calls;
  json["unchecked_calls"] = agreement.unchecked_calls;
  if (agreement.first_disagreement) {
    const Disagreement& first = *agreement.first_disagreement;
    Json entry;
    entry["epoch"] = first.epoch;
    entry["round"] = first.round;
    entry["callback"] = first.callback;
    entry["robot"] = first.robot;
    entry["state"] = first.state;
    entry["reference_robot"] = first.reference_robot;
    entry["reference_state"] = first.reference_state;
    json["first_disagreement"] = entry;
  } else {
    json["first_disagreement"] = nullptr;
  }
  return json;
}

Json CollisionsJson(const CollisionMetrics& collisions, int64_t radio_round_ns) {
  Json json;
  json["count"] = collisions.count;
  json["min_separation_m"] = FiniteOrNull(collisions.min_separation_m);
  json["robots_involved"] = collisions.robots_involved;
  json["pairs"] = Json::array();
  for (const CollisionEvent& collision : collisions.pairs) {
    Json entry;
    entry["time_s"] = Seconds(collision.time_ns);
    entry["round"] = RoundOf(collision.time_ns, radio_round_ns);
    entry["a"] = collision.a;
    entry["b"] = collision.b;
    json["pairs"].push_back(entry);
  }
  return json;
}

Json WallsJson(const WallMetrics& walls, int64_t radio_round_ns) {
  Json json;
  json["contacts"] = walls.contacts;
  json["robots_involved"] = walls.robots_involved;
  json["first_contacts"] = Json::array();
  for (const WallContactEvent& contact : walls.first_contacts) {
    Json entry;
    entry["time_s"] = Seconds(contact.time_ns);
    entry["round"] = RoundOf(contact.time_ns, radio_round_ns);
    entry["robot"] = contact.robot;
    json["first_contacts"].push_back(entry);
  }
  return json;
}

Json SafetyJson(const SafetyMetrics& safety, int64_t radio_round_ns) {
  Json json;
  json["enabled"] = safety.enabled;
  json["interventions"] = safety.interventions;
  json["precautions"] = safety.precautions;
  json["robots_involved"] = safety.robots_involved;
  json["per_robot"] = Json::array();
  for (const RobotInterventions& robot : safety.per_robot) {
    Json entry;
    entry["robot"] = robot.robot;
    entry["interventions"] = robot.interventions;
    json["per_robot"].push_back(entry);
  }
  json["first_interventions"] = Json::array();
  for (const SafetyIntervention& intervention : safety.first) {
    Json entry;
    entry["time_s"] = Seconds(intervention.time_ns);
    entry["round"] = RoundOf(intervention.time_ns, radio_round_ns);
    entry["robot"] = intervention.robot;
    entry["against"] = intervention.other.has_value() ? Json(*intervention.other) : Json("wall");
    json["first_interventions"].push_back(entry);
  }
  json["join_waits"] = safety.join_waits;
  json["joiner_waits"] = Json::array();
  for (const JoinWait& wait : safety.joiner_waits) {
    Json entry;
    entry["robot"] = wait.robot;
    entry["from_s"] = Seconds(wait.from_ns);
    entry["joined_s"] = wait.joined_ns ? Json(Seconds(*wait.joined_ns)) : Json(nullptr);
    json["joiner_waits"].push_back(entry);
  }
  return json;
}

Json EstimationJson(const EstimationMetrics& estimation) {
  Json json;
  json["position_rmse_m"] = FiniteOrNull(estimation.position_rmse_m);
  json["max_error_m"] = FiniteOrNull(estimation.max_error_m);
  json["max_error_robot"] = IntegerOrNull(estimation.max_error_robot);
  json["max_error_round"] = IntegerOrNull(estimation.max_error_round);
  json["samples"] = estimation.samples;
  json["non_finite_samples"] = estimation.non_finite_samples;
  return json;
}

Json MembershipJson(const MembershipMetrics& membership) {
  Json json;
  json["removals"] = membership.removals;
  json["joins"] = membership.joins;
  json["robots_removed"] = membership.robots_removed;
  json["robots_joined"] = membership.robots_joined;
  json["removals_of_running_robots"] = membership.removals_of_running_robots;
  json["max_removal_latency_rounds"] = IntegerOrNull(membership.max_removal_latency_rounds);
  json["mean_removal_latency_rounds"] = FiniteOrNull(membership.mean_removal_latency_rounds);
  json["completed_joins"] = membership.completed_joins;
  json["max_join_latency_rounds"] = IntegerOrNull(membership.max_join_latency_rounds);
  json["mean_join_latency_rounds"] = FiniteOrNull(membership.mean_join_latency_rounds);
  return json;
}

Json SkewJson(const SkewStats& skew) {
  Json json;
  json["rounds"] = skew.samples;
  json["p50"] = FiniteOrNull(skew.p50_us);
  json["p99"] = FiniteOrNull(skew.p99_us);
  json["max"] = FiniteOrNull(skew.max_us);
  return json;
}

// `skew`: the run's round-start skew, also written here as in layout
// version 2 (docs/metrics.md, `dds`).
Json DdsJson(const DdsMetrics& dds, const std::optional<SkewStats>& skew) {
  Json json;
  json["domain_id"] = dds.domain_id;
  json["delivery_ratio"] = FiniteOrNull(dds.delivery_ratio);
  if (skew) json["round_start_skew_us"] = SkewJson(*skew);
  json["cpu_seconds_per_robot"] = Json::array();
  for (const double seconds : dds.cpu_seconds_per_robot) json["cpu_seconds_per_robot"].push_back(FiniteOrNull(seconds));
  json["reports_rejected"] = dds.reports_rejected;
  json["reports_late"] = dds.reports_late;
  json["reports_other_runs"] = dds.reports_other_runs;
  json["drives_other_runs"] = dds.drives_other_runs;
  json["stopped_early"] = dds.stopped_early;
  json["robot_exits"] = Json::array();
  for (const std::optional<int>& exit : dds.robot_exits) json["robot_exits"].push_back(IntegerOrNull(exit));
  return json;
}

}  // namespace

std::vector<std::string> UnjoinedJoiners(const Metrics& metrics) {
  std::vector<std::string> lines;
  for (const JoinWait& wait : metrics.safety.joiner_waits) {
    if (wait.joined_ns) continue;
    const double from_s = Seconds(wait.from_ns);
    char line[160];
    std::snprintf(line, sizeof line,
                  "robot %u never joined: it waited %.1f s for a clear start disc (from %.1f s to the end)",
                  unsigned{wait.robot}, std::max(0.0, metrics.sim_seconds - from_s), from_s);
    lines.emplace_back(line);
  }
  return lines;
}

std::string ToJson(const Metrics& metrics) {
  Json json;
  json["schema_version"] = kSchemaVersion;
  json["runtime"] = metrics.runtime;
  json["scenario"] = metrics.scenario;
  json["app"] = AppJson(metrics.app);
  json["seed"] = metrics.seed;
  json["robots"] = metrics.robots;
  json["sim_seconds"] = FiniteOrNull(metrics.sim_seconds);
  json["wall_seconds"] = FiniteOrNull(metrics.wall_seconds);
  json["radio_rounds"] = metrics.radio_rounds;
  json["radio_round_s"] = metrics.radio_round_ns > 0 ? Json(Seconds(metrics.radio_round_ns)) : Json(nullptr);
  json["epochs_started"] = metrics.epochs_started;
  json["epoch_starts"] = metrics.epoch_starts;
  json["goal"] = GoalJson(metrics.goal);
  if (metrics.activation) json["activation"] = ActivationJson(*metrics.activation);
  json["synchrony"] = SynchronyJson(metrics.synchrony);
  json["round_phase"] = RoundPhaseJson(metrics.round_phase);
  if (metrics.round_start_skew) json["round_start_skew_us"] = SkewJson(*metrics.round_start_skew);
  json["common_knowledge"] = CommonKnowledgeJson(metrics.common_knowledge);
  json["agreement"] = AgreementJson(metrics.agreement);
  json["collisions"] = CollisionsJson(metrics.collisions, metrics.radio_round_ns);
  json["walls"] = WallsJson(metrics.walls, metrics.radio_round_ns);
  json["safety"] = SafetyJson(metrics.safety, metrics.radio_round_ns);
  json["estimation"] = EstimationJson(metrics.estimation);
  json["membership"] = MembershipJson(metrics.membership);
  Json diagnostics;
  diagnostics["rounds_observed"] = metrics.diagnostics.rounds_observed;
  diagnostics["ignored_observations"] = metrics.diagnostics.ignored_observations;
  json["diagnostics"] = diagnostics;
  if (metrics.dds) json["dds"] = DdsJson(*metrics.dds, metrics.round_start_skew);
  // Strings come from scenario files and student apps; replacing invalid
  // UTF-8 keeps a bad byte from losing the whole report (dump would throw).
  return json.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace syrof::lab::metrics
