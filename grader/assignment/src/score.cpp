#include "syrof/assignment/score.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace syrof::grader::assignment {
namespace {

using lab::metrics::Metrics;

std::string Format(const char* format, auto... values) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format, values...);
  return buffer;
}

// Points are shown and summed to the hundredth.
double Round(double points) { return std::round(points * 100.0) / 100.0; }

CriterionScore Make(const char* criterion, double max_points, double earned, std::string reason) {
  return {criterion, Round(std::clamp(earned, 0.0, max_points)), max_points, std::move(reason)};
}

std::string Plural(int64_t count, const char* one, const char* many) {
  return std::to_string(count) + " " + (count == 1 ? one : many);
}

// A goal missed because a joiner never joined says so: the checks alone
// only say where the robot is not ("robot 2 is 2.471 m from ...").
std::string WithUnjoined(std::string reason, const Metrics& metrics) {
  for (const std::string& line : lab::metrics::UnjoinedJoiners(metrics)) reason += "; " + line;
  return reason;
}

CriterionScore ScoreGoal(const GoalCriterion& rule, const Metrics& metrics) {
  const lab::metrics::GoalResult& goal = metrics.goal;
  if (goal.source == "scenario" && !goal.checks.empty() && rule.per_check) {
    const auto passed = std::count_if(goal.checks.begin(), goal.checks.end(),
                                      [](const lab::metrics::GoalCheckResult& check) { return check.passed; });
    const double share = static_cast<double>(passed) / static_cast<double>(goal.checks.size());
    const bool lost = passed < static_cast<std::ptrdiff_t>(goal.checks.size());
    return Make("goal", rule.points, rule.points * share, lost ? WithUnjoined(goal.detail, metrics) : goal.detail);
  }
  if (goal.reached) return Make("goal", rule.points, rule.points, "goal reached: " + goal.detail);
  return Make("goal", rule.points, 0.0, WithUnjoined("goal missed: " + goal.detail, metrics));
}

CriterionScore ScoreCollisions(const CollisionCriterion& rule, const Metrics& metrics) {
  const int64_t collisions = metrics.collisions.count;
  const int64_t walls = metrics.walls.contacts;
  const double lost = rule.per_collision * static_cast<double>(collisions) +
                      rule.per_wall_contact * static_cast<double>(walls);
  std::string reason;
  if (collisions == 0 && walls == 0) {
    reason = "no collision";
  } else {
    reason = Plural(collisions, "collision", "collisions") + " and " + Plural(walls, "wall contact", "wall contacts");
    if (!metrics.collisions.pairs.empty()) {
      const lab::metrics::CollisionEvent& first = metrics.collisions.pairs.front();
      reason += Format("; first: robots %u and %u at %.2f s", unsigned{first.a}, unsigned{first.b},
                       static_cast<double>(first.time_ns) / 1e9);
    } else if (!metrics.walls.first_contacts.empty()) {
      const lab::metrics::WallContactEvent& first = metrics.walls.first_contacts.front();
      reason += Format("; first: robot %u against a wall at %.2f s", unsigned{first.robot},
                       static_cast<double>(first.time_ns) / 1e9);
    }
    reason += Format(" (-%g per collision, -%g per wall contact)", rule.per_collision, rule.per_wall_contact);
  }
  return Make("collisions", rule.points, rule.points - lost, reason);
}

CriterionScore ScoreSafety(const SafetyCriterion& rule, const Metrics& metrics) {
  if (!metrics.safety.enabled) {
    return Make("safety", rule.points, rule.points, "the scenario turns the safety filter off: nothing to score");
  }
  const int64_t count = metrics.safety.interventions;
  std::string reason = count == 0 ? "the safety filter never had to step in"
                                  : Plural(count, "safety-filter intervention", "safety-filter interventions") +
                                        Format(" (-%g each)", rule.per_intervention);
  // Precautions are the filter's own insurance, not the app's doing.
  const int64_t precautions = metrics.safety.precautions;
  if (precautions > 0) {
    reason += "; " + Plural(precautions, "precaution", "precautions") +
              " not charged (the filter held a command that kept its rule, for its wider cover of the "
              "robot's own error)";
  }
  return Make("safety", rule.points, rule.points - rule.per_intervention * static_cast<double>(count), reason);
}

CriterionScore ScoreSynchrony(const SynchronyCriterion& rule, const Metrics& metrics) {
  const lab::metrics::SynchronyMetrics& synchrony = metrics.synchrony;
  if (synchrony.max_start_skew_rounds <= rule.max_skew_rounds) {
    return Make("synchrony", rule.points, rule.points,
                Format("every epoch started within %lld rounds (at most %lld allowed)",
                       static_cast<long long>(synchrony.max_start_skew_rounds),
                       static_cast<long long>(rule.max_skew_rounds)));
  }
  return Make("synchrony", rule.points, 0,
              Format("epoch %u started %lld rounds apart on different robots; at most %lld allowed",
                     unsigned{synchrony.max_skew_epoch.value_or(0)},
                     static_cast<long long>(synchrony.max_start_skew_rounds),
                     static_cast<long long>(rule.max_skew_rounds)));
}

CriterionScore ScoreCommonKnowledge(const CommonKnowledgeCriterion& rule, const Metrics& metrics) {
  const lab::metrics::CommonKnowledgeMetrics& knowledge = metrics.common_knowledge;
  if (knowledge.violations == 0) {
    return Make("common_knowledge", rule.points, rule.points, "every COOPERATIVE robot held the same map");
  }
  std::string reason = Plural(knowledge.violations, "common-knowledge (P3) violation", "common-knowledge (P3) violations");
  if (!knowledge.first_violations.empty()) {
    const lab::metrics::Violation& first = knowledge.first_violations.front();
    reason += Format("; first: robot %u's map in epoch %u differs from robot %u's", unsigned{first.robot},
                     unsigned{first.epoch}, unsigned{first.first_robot});
  }
  return Make("common_knowledge", rule.points, 0, reason);
}

CriterionScore ScoreAgreement(const AgreementCriterion& rule, const Metrics& metrics) {
  if (!metrics.agreement) {
    return Make("agreement", rule.points, 0, "the " + metrics.runtime + " runtime does not measure agreement");
  }
  const lab::metrics::AgreementMetrics& agreement = *metrics.agreement;
  if (!agreement.agreed_fraction) {
    return Make("agreement", rule.points, 0, "no epoch started COOPERATIVE, so agreement could not be shown");
  }
  const double fraction = *agreement.agreed_fraction;
  std::string reason = Format("the robots' global states agreed in %lld of %lld COOPERATIVE epochs",
                              static_cast<long long>(agreement.agreed_epochs),
                              static_cast<long long>(agreement.cooperative_epochs));
  if (agreement.first_disagreement) {
    const lab::metrics::Disagreement& first = *agreement.first_disagreement;
    const char* call = first.callback == "new_round" ? "newRound" : "endOfRound";
    reason += Format("; first in epoch %u: robot %u's %s returned %u, robot %u's %u", unsigned{first.epoch},
                     unsigned{first.robot}, call, unsigned{first.state}, unsigned{first.reference_robot},
                     unsigned{first.reference_state});
  }
  const double earned = fraction >= rule.min_fraction ? rule.points : rule.points * fraction;
  return Make("agreement", rule.points, earned, reason);
}

CriterionScore ScoreFaults(const FaultCriterion& rule, const Metrics& metrics) {
  const lab::metrics::AppMetrics& app = metrics.app;
  const auto faults = static_cast<int64_t>(app.faults.size());
  const double lost = rule.per_fault * static_cast<double>(faults) +
                      rule.per_invalid_command * static_cast<double>(app.invalid_commands.count) +
                      rule.per_refused_payload * static_cast<double>(app.payload_refused.count);
  if (faults == 0 && app.invalid_commands.count == 0 && app.payload_refused.count == 0) {
    return Make("faults", rule.points, rule.points, "the app never faulted");
  }
  std::string reason;
  if (faults > 0) {
    const lab::metrics::AppFault& first = app.faults.front();
    reason = Plural(faults, "robot's app faulted", "robots' apps faulted") +
             Format("; first: robot %u in %s at %.2f s: %s", unsigned{first.robot}, first.callback.c_str(),
                    static_cast<double>(first.time_ns) / 1e9, first.verdict.c_str()) +
             (first.detail.empty() ? "" : " (" + first.detail + ")");
  }
  if (app.invalid_commands.count > 0) {
    if (!reason.empty()) reason += "; ";
    reason += Plural(app.invalid_commands.count, "refused command", "refused commands");
    if (app.invalid_commands.first) reason += " (first: " + app.invalid_commands.first->what + ")";
  }
  if (app.payload_refused.count > 0) {
    if (!reason.empty()) reason += "; ";
    reason += Plural(app.payload_refused.count, "refused payload", "refused payloads");
  }
  return Make("faults", rule.points, rule.points - lost, reason);
}

}  // namespace

RunScore ScoreRun(const Rubric& rubric, const Metrics& metrics) {
  RunScore score;
  if (rubric.goal) score.criteria.push_back(ScoreGoal(*rubric.goal, metrics));
  if (rubric.collisions) score.criteria.push_back(ScoreCollisions(*rubric.collisions, metrics));
  if (rubric.safety) score.criteria.push_back(ScoreSafety(*rubric.safety, metrics));
  if (rubric.synchrony) score.criteria.push_back(ScoreSynchrony(*rubric.synchrony, metrics));
  if (rubric.common_knowledge) score.criteria.push_back(ScoreCommonKnowledge(*rubric.common_knowledge, metrics));
  if (rubric.agreement) score.criteria.push_back(ScoreAgreement(*rubric.agreement, metrics));
  if (rubric.faults) score.criteria.push_back(ScoreFaults(*rubric.faults, metrics));
  for (const CriterionScore& criterion : score.criteria) {
    score.points += criterion.points;
    score.max_points += criterion.max_points;
  }
  score.points = Round(score.points);
  score.max_points = Round(score.max_points);
  return score;
}

}  // namespace syrof::grader::assignment
