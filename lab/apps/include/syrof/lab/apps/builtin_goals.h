// The built-in apps' goals, judged on final true poses: used by the
// simulator's metrics (the assignment's own goal) and by tests.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>

#include "syrof/lab/apps/formation.h"

namespace syrof::lab::apps {

/// A robot's true pose at the end of a run.
struct GoalPose {
  uint16_t id = 0;
  double x_m = 0;
  double y_m = 0;
  double heading_rad = 0;
  bool present = true;  ///< false: crashed or never joined; left out of the goal
  /// This robot's own body radius (its kind's), for the overlap check; 0
  /// means EvaluateGoal's body_radius_m (a swarm of one kind).
  double radius_m = 0;
};

/// The verdict.
struct GoalReport {
  bool reached = false;
  double error_m = 0;  ///< the worst distance of a robot from its place (0 when every robot is in place)
  std::string detail;  ///< one line for reports, e.g. why the goal was missed
};

/// Judges `final_true_poses` (any order; robots with present == false are
/// ignored) against the goal of the built-in app `app` (without
/// "builtin:") run with `params` (missing keys take their defaults):
///   idle           no goal: always reached, error 0;
///   gather         the smallest circle holding every robot has a radius of
///                  at most HexRingRadiusM(n, spacing) + tolerance_m;
///                  error = how much it exceeds HexRingRadiusM;
///   circle         every robot within tolerance_m of a distinct point of
///                  CircleTargets for the n present robots; error = the
///                  longest robot-to-point distance of the bottleneck
///                  matching;
///   leader_follow  the leader (smallest present id) within tolerance_m of
///                  its path, and every follower within tolerance_m of a
///                  distinct slot of FollowerSlots behind the leader's
///                  angle; error = the worst of those distances.
/// `body_radius_m` is the radius the formation is planned for (what the
/// apps' geometry uses). In every app two present bodies closer than the sum
/// of their own radii (GoalPose::radius_m) mean the goal is missed. An unknown app is reported as not reached. A run with no
/// present robot reaches every goal.
GoalReport EvaluateGoal(std::string_view app, const std::map<std::string, double>& params, ArenaSize arena,
                        double body_radius_m, std::span<const GoalPose> final_true_poses);

}  // namespace syrof::lab::apps
