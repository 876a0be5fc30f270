#include "syrof/lab/view/verdict.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <utility>

#include "syrof/lab/apps/catalog.h"
#include "syrof/lab/apps/formation.h"
#include "syrof/lab/goals/goals.h"

namespace syrof::lab::view {
namespace {

using nlohmann::json;

std::string Plural(int64_t count, std::string_view one, std::string_view many) {
  return fmt::format("{} {}", count, count == 1 ? one : many);
}

// "lost beacon at round 23, 0 → 1" or "3 lost beacons: round 23, 0 → 1; ...".
std::string LostText(const std::vector<LostBeaconSeen>& lost) {
  constexpr size_t kListed = 4;
  if (lost.size() == 1) return fmt::format("lost beacon at round {}, {} → {}", lost[0].round, lost[0].from, lost[0].to);
  std::string text = fmt::format("{} lost beacons:", lost.size());
  for (size_t i = 0; i < lost.size() && i < kListed; ++i) {
    text += fmt::format("{} round {}, {} → {}", i == 0 ? "" : ";", lost[i].round, lost[i].from, lost[i].to);
  }
  if (lost.size() > kListed) text += fmt::format(" and {} more", lost.size() - kListed);
  return text;
}

// Why the goal was missed, in one line: the first failing check's reason,
// or the built-in goal's detail.
std::string GoalMissedText(const metrics::GoalResult& goal) {
  for (const metrics::GoalCheckResult& check : goal.checks) {
    if (!check.passed) return fmt::format("{}: {}", check.name, check.reason);
  }
  return goal.detail;
}

std::string GoalLine(const metrics::GoalResult& goal) {
  if (goal.source != "scenario") return goal.detail;
  size_t passed = 0;
  for (const metrics::GoalCheckResult& check : goal.checks) passed += check.passed ? 1 : 0;
  std::string text = fmt::format("{} of {} checks held", passed, goal.checks.size());
  for (const metrics::GoalCheckResult& check : goal.checks) {
    text += fmt::format("; {} {}: {}", check.name, check.passed ? "held" : "FAILED", check.reason);
  }
  return text;
}

}  // namespace

std::string_view ToString(VerdictState state) {
  switch (state) {
    case VerdictState::kOk: return "ok";
    case VerdictState::kUnjudged: return "unjudged";
    case VerdictState::kMissed: return "missed";
    case VerdictState::kBroken: return "broken";
  }
  return "broken";
}

Verdict VerdictOf(const metrics::Metrics& m, const ReplayFacts& facts) {
  Verdict verdict;
  std::vector<std::string> broken;  // what broke, most telling first

  // The app's agreement: the app's own global state differed between robots
  // that held the same map in a COOPERATIVE epoch.
  if (!m.agreement) {
    verdict.lines.push_back({"agreement", true, "not measured: this runtime cannot see the app's returns"});
  } else if (m.agreement->disagreeing_calls > 0) {
    std::string text;
    if (const auto& first = m.agreement->first_disagreement) {
      text = fmt::format("agreement split in epoch {}: robot {} holds {}, robot {} holds {} ({}, round {})",
                         first->epoch, first->robot, first->state, first->reference_robot, first->reference_state,
                         first->callback == "new_round" ? "newRound" : "endOfRound", first->round);
    } else {
      text = "agreement split";
    }
    broken.push_back(text);
    verdict.lines.push_back({"agreement", false,
                             fmt::format("{}; {} differed, in {} of {} COOPERATIVE epochs", text,
                                         Plural(m.agreement->disagreeing_calls, "call", "calls"),
                                         m.agreement->cooperative_epochs - m.agreement->agreed_epochs,
                                         m.agreement->cooperative_epochs)});
  } else {
    verdict.lines.push_back(
        {"agreement", true,
         fmt::format("the app's state agreed in every COOPERATIVE epoch ({})", m.agreement->cooperative_epochs)});
  }

  // P3: robots that started an epoch COOPERATIVE with different maps.
  const metrics::CommonKnowledgeMetrics& ck = m.common_knowledge;
  if (ck.violations > 0) {
    std::string text = fmt::format("P3 violated ({})", Plural(ck.violations, "start", "starts"));
    if (!ck.first_violations.empty()) {
      const metrics::Violation& first = ck.first_violations.front();
      text = fmt::format("P3 violated in epoch {}: robot {} started it COOPERATIVE with another map than robot {} "
                         "(round {}; {} in all)",
                         first.epoch, first.robot, first.first_robot, first.round,
                         Plural(ck.violations, "start", "starts"));
    }
    broken.push_back(text);
    verdict.lines.push_back({"P3", false, text});
  } else {
    verdict.lines.push_back({"P3", true, "no violation: every COOPERATIVE epoch was started with one map"});
  }

  if (m.collisions.count > 0) {
    std::string text = Plural(m.collisions.count, "collision", "collisions");
    if (!m.collisions.pairs.empty()) {
      const metrics::CollisionEvent& first = m.collisions.pairs.front();
      text += fmt::format(", the first robots {} and {} at {:.2f} s", first.a, first.b,
                          static_cast<double>(first.time_ns) / 1e9);
    }
    broken.push_back(text);
    verdict.lines.push_back({"collisions", false, text});
  } else {
    verdict.lines.push_back({"collisions", true, "none"});
  }

  if (!m.app.faults.empty()) {
    const metrics::AppFault& first = m.app.faults.front();
    std::string text = fmt::format("robot {}'s app failed in {} of epoch {}: {}", first.robot, first.callback,
                                   first.epoch, first.verdict);
    if (!first.detail.empty()) text += fmt::format(" ({})", first.detail);
    broken.push_back(text);
    verdict.lines.push_back({"app", false, text});
  } else if (m.app.invalid_commands.count > 0 || m.app.payload_refused.count > 0) {
    const std::string text =
        fmt::format("{} refused, {} refused", Plural(m.app.invalid_commands.count, "command", "commands"),
                    Plural(m.app.payload_refused.count, "payload", "payloads"));
    broken.push_back(text);
    verdict.lines.push_back({"app", false, text});
  } else {
    verdict.lines.push_back({"app", true, "no fault, no refused command or payload"});
  }

  // A library's run without `goal:` has no goal to meet (the built-in
  // goals are the built-in apps'): not held against it.
  const bool no_goal = m.goal.source != "scenario" && !m.goal.app.starts_with("builtin:");
  const bool reached = m.goal.reached || no_goal;
  verdict.lines.insert(verdict.lines.begin(),
                       {"goal", reached,
                        no_goal ? "none declared: the scenario has no `goal:`"
                                : fmt::format("{}: {}", reached ? "met" : "missed", GoalLine(m.goal))});
  if (!facts.lost.empty()) verdict.lines.push_back({"lost beacons", true, LostText(facts.lost)});

  const std::string lost = facts.lost.empty() ? "" : "; " + LostText(facts.lost);
  if (!broken.empty()) {
    verdict.state = VerdictState::kBroken;
    verdict.headline = "BROKEN: " + broken.front() + lost;
  } else if (!reached) {
    verdict.state = VerdictState::kMissed;
    verdict.headline = "Goal missed: " + GoalMissedText(m.goal) + lost;
  } else if (no_goal) {
    verdict.state = VerdictState::kOk;
    verdict.headline = "Nothing broken (no goal declared): no P3 violation, no collision, no app fault" + lost;
  } else {
    verdict.state = VerdictState::kOk;
    verdict.headline = "Goal met: " + GoalLine(m.goal) + lost;
  }
  return verdict;
}

Verdict VerdictOfReplay(const ReplayFacts& facts) {
  Verdict verdict;
  const std::string collisions = Plural(facts.collisions, "collision", "collisions");
  const std::string faults = Plural(facts.app_faults, "app fault", "app faults");
  verdict.lines.push_back(
      {"goal", true, "not judged here: this page was made from the replay alone, without the run's metrics"});
  verdict.lines.push_back({"collisions", facts.collisions == 0, facts.collisions == 0 ? "none" : collisions});
  verdict.lines.push_back({"app", facts.app_faults == 0, facts.app_faults == 0 ? "no fault" : faults});
  if (!facts.lost.empty()) verdict.lines.push_back({"lost beacons", true, LostText(facts.lost)});
  const std::string lost = facts.lost.empty() ? "" : "; " + LostText(facts.lost);
  if (facts.collisions > 0 || facts.app_faults > 0) {
    verdict.state = VerdictState::kBroken;
    verdict.headline = "BROKEN: " + (facts.collisions > 0 ? collisions : faults) + " in the replay" + lost;
  } else {
    verdict.state = VerdictState::kUnjudged;
    verdict.headline = "Not judged here: without the run's metrics (`syrof view` reads the metrics.json beside the "
                       "replay) the goal, P3 and the app's agreement are unknown; the replay shows no collision and "
                       "no app fault" + lost;
  }
  return verdict;
}

json VerdictData(const Verdict& verdict) {
  json lines = json::array();
  for (const VerdictLine& line : verdict.lines) lines.push_back({line.topic, line.ok, line.text});
  return {{"state", ToString(verdict.state)}, {"headline", verdict.headline}, {"lines", std::move(lines)}};
}

// ---- metrics.json, untrusted ---------------------------------------------------

namespace {

// Reads fields of one JSON object, naming the key path of the first problem.
class Fields {
 public:
  Fields(const json& node, std::string path, std::string& problem)
      : node_(node), path_(std::move(path)), problem_(problem) {}

  const json* Get(std::string_view key) {
    if (!problem_.empty()) return nullptr;
    if (!node_.is_object()) {
      problem_ = fmt::format("{}: expected an object", path_.empty() ? "the file" : path_);
      return nullptr;
    }
    const auto found = node_.find(std::string(key));
    if (found == node_.end()) {
      problem_ = fmt::format("{}: missing", Path(key));
      return nullptr;
    }
    return &*found;
  }
  std::string Path(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }

  bool Bool(std::string_view key, bool& out) {
    const json* value = Get(key);
    if (value == nullptr) return false;
    if (!value->is_boolean()) return Fail(key, "expected true or false");
    out = value->get<bool>();
    return true;
  }
  bool String(std::string_view key, std::string& out) {
    const json* value = Get(key);
    if (value == nullptr) return false;
    if (!value->is_string()) return Fail(key, "expected a string");
    out = value->get<std::string>();
    return true;
  }
  template <typename Integer>
  bool Int(std::string_view key, Integer& out) {
    const json* value = Get(key);
    if (value == nullptr) return false;
    if (!value->is_number_integer()) return Fail(key, "expected an integer");
    const int64_t number = value->is_number_unsigned() && value->get<uint64_t>() > uint64_t{INT64_MAX}
                               ? -1
                               : value->get<int64_t>();
    if (number < 0 || static_cast<uint64_t>(number) > std::numeric_limits<Integer>::max()) {
      return Fail(key, fmt::format("{} is out of range (0 to {})", value->dump(),
                                   static_cast<uint64_t>(std::numeric_limits<Integer>::max())));
    }
    out = static_cast<Integer>(number);
    return true;
  }
  bool Seconds(std::string_view key, int64_t& out_ns) {
    const json* value = Get(key);
    if (value == nullptr) return false;
    if (!value->is_number() || !std::isfinite(value->get<double>()) || std::abs(value->get<double>()) > 1e9) {
      return Fail(key, "expected a number of seconds");
    }
    out_ns = std::llround(value->get<double>() * 1e9);
    return true;
  }
  // An array's elements, each read by `read(Fields&)`; at most `limit` kept.
  template <typename Read>
  bool Array(std::string_view key, size_t limit, Read read) {
    const json* value = Get(key);
    if (value == nullptr) return false;
    if (!value->is_array()) return Fail(key, "expected an array");
    for (size_t i = 0; i < value->size() && i < limit; ++i) {
      Fields element((*value)[i], fmt::format("{}[{}]", Path(key), i), problem_);
      if (!read(element)) return false;
    }
    return true;
  }
  // An object, or null (returns false with no problem for null).
  bool Object(std::string_view key, std::optional<Fields>& out, bool null_allowed) {
    const json* value = Get(key);
    if (value == nullptr) return false;
    if (value->is_null() && null_allowed) return false;
    if (!value->is_object()) return Fail(key, null_allowed ? "expected an object or null" : "expected an object");
    out.emplace(*value, Path(key), problem_);
    return true;
  }
  bool ok() const { return problem_.empty(); }

 private:
  bool Fail(std::string_view key, const std::string& message) {
    problem_ = fmt::format("{}: {}", Path(key), message);
    return false;
  }
  const json& node_;
  std::string path_;
  std::string& problem_;
};

constexpr size_t kFirstFew = 16;  // of each list, the verdict reads the first

}  // namespace

std::optional<metrics::Metrics> ReadVerdictMetrics(std::istream& in, const std::string& name, Error& error) {
  const json root = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) {
    error = Error{.where = name, .message = "not JSON (a metrics.json written by `syrof run` was expected)"};
    return std::nullopt;
  }
  std::string problem;
  metrics::Metrics m;
  Fields top(root, "", problem);
  std::optional<Fields> section;

  // The seed, to tell another run's metrics.json from this replay's.
  if (const json* seed = top.Get("seed"); seed != nullptr) {
    if (!seed->is_number_unsigned()) {
      problem = "seed: expected a whole number from 0 to 2^64 - 1";
    } else {
      m.seed = seed->get<uint64_t>();
    }
  }

  if (top.Object("goal", section, false)) {
    section->String("app", m.goal.app);
    section->Bool("reached", m.goal.reached);
    section->String("detail", m.goal.detail);
    section->String("source", m.goal.source);
    section->Array("checks", kFirstFew, [&m](Fields& check) {
      metrics::GoalCheckResult& result = m.goal.checks.emplace_back();
      return check.String("name", result.name) && check.String("check", result.check) &&
             check.Bool("passed", result.passed) && check.String("reason", result.reason);
    });
  }
  if (top.Object("common_knowledge", section, false)) {
    section->Int("violations", m.common_knowledge.violations);
    section->Array("first_violations", 1, [&m](Fields& entry) {
      metrics::Violation& violation = m.common_knowledge.first_violations.emplace_back();
      return entry.Int("epoch", violation.epoch) && entry.Int("robot", violation.robot) &&
             entry.Int("round", violation.round) && entry.Int("first_robot", violation.first_robot);
    });
  }
  if (top.Object("agreement", section, true)) {
    metrics::AgreementMetrics& agreement = m.agreement.emplace();
    section->Int("cooperative_epochs", agreement.cooperative_epochs);
    section->Int("agreed_epochs", agreement.agreed_epochs);
    section->Int("disagreeing_calls", agreement.disagreeing_calls);
    std::optional<Fields> first;
    if (section->Object("first_disagreement", first, true)) {
      metrics::Disagreement& d = agreement.first_disagreement.emplace();
      first->Int("epoch", d.epoch) && first->Int("round", d.round) && first->String("callback", d.callback) &&
          first->Int("robot", d.robot) && first->Int("state", d.state) &&
          first->Int("reference_robot", d.reference_robot) && first->Int("reference_state", d.reference_state);
    }
  }
  if (top.Object("collisions", section, false)) {
    section->Int("count", m.collisions.count);
    section->Array("pairs", 1, [&m](Fields& entry) {
      metrics::CollisionEvent& pair = m.collisions.pairs.emplace_back();
      return entry.Seconds("time_s", pair.time_ns) && entry.Int("a", pair.a) && entry.Int("b", pair.b);
    });
  }
  if (top.Object("app", section, false)) {
    section->Array("faults", 1, [&m](Fields& entry) {
      metrics::AppFault& fault = m.app.faults.emplace_back();
      return entry.Int("robot", fault.robot) && entry.String("callback", fault.callback) &&
             entry.Int("epoch", fault.epoch) && entry.String("verdict", fault.verdict) &&
             entry.String("detail", fault.detail);
    });
    for (auto [key, incidents] : {std::pair{"invalid_commands", &m.app.invalid_commands},
                                  std::pair{"payload_refused", &m.app.payload_refused}}) {
      std::optional<Fields> part;
      if (section->Object(key, part, false)) part->Int("count", incidents->count);
    }
  }
  if (!problem.empty()) {
    error = Error{.where = name, .message = problem};
    return std::nullopt;
  }
  return m;
}

// ---- The goal's target -----------------------------------------------------------

json GoalTargets(const scenario::Scenario& scenario, size_t goal_robots) {
  json targets = json::array();
  if (scenario.goal.empty()) {
    // The built-in app's own goal (lab/apps' builtin_goals.h).
    const std::string_view app = apps::BareAppName(scenario.app.name);
    const apps::ArenaSize arena{scenario.arena.width_m, scenario.arena.height_m};
    const double body_m = scenario.omni.body_radius_m;
    if (app == "circle" && goal_robots > 0) {
      const apps::CircleParams params = apps::ReadCircleParams(scenario.app.params);
      json points = json::array();
      for (const apps::Position& point : apps::CircleTargets(params, goal_robots, arena, body_m)) {
        points.push_back({point.x_m, point.y_m, -1});
      }
      const apps::CircleFormation circle = apps::MakeCircleFormation(params, goal_robots, arena, body_m);
      targets.push_back({{"shape", "ring"}, {"name", "circle"}, {"x", circle.centre.x_m}, {"y", circle.centre.y_m},
                         {"r_min", circle.radius_m}, {"r_max", circle.radius_m}});
      targets.push_back({{"shape", "points"}, {"name", "circle: a robot's point"}, {"r", params.tolerance_m},
                         {"points", std::move(points)}});
    } else if (app == "gather" && goal_robots > 0) {
      const apps::GatherParams params = apps::ReadGatherParams(scenario.app.params);
      const double radius =
          apps::HexRingRadiusM(goal_robots, apps::GatherSpacingM(params, body_m)) + params.tolerance_m;
      targets.push_back({{"shape", "free_ring"}, {"name", "gather"}, {"r_min", radius}, {"r_max", radius}});
    }
    return targets;
  }
  for (const goals::GoalCheck& check : scenario.goal) {
    switch (check.kind) {
      case goals::CheckKind::kGathered:
        if (check.input_use == goals::GoalCheck::InputUse::kNone && check.centre) {
          targets.push_back({{"shape", "ring"}, {"name", check.name}, {"x", check.centre->x_m},
                             {"y", check.centre->y_m}, {"r_min", check.radius_m}, {"r_max", check.radius_m}});
        } else if (check.input_use == goals::GoalCheck::InputUse::kNone) {
          targets.push_back({{"shape", "free_ring"}, {"name", check.name}, {"r_min", check.radius_m},
                             {"r_max", check.radius_m}});
        } else {
          targets.push_back({{"shape", "none"}, {"name", check.name},
                             {"why", fmt::format("placed by the robots' input '{}'", check.input)}});
        }
        break;
      case goals::CheckKind::kCircle:
        if (check.centre) {
          targets.push_back({{"shape", "ring"}, {"name", check.name}, {"x", check.centre->x_m},
                             {"y", check.centre->y_m}, {"r_min", check.radius_min_m}, {"r_max", check.radius_max_m}});
        } else {
          targets.push_back({{"shape", "free_ring"}, {"name", check.name}, {"r_min", check.radius_min_m},
                             {"r_max", check.radius_max_m}});
        }
        break;
      case goals::CheckKind::kSlots: {
        json points = json::array();
        for (size_t i = 0; i < check.points.size(); ++i) {
          points.push_back({check.points[i].x_m, check.points[i].y_m, check.by_id ? static_cast<int64_t>(i) : -1});
        }
        targets.push_back(
            {{"shape", "points"}, {"name", check.name}, {"r", check.tolerance_m}, {"points", std::move(points)}});
        break;
      }
      case goals::CheckKind::kCoverage:
        targets.push_back({{"shape", "rect"}, {"name", check.name}, {"x0", check.area_min.x_m},
                           {"y0", check.area_min.y_m}, {"x1", check.area_max.x_m}, {"y1", check.area_max.y_m}});
        break;
      case goals::CheckKind::kLine:
      case goals::CheckKind::kShape:
        targets.push_back({{"shape", "none"}, {"name", check.name}, {"why", "anywhere in the arena, any rotation"}});
        break;
    }
  }
  return targets;
}

}  // namespace syrof::lab::view
