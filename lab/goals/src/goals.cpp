#include "syrof/lab/goals/goals.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <new>
#include <numbers>

#include "syrof/base/check.h"
#include "syrof/queries/queries.h"

namespace syrof::lab::goals {

struct Workspace::Impl {
  Impl() {
    const size_t alignment = syrof_queries_workspace_alignment();
    memory = static_cast<unsigned char*>(::operator new(syrof_queries_workspace_size(), std::align_val_t{alignment}));
    SYROF_CHECK(syrof_queries_workspace_init(memory, syrof_queries_workspace_size(), &handle) == SYROF_QUERIES_OK);
  }
  ~Impl() { ::operator delete(memory, std::align_val_t{syrof_queries_workspace_alignment()}); }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  unsigned char* memory = nullptr;
  syrof_queries_workspace* handle = nullptr;
};

Workspace::Workspace() : impl_(std::make_unique<Impl>()) {}
Workspace::~Workspace() = default;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The shape's rotation is searched on this grid, then refined once
// (Procrustes on the best grid angle's assignment).
constexpr int kShapeAngleSteps = 360;

constexpr std::array<std::string_view, 6> kKindNames = {"slots", "shape", "line", "gathered", "circle", "coverage"};

std::string Format(const char* format, auto... values) {
  char buffer[320];
  std::snprintf(buffer, sizeof buffer, format, values...);
  return buffer;
}

double Distance(double ax, double ay, double bx, double by) { return std::hypot(ax - bx, ay - by); }

double Degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

Measure Fail(std::string reason, double value = kNaN) { return {false, value, std::move(reason)}; }

// Robot `id`'s value of the check's input (the loader gives every robot
// one; a missing one reads as NaN, which no comparison favours).
double InputOf(const GoalCheck& check, uint16_t id) {
  return id < check.input_values.size() ? check.input_values[id] : kNaN;
}

// Robots in increasing id order.
std::vector<RobotPose> Sorted(std::span<const RobotPose> poses) {
  std::vector<RobotPose> sorted(poses.begin(), poses.end());
  std::sort(sorted.begin(), sorted.end(), [](const RobotPose& a, const RobotPose& b) { return a.id < b.id; });
  return sorted;
}

// Bottleneck matching of `robots` (increasing id) to `targets`, by the
// queries' MinWeightedMatching on millimetre positions; the distances are
// then measured in metres. False when a position is outside the queries'
// range. target_of[i] is robot i's target.
bool Match(Workspace& workspace, std::span<const RobotPose> robots, std::span<const Point> targets,
           std::vector<uint16_t>& target_of) {
  std::vector<syrof_queries_member> members(robots.size());
  for (size_t i = 0; i < robots.size(); ++i) {
    syrof_queries_point point{};
    if (syrof_queries_point_from_metres(static_cast<float>(robots[i].x_m), static_cast<float>(robots[i].y_m), &point) !=
        SYROF_QUERIES_OK) {
      return false;
    }
    members[i] = {robots[i].id, point.x_mm, point.y_mm};
  }
  std::vector<syrof_queries_point> points(targets.size());
  for (size_t k = 0; k < targets.size(); ++k) {
    if (syrof_queries_point_from_metres(static_cast<float>(targets[k].x_m), static_cast<float>(targets[k].y_m),
                                        &points[k]) != SYROF_QUERIES_OK) {
      return false;
    }
  }
  std::vector<syrof_queries_assignment> by_robot(members.size());
  std::vector<uint16_t> robot_of_target(points.size());
  if (syrof_queries_min_weighted_matching(workspace.impl().handle, members.data(), members.size(), points.data(),
                                          points.size(), by_robot.data(), by_robot.size(), robot_of_target.data(),
                                          robot_of_target.size(), nullptr) != SYROF_QUERIES_OK) {
    return false;
  }
  target_of.resize(members.size());
  for (size_t i = 0; i < members.size(); ++i) target_of[i] = by_robot[i].target_index;
  return true;
}

// The worst robot-to-target distance of a matching, and its robot's index.
double Worst(std::span<const RobotPose> robots, std::span<const Point> targets, std::span<const uint16_t> target_of,
             size_t& worst_index) {
  double worst = 0;
  worst_index = 0;
  for (size_t i = 0; i < robots.size(); ++i) {
    const Point& target = targets[target_of[i]];
    const double distance = Distance(robots[i].x_m, robots[i].y_m, target.x_m, target.y_m);
    if (distance > worst) {
      worst = distance;
      worst_index = i;
    }
  }
  return worst;
}

Measure MeasureSlots(const GoalCheck& check, std::span<const RobotPose> robots, Workspace& workspace) {
  std::vector<uint16_t> target_of(robots.size());
  if (check.by_id) {
    for (size_t i = 0; i < robots.size(); ++i) {
      if (robots[i].id >= check.points.size()) {
        return Fail(Format("robot %u has no slot (the check lists %zu, for robots 0..%zu)", unsigned{robots[i].id},
                           check.points.size(), check.points.size() - 1));
      }
      target_of[i] = robots[i].id;
    }
  } else {
    if (robots.size() > check.points.size()) {
      return Fail(Format("%zu robots are running but the check has only %zu slots", robots.size(), check.points.size()));
    }
    if (!Match(workspace, robots, check.points, target_of)) return Fail("a robot or slot is outside the queries' range");
  }
  size_t worst_index = 0;
  const double worst = Worst(robots, check.points, target_of, worst_index);
  const Point& slot = check.points[target_of[worst_index]];
  const bool holds = worst <= check.tolerance_m;
  return {holds, worst,
          holds ? Format("every robot is within %.3f m of its slot (tolerance %.3f m)", worst, check.tolerance_m)
                : Format("robot %u is %.3f m from its slot (%.3f, %.3f), tolerance %.3f m",
                         unsigned{robots[worst_index].id}, worst, slot.x_m, slot.y_m, check.tolerance_m)};
}

// The shape's points rotated by `angle_rad` about their centroid and moved
// onto `centre`.
std::vector<Point> PlaceShape(std::span<const Point> shape, Point shape_centre, Point centre, double angle_rad) {
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  std::vector<Point> placed(shape.size());
  for (size_t k = 0; k < shape.size(); ++k) {
    const double dx = shape[k].x_m - shape_centre.x_m;
    const double dy = shape[k].y_m - shape_centre.y_m;
    placed[k] = {centre.x_m + c * dx - s * dy, centre.y_m + s * dx + c * dy};
  }
  return placed;
}

Point Centroid(std::span<const Point> points) {
  Point sum;
  for (const Point& p : points) {
    sum.x_m += p.x_m;
    sum.y_m += p.y_m;
  }
  const double n = static_cast<double>(points.size());
  return {sum.x_m / n, sum.y_m / n};
}

Point Centroid(std::span<const RobotPose> robots) {
  Point sum;
  for (const RobotPose& r : robots) {
    sum.x_m += r.x_m;
    sum.y_m += r.y_m;
  }
  const double n = static_cast<double>(robots.size());
  return {sum.x_m / n, sum.y_m / n};
}

// Up to translation and rotation: with every point taken, the best
// translation in the least-squares sense puts the centroids together
// whatever the assignment, so only the angle is searched: a grid of
// kShapeAngleSteps angles (bottleneck matching at each; the first best
// wins), then one Procrustes step on the best assignment, kept if better.
Measure MeasureShape(const GoalCheck& check, std::span<const RobotPose> robots, Workspace& workspace) {
  if (robots.size() != check.points.size()) {
    return Fail(Format("%zu robots are running; the shape has %zu points", robots.size(), check.points.size()));
  }
  const Point robot_centre = Centroid(robots);
  const Point shape_centre = Centroid(check.points);
  double best = std::numeric_limits<double>::infinity();
  double best_angle = 0;
  std::vector<uint16_t> best_target_of;
  size_t best_index = 0;
  std::vector<uint16_t> target_of;
  auto consider = [&](double angle) {
    const std::vector<Point> placed = PlaceShape(check.points, shape_centre, robot_centre, angle);
    if (!Match(workspace, robots, placed, target_of)) return;
    size_t index = 0;
    const double worst = Worst(robots, placed, target_of, index);
    if (worst < best) {
      best = worst;
      best_angle = angle;
      best_target_of = target_of;
      best_index = index;
    }
  };
  for (int step = 0; step < kShapeAngleSteps; ++step) consider(kTwoPi * step / kShapeAngleSteps);
  if (best_target_of.empty()) return Fail("a robot or point is outside the queries' range");
  double dot = 0;
  double cross = 0;
  for (size_t i = 0; i < robots.size(); ++i) {
    const Point& p = check.points[best_target_of[i]];
    const double sx = p.x_m - shape_centre.x_m;
    const double sy = p.y_m - shape_centre.y_m;
    const double rx = robots[i].x_m - robot_centre.x_m;
    const double ry = robots[i].y_m - robot_centre.y_m;
    dot += sx * rx + sy * ry;
    cross += sx * ry - sy * rx;
  }
  if (dot != 0 || cross != 0) consider(std::atan2(cross, dot));
  const bool holds = best <= check.tolerance_m;
  double shown = std::fmod(Degrees(best_angle), 360.0);
  if (shown < 0) shown += 360.0;
  return {holds, best,
          holds ? Format("every robot is within %.3f m of its point of the shape (rotated %.1f deg), tolerance %.3f m",
                         best, shown, check.tolerance_m)
                : Format("robot %u is %.3f m from its point of the shape at the best alignment (rotated %.1f deg), "
                         "tolerance %.3f m",
                         unsigned{robots[best_index].id}, best, shown, check.tolerance_m)};
}

// Robot k (k-th by id) belongs at centre + (k - (n-1)/2) * spacing * u: the
// least-squares placement along a given direction u; a free direction is
// the least-squares one, u parallel to sum (k - kbar)(p_k - centre).
Measure MeasureLine(const GoalCheck& check, std::span<const RobotPose> by_id) {
  // With order_by the places go in increasing order of the input (ties by id).
  std::vector<RobotPose> robots(by_id.begin(), by_id.end());
  if (check.input_use == GoalCheck::InputUse::kOrderBy) {
    std::stable_sort(robots.begin(), robots.end(), [&](const RobotPose& a, const RobotPose& b) {
      return InputOf(check, a.id) < InputOf(check, b.id);
    });
  }
  const char* const order = check.input_use == GoalCheck::InputUse::kOrderBy ? check.input.c_str() : "id";
  const size_t n = robots.size();
  const Point centre = Centroid(robots);
  const double middle = (static_cast<double>(n) - 1.0) / 2.0;
  double ux = 1;
  double uy = 0;
  if (check.direction_rad) {
    ux = std::cos(*check.direction_rad);
    uy = std::sin(*check.direction_rad);
  } else {
    double wx = 0;
    double wy = 0;
    for (size_t k = 0; k < n; ++k) {
      wx += (static_cast<double>(k) - middle) * (robots[k].x_m - centre.x_m);
      wy += (static_cast<double>(k) - middle) * (robots[k].y_m - centre.y_m);
    }
    const double length = std::hypot(wx, wy);
    if (length > 0) {
      ux = wx / length;
      uy = wy / length;
    }
  }
  double worst = 0;
  size_t worst_index = 0;
  for (size_t k = 0; k < n; ++k) {
    const double offset = (static_cast<double>(k) - middle) * check.spacing_m;
    const double distance =
        Distance(robots[k].x_m, robots[k].y_m, centre.x_m + offset * ux, centre.y_m + offset * uy);
    if (distance > worst) {
      worst = distance;
      worst_index = k;
    }
  }
  const bool holds = worst <= check.tolerance_m;
  const double direction_deg = Degrees(std::atan2(uy, ux));
  return {holds, worst,
          holds ? Format("%zu robots on a line by %s, %.3f m apart towards %.1f deg: worst %.3f m from its place "
                         "(tolerance %.3f m)",
                         n, order, check.spacing_m, direction_deg, worst, check.tolerance_m)
                : Format("robot %u is %.3f m from its place on the line by %s (spacing %.3f m, direction %.1f deg), "
                         "tolerance %.3f m",
                         unsigned{robots[worst_index].id}, worst, order, check.spacing_m, direction_deg,
                         check.tolerance_m)};
}

// Every robot within check.radius_m of `centre`; `where` names the centre.
Measure MeasureAround(const GoalCheck& check, std::span<const RobotPose> robots, Point centre,
                      const std::string& where) {
  double worst = 0;
  size_t worst_index = 0;
  for (size_t i = 0; i < robots.size(); ++i) {
    const double distance = Distance(robots[i].x_m, robots[i].y_m, centre.x_m, centre.y_m);
    if (distance > worst) {
      worst = distance;
      worst_index = i;
    }
  }
  const bool holds = worst <= check.radius_m;
  return {holds, worst,
          holds ? Format("every robot is within %.3f m of %s; the limit is %.3f m", worst, where.c_str(),
                         check.radius_m)
                : Format("robot %u is %.3f m from %s; the limit is %.3f m", unsigned{robots[worst_index].id}, worst,
                         where.c_str(), check.radius_m)};
}

// The smallest circle holding `robots` (the queries'); false when a robot is
// outside the queries' range or the query refused.
bool EnclosingCircle(std::span<const RobotPose> robots, Workspace& workspace, syrof_queries_circle& circle) {
  std::vector<syrof_queries_member> members(robots.size());
  for (size_t i = 0; i < robots.size(); ++i) {
    syrof_queries_point point{};
    if (syrof_queries_point_from_metres(static_cast<float>(robots[i].x_m), static_cast<float>(robots[i].y_m), &point) !=
        SYROF_QUERIES_OK) {
      return false;
    }
    members[i] = {robots[i].id, point.x_mm, point.y_mm};
  }
  return syrof_queries_shortest_enclosing_circle(workspace.impl().handle, members.data(), members.size(), &circle) ==
         SYROF_QUERIES_OK;
}

// group_by: each group of robots sharing a value gathered on its own, the
// groups' centres at least groups_apart_m apart. The value is the largest
// group's circle.
Measure MeasureGroups(const GoalCheck& check, std::span<const RobotPose> robots, Workspace& workspace) {
  std::map<double, std::vector<RobotPose>> groups;
  for (const RobotPose& robot : robots) groups[InputOf(check, robot.id)].push_back(robot);
  std::vector<std::pair<double, syrof_queries_circle>> circles;
  double worst = 0;
  for (const auto& [value, members] : groups) {
    syrof_queries_circle circle{};
    if (!EnclosingCircle(members, workspace, circle)) return Fail("a robot is outside the queries' range");
    circles.emplace_back(value, circle);
    worst = std::max(worst, static_cast<double>(circle.radius_m));
    if (circle.radius_m > check.radius_m) {
      return {false, worst,
              Format("the %zu robots of %s %g fit only in a circle of %.3f m around (%.3f, %.3f); the limit is %.3f m",
                     members.size(), check.input.c_str(), value, static_cast<double>(circle.radius_m),
                     static_cast<double>(circle.centre_x_m), static_cast<double>(circle.centre_y_m), check.radius_m)};
    }
  }
  for (size_t a = 0; a < circles.size(); ++a) {
    for (size_t b = a + 1; b < circles.size(); ++b) {
      const double apart = Distance(circles[a].second.centre_x_m, circles[a].second.centre_y_m,
                                    circles[b].second.centre_x_m, circles[b].second.centre_y_m);
      if (apart < check.groups_apart_m) {
        return {false, worst,
                Format("the groups of %s %g and %g are only %.3f m apart; they must be %.3f m apart",
                       check.input.c_str(), circles[a].first, circles[b].first, apart, check.groups_apart_m)};
      }
    }
  }
  return {true, worst,
          Format("%zu groups by %s, each within a circle of at most %.3f m, at least %.3f m apart; the limit is %.3f m",
                 circles.size(), check.input.c_str(), worst, check.groups_apart_m, check.radius_m)};
}

Measure MeasureGathered(const GoalCheck& check, std::span<const RobotPose> robots, Workspace& workspace) {
  if (check.input_use == GoalCheck::InputUse::kGroupBy) return MeasureGroups(check, robots, workspace);
  if (check.input_use == GoalCheck::InputUse::kCentreAtMax) {
    const RobotPose* top = &robots[0];
    for (const RobotPose& robot : robots) {
      if (InputOf(check, robot.id) > InputOf(check, top->id)) top = &robot;  // increasing id: ties keep the lowest
    }
    return MeasureAround(check, robots, Point{top->x_m, top->y_m},
                         Format("robot %u (the largest %s, %g)", unsigned{top->id}, check.input.c_str(),
                                InputOf(check, top->id)));
  }
  if (check.centre) {
    return MeasureAround(check, robots, *check.centre, Format("(%.3f, %.3f)", check.centre->x_m, check.centre->y_m));
  }
  syrof_queries_circle circle{};
  if (!EnclosingCircle(robots, workspace, circle)) return Fail("the enclosing circle query refused the poses");
  const double radius = circle.radius_m;
  const bool holds = radius <= check.radius_m;
  return {holds, radius,
          Format("the %zu robots fit in a circle of %.3f m around (%.3f, %.3f); the limit is %.3f m", robots.size(),
                 radius, static_cast<double>(circle.centre_x_m), static_cast<double>(circle.centre_y_m),
                 check.radius_m)};
}

// Evenly on a circle: every robot's distance from the centre (given, or the
// robots' centroid, which is the centre of evenly spaced points) in the
// radius range, and each gap between angular neighbours within the angle
// tolerance of 2*pi/n.
Measure MeasureCircle(const GoalCheck& check, std::span<const RobotPose> robots) {
  const Point centre = check.centre ? *check.centre : Centroid(robots);
  struct Polar {
    double angle;
    uint16_t id;
  };
  std::vector<Polar> polar;
  for (const RobotPose& robot : robots) {
    const double radius = Distance(robot.x_m, robot.y_m, centre.x_m, centre.y_m);
    if (radius < check.radius_min_m || radius > check.radius_max_m) {
      return Fail(Format("robot %u is %.3f m from the centre (%.3f, %.3f); the radius must be in [%.3f, %.3f] m",
                         unsigned{robot.id}, radius, centre.x_m, centre.y_m, check.radius_min_m, check.radius_max_m),
                  kNaN);
    }
    polar.push_back({std::atan2(robot.y_m - centre.y_m, robot.x_m - centre.x_m), robot.id});
  }
  std::sort(polar.begin(), polar.end(),
            [](const Polar& a, const Polar& b) { return a.angle != b.angle ? a.angle < b.angle : a.id < b.id; });
  const size_t n = polar.size();
  const double ideal = kTwoPi / static_cast<double>(n);
  double worst = 0;
  size_t worst_index = 0;
  double worst_gap = ideal;
  for (size_t i = 0; i < n && n > 1; ++i) {
    const double next = i + 1 < n ? polar[i + 1].angle : polar[0].angle + kTwoPi;
    const double gap = next - polar[i].angle;
    const double deviation = std::abs(gap - ideal);
    if (deviation > worst) {
      worst = deviation;
      worst_index = i;
      worst_gap = gap;
    }
  }
  const bool holds = worst <= check.angle_tolerance_rad;
  if (holds) {
    return {true, worst,
            Format("%zu robots on the circle around (%.3f, %.3f), radii in [%.3f, %.3f] m; worst gap %.3f rad off "
                   "%.3f rad (tolerance %.3f rad)",
                   n, centre.x_m, centre.y_m, check.radius_min_m, check.radius_max_m, worst, ideal,
                   check.angle_tolerance_rad)};
  }
  return {false, worst,
          Format("the gap from robot %u to robot %u is %.3f rad; evenly spaced needs %.3f rad, tolerance %.3f rad",
                 unsigned{polar[worst_index].id}, unsigned{polar[(worst_index + 1) % n].id}, worst_gap, ideal,
                 check.angle_tolerance_rad)};
}

}  // namespace

std::string_view ToString(CheckKind kind) { return kKindNames[static_cast<size_t>(kind)]; }

std::span<const std::string_view> CheckKindNames() { return kKindNames; }

std::string_view ToString(When when) { return when == When::kFinal ? "final" : "every_epoch"; }

std::string_view Unit(CheckKind kind) {
  switch (kind) {
    case CheckKind::kCircle:
      return "rad";
    case CheckKind::kCoverage:
      return "fraction";
    default:
      return "m";
  }
}

double Limit(const GoalCheck& check) {
  switch (check.kind) {
    case CheckKind::kGathered:
      return check.radius_m;
    case CheckKind::kCircle:
      return check.angle_tolerance_rad;
    case CheckKind::kCoverage:
      return check.min_fraction;
    default:
      return check.tolerance_m;
  }
}

Measure MeasurePoses(const GoalCheck& check, std::span<const RobotPose> poses, Workspace& workspace) {
  SYROF_CHECK(check.kind != CheckKind::kCoverage);
  if (poses.empty()) return Fail("no robot is running");
  const std::vector<RobotPose> robots = Sorted(poses);
  switch (check.kind) {
    case CheckKind::kSlots:
      return MeasureSlots(check, robots, workspace);
    case CheckKind::kShape:
      return MeasureShape(check, robots, workspace);
    case CheckKind::kLine:
      return MeasureLine(check, robots);
    case CheckKind::kGathered:
      return MeasureGathered(check, robots, workspace);
    case CheckKind::kCircle:
      return MeasureCircle(check, robots);
    case CheckKind::kCoverage:
      break;
  }
  return Fail("not a geometric check");
}

// ---- GoalMonitor -----------------------------------------------------------

struct GoalMonitor::Track {
  int64_t samples = 0;
  double worst = 0;
  std::optional<std::string> first_failure;  // "at epoch E (T s): reason"
  bool streak = false;
  uint16_t streak_epoch = 0;
  double streak_s = 0;
  // Coverage.
  int64_t columns = 0;
  int64_t rows = 0;
  std::vector<uint8_t> visited;
  int64_t covered = 0;
  std::optional<double> reached_s;
};

void GoalMonitor::AddToDigest(base::StateDigest& digest) const {
  for (const Track& track : tracks_) {
    digest.AddValue(track.samples);
    digest.AddValue(track.worst);
    digest.AddValue(track.first_failure.has_value());
    if (track.first_failure) {
      digest.AddBytes(std::as_bytes(std::span(track.first_failure->data(), track.first_failure->size())));
    }
    digest.AddValue(track.streak);
    digest.AddValue(track.streak_epoch);
    digest.AddValue(track.streak_s);
    digest.AddRange(std::span<const uint8_t>(track.visited));
    digest.AddValue(track.covered);
    digest.AddValue(track.reached_s.has_value());
    digest.AddValue(track.reached_s.value_or(0));
  }
}

GoalMonitor::GoalMonitor(std::vector<GoalCheck> checks) : checks_(std::move(checks)), tracks_(checks_.size()) {
  for (size_t i = 0; i < checks_.size(); ++i) {
    const GoalCheck& check = checks_[i];
    if (check.kind != CheckKind::kCoverage) continue;
    SYROF_CHECK(check.cell_m > 0 && check.area_max.x_m > check.area_min.x_m && check.area_max.y_m > check.area_min.y_m);
    Track& track = tracks_[i];
    track.columns = static_cast<int64_t>(std::ceil((check.area_max.x_m - check.area_min.x_m) / check.cell_m));
    track.rows = static_cast<int64_t>(std::ceil((check.area_max.y_m - check.area_min.y_m) / check.cell_m));
    SYROF_CHECK(track.columns * track.rows <= kMaxCoverageCells);
    track.visited.assign(static_cast<size_t>(track.columns * track.rows), 0);
  }
  if (!checks_.empty()) workspace_ = std::make_unique<Workspace>();
}

GoalMonitor::~GoalMonitor() = default;
GoalMonitor::GoalMonitor(GoalMonitor&&) noexcept = default;

// A cell is visited when its centre lies within a running robot's body.
void GoalMonitor::OnRound(double time_s, std::span<const RobotPose> running) {
  for (size_t i = 0; i < checks_.size(); ++i) {
    const GoalCheck& check = checks_[i];
    if (check.kind != CheckKind::kCoverage) continue;
    Track& track = tracks_[i];
    for (const RobotPose& robot : running) {
      const auto first = [&](double low, double origin, int64_t count) {
        return std::clamp<int64_t>(static_cast<int64_t>(std::floor((low - origin) / check.cell_m)), 0, count);
      };
      const int64_t column_begin = first(robot.x_m - robot.radius_m, check.area_min.x_m, track.columns);
      const int64_t column_end = first(robot.x_m + robot.radius_m, check.area_min.x_m, track.columns - 1) + 1;
      const int64_t row_begin = first(robot.y_m - robot.radius_m, check.area_min.y_m, track.rows);
      const int64_t row_end = first(robot.y_m + robot.radius_m, check.area_min.y_m, track.rows - 1) + 1;
      for (int64_t row = row_begin; row < row_end; ++row) {
        for (int64_t column = column_begin; column < column_end; ++column) {
          const double cx = check.area_min.x_m + (static_cast<double>(column) + 0.5) * check.cell_m;
          const double cy = check.area_min.y_m + (static_cast<double>(row) + 0.5) * check.cell_m;
          uint8_t& cell = track.visited[static_cast<size_t>(row * track.columns + column)];
          if (cell == 0 && Distance(cx, cy, robot.x_m, robot.y_m) <= robot.radius_m) {
            cell = 1;
            ++track.covered;
          }
        }
      }
    }
    const double fraction = static_cast<double>(track.covered) / static_cast<double>(track.visited.size());
    if (!track.reached_s && fraction >= check.min_fraction) track.reached_s = time_s;
  }
}

void GoalMonitor::OnEpoch(uint16_t epoch, double time_s, std::span<const RobotPose> running) {
  for (size_t i = 0; i < checks_.size(); ++i) {
    const GoalCheck& check = checks_[i];
    if (check.kind == CheckKind::kCoverage) continue;
    const bool sampled = check.when == When::kEveryEpoch && time_s >= check.from_s;
    if (!sampled && !check.deadline_s) continue;
    Track& track = tracks_[i];
    const Measure measure = MeasurePoses(check, running, *workspace_);
    if (sampled) {
      ++track.samples;
      // The worst value; an unmeasurable sample (NaN) stays the worst.
      if (!std::isnan(track.worst) && !(measure.value <= track.worst)) track.worst = measure.value;
      if (!measure.holds && !track.first_failure) {
        track.first_failure = Format("at epoch %u (%.2f s): ", unsigned{epoch}, time_s) + measure.reason;
      }
    } else {
      ++track.samples;
    }
    if (measure.holds && !track.streak) {
      track.streak = true;
      track.streak_epoch = epoch;
      track.streak_s = time_s;
    } else if (!measure.holds) {
      track.streak = false;
    }
  }
}

std::vector<CheckResult> GoalMonitor::Finish(double time_s, std::span<const RobotPose> running) {
  std::vector<CheckResult> results;
  for (size_t i = 0; i < checks_.size(); ++i) {
    const GoalCheck& check = checks_[i];
    const Track& track = tracks_[i];
    CheckResult result;
    result.name = check.name;
    result.kind = check.kind;
    result.when = check.when;
    result.limit = Limit(check);
    result.deadline_s = check.deadline_s;
    result.samples = track.samples;
    if (check.kind == CheckKind::kCoverage) {
      const double total = static_cast<double>(track.visited.size());
      result.value = static_cast<double>(track.covered) / total;
      const std::string visited =
          Format("visited %.1f%% of %lld cells of %.3f m in [%.3f, %.3f] x [%.3f, %.3f]; needs %.1f%%",
                 100.0 * result.value, static_cast<long long>(track.visited.size()), check.cell_m, check.area_min.x_m,
                 check.area_max.x_m, check.area_min.y_m, check.area_max.y_m, 100.0 * check.min_fraction);
      result.passed = result.value >= check.min_fraction;
      result.reason = visited;
      if (check.deadline_s && result.passed) {
        result.held_from_s = track.reached_s;
        result.passed = *track.reached_s <= *check.deadline_s;
        result.reason += Format(", reached at %.2f s (deadline %.2f s)", *track.reached_s, *check.deadline_s);
      }
      results.push_back(std::move(result));
      continue;
    }
    const Measure final_measure = MeasurePoses(check, running, *workspace_);
    result.value = final_measure.value;
    result.passed = final_measure.holds;
    result.reason = final_measure.reason;
    if (check.when == When::kEveryEpoch) {
      if (track.samples > 0 && !(track.worst <= result.value)) result.value = track.worst;
      if (track.first_failure) {
        result.passed = false;
        result.reason = *track.first_failure;
      } else if (!final_measure.holds) {
        result.reason = "at the end: " + final_measure.reason;
      } else {
        result.reason = Format("held at %lld epochs from %.2f s and at the end; ", static_cast<long long>(track.samples),
                               check.from_s) +
                        final_measure.reason;
      }
    }
    if (check.deadline_s && result.passed) {
      if (track.streak) {
        result.held_from_epoch = track.streak_epoch;
        result.held_from_s = track.streak_s;
      } else {
        result.held_from_s = time_s;
      }
      result.passed = *result.held_from_s <= *check.deadline_s;
      const std::string since = result.held_from_epoch
                                    ? Format("epoch %u (%.2f s)", unsigned{*result.held_from_epoch}, *result.held_from_s)
                                    : Format("the end (%.2f s)", *result.held_from_s);
      result.reason = result.passed ? Format("held from %s on, deadline %.2f s; ", since.c_str(), *check.deadline_s) +
                                          result.reason
                                    : Format("held only from %s on; the deadline is %.2f s", since.c_str(),
                                             *check.deadline_s);
    } else if (check.deadline_s && !final_measure.holds && check.when == When::kFinal) {
      result.reason = "at the end: " + final_measure.reason;
    }
    results.push_back(std::move(result));
  }
  return results;
}

}  // namespace syrof::lab::goals
