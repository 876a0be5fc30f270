#include "syrof/lab/apps/builtin_goals.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "target_matching.h"

namespace syrof::lab::apps {
namespace {

std::string Format(const char* format, auto... values) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, values...);
  return buffer;
}

Position PositionOf(const GoalPose& pose) { return {pose.x_m, pose.y_m}; }

double Distance(Position a, Position b) { return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m); }

double RadiusOf(const GoalPose& pose, double body_radius_m) { return pose.radius_m > 0 ? pose.radius_m : body_radius_m; }

// The first pair (in id order) of bodies closer than the sum of their radii,
// as a detail line; empty when there is none.
std::string FindOverlap(std::span<const GoalPose> poses, double body_radius_m) {
  for (size_t i = 0; i < poses.size(); ++i) {
    for (size_t j = i + 1; j < poses.size(); ++j) {
      const double distance_m = Distance(PositionOf(poses[i]), PositionOf(poses[j]));
      const double needed_m = RadiusOf(poses[i], body_radius_m) + RadiusOf(poses[j], body_radius_m);
      if (distance_m < needed_m) {
        return Format("robots %u and %u overlap (%.3f m apart, bodies need %.3f m)", unsigned{poses[i].id},
                      unsigned{poses[j].id}, distance_m, needed_m);
      }
    }
  }
  return {};
}

// The poses as query members (increasing id); false if a position is
// outside the queries' millimetre range.
bool ToMembers(std::span<const GoalPose> poses, std::vector<syrof_queries_member>& members) {
  members.clear();
  for (const GoalPose& pose : poses) {
    syrof_queries_point point{};
    if (syrof_queries_point_from_metres(static_cast<float>(pose.x_m), static_cast<float>(pose.y_m), &point) !=
        SYROF_QUERIES_OK) {
      return false;
    }
    members.push_back({pose.id, point.x_mm, point.y_mm});
  }
  return true;
}

GoalReport Verdict(double error_m, double tolerance_m, const std::string& overlap, std::string detail) {
  GoalReport report;
  report.error_m = error_m;
  report.reached = error_m <= tolerance_m && overlap.empty();
  report.detail = overlap.empty() ? std::move(detail) : overlap + "; " + detail;
  return report;
}

GoalReport Unjudgeable(const char* why) { return {false, 0.0, why}; }

GoalReport EvaluateGather(const GatherParams& params, double body_radius_m, std::span<const GoalPose> poses,
                          const std::string& overlap) {
  std::vector<syrof_queries_member> members;
  if (!ToMembers(poses, members)) return Unjudgeable("a robot is outside the queries' coordinate range");
  const OwnedWorkspace workspace;
  syrof_queries_circle circle{};
  if (syrof_queries_shortest_enclosing_circle(workspace.get(), members.data(), members.size(), &circle) !=
      SYROF_QUERIES_OK) {
    return Unjudgeable("the enclosing circle query refused the poses");
  }
  const double packing_m = HexRingRadiusM(poses.size(), GatherSpacingM(params, body_radius_m));
  const double error_m = std::max(0.0, static_cast<double>(circle.radius_m) - packing_m);
  return Verdict(error_m, params.tolerance_m, overlap,
                 Format("%zu robots within %.3f m of (%.3f, %.3f); the packing needs %.3f m + tolerance %.3f m",
                        poses.size(), static_cast<double>(circle.radius_m), static_cast<double>(circle.centre_x_m),
                        static_cast<double>(circle.centre_y_m), packing_m, params.tolerance_m));
}

// The bottleneck distance of matching `poses` to `targets`, or a negative
// value if the query refused them.
double MatchBottleneckM(std::span<const GoalPose> poses, std::span<const Position> targets) {
  std::vector<syrof_queries_member> members;
  if (!ToMembers(poses, members)) return -1.0;
  const OwnedWorkspace workspace;
  TargetAssignment assignment;
  if (!AssignTargets(workspace.get(), members, targets, assignment)) return -1.0;
  // The query's bottleneck is measured on millimetre positions; measure the
  // true distances of its pairs instead.
  double worst_m = 0.0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const uint16_t target = assignment.target_of_member[i];
    if (target != SYROF_QUERIES_NO_TARGET) worst_m = std::max(worst_m, Distance(PositionOf(poses[i]), targets[target]));
  }
  return worst_m;
}

GoalReport EvaluateCircle(const CircleParams& params, ArenaSize arena, double body_radius_m,
                          std::span<const GoalPose> poses, const std::string& overlap) {
  const std::vector<Position> points = CircleTargets(params, poses.size(), arena, body_radius_m);
  const double error_m = MatchBottleneckM(poses, points);
  if (error_m < 0.0) return Unjudgeable("a robot or point is outside the queries' coordinate range");
  const CircleFormation circle = MakeCircleFormation(params, poses.size(), arena, body_radius_m);
  return Verdict(error_m, params.tolerance_m, overlap,
                 Format("%zu robots on the circle of %.3f m around (%.3f, %.3f): worst %.3f m from its point "
                        "(tolerance %.3f m)",
                        poses.size(), circle.radius_m, circle.centre.x_m, circle.centre.y_m, error_m,
                        params.tolerance_m));
}

// The maneuver length the goal checks assume (syrof_app_info::maneuver_ms
// is not known after the run; 1 s is the scenarios' default).
constexpr double kDefaultManeuverS = 1.0;

GoalReport EvaluateLeaderFollow(const LeaderFollowParams& params, ArenaSize arena, double body_radius_m,
                                std::span<const GoalPose> poses, const std::string& overlap) {
  // `poses` is in increasing id order: the leader comes first.
  const LeaderPath path = MakeLeaderPath(params, poses.size(), arena, body_radius_m);
  const Position leader = PositionOf(poses.front());
  const double leader_off_m = std::abs(Distance(leader, path.centre) - path.radius_m);
  const std::vector<Position> slots = FollowerSlots(path, PathAngleRad(path, leader), poses.size() - 1);
  const double followers_m = MatchBottleneckM(poses.subspan(1), slots);
  if (followers_m < 0.0) return Unjudgeable("a robot or slot is outside the queries' coordinate range");
  // Followers aim at slots behind where the leader stood when the maneuver
  // began, so by design they trail the slots of its current place by up to
  // the leader's move in one maneuver (checked for the default 1 s one).
  const double lag_m = LeaderStepM(params, body_radius_m, kDefaultManeuverS);
  const double error_m = std::max(leader_off_m, std::max(0.0, followers_m - lag_m));
  return Verdict(error_m, params.tolerance_m, overlap,
                 Format("leader %u %.3f m off its path; %zu followers, worst %.3f m from its slot, of which up to "
                        "%.3f m is the leader's last move (tolerance %.3f m)",
                        unsigned{poses.front().id}, leader_off_m, poses.size() - 1, followers_m, lag_m,
                        params.tolerance_m));
}

}  // namespace

GoalReport EvaluateGoal(std::string_view app, const std::map<std::string, double>& params, ArenaSize arena,
                        double body_radius_m, std::span<const GoalPose> final_true_poses) {
  if (app == "idle") return {true, 0.0, "idle has no goal"};
  if (app != "gather" && app != "circle" && app != "leader_follow") {
    return Unjudgeable("not a built-in app");
  }
  std::vector<GoalPose> present;
  for (const GoalPose& pose : final_true_poses) {
    if (pose.present) present.push_back(pose);
  }
  std::sort(present.begin(), present.end(), [](const GoalPose& a, const GoalPose& b) { return a.id < b.id; });
  if (present.empty()) return {true, 0.0, "no robot present"};
  const std::string overlap = FindOverlap(present, body_radius_m);
  if (app == "gather") return EvaluateGather(ReadGatherParams(params), body_radius_m, present, overlap);
  if (app == "circle") return EvaluateCircle(ReadCircleParams(params), arena, body_radius_m, present, overlap);
  return EvaluateLeaderFollow(ReadLeaderFollowParams(params), arena, body_radius_m, present, overlap);
}

}  // namespace syrof::lab::apps
