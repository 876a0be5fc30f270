// The goal checks' cost per evaluation, by swarm size: the shape check (360
// rotations, a bottleneck matching at each) is the costly one; the others
// are linear or one query. Prints milliseconds per evaluation; an
// `every_epoch` check pays it once per epoch.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "syrof/lab/goals/goals.h"

using namespace syrof::lab::goals;

namespace {

double MillisecondsPerEvaluation(const GoalCheck& check, const std::vector<RobotPose>& robots, Workspace& workspace,
                                 int repetitions) {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < repetitions; ++i) (void)MeasurePoses(check, robots, workspace);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / repetitions;
}

}  // namespace

int main() {
  Workspace workspace;
  std::printf("%8s %14s %14s %14s\n", "robots", "shape_ms", "slots_ms", "circle_ms");
  for (const int n : {10, 30, 100}) {
    GoalCheck shape;
    shape.kind = CheckKind::kShape;
    std::vector<RobotPose> robots;
    for (int i = 0; i < n; ++i) {
      const double angle = 2 * std::numbers::pi * i / n;
      const double radius = 1 + 0.3 * (i % 3);
      shape.points.push_back({std::cos(angle) * radius, std::sin(angle) * radius});
      robots.push_back({static_cast<uint16_t>(i), 5 + std::cos(angle + 0.4) * radius,
                        5 + std::sin(angle + 0.4) * radius, 0.1});
    }
    GoalCheck slots = shape;
    slots.kind = CheckKind::kSlots;
    for (Point& p : slots.points) p = {p.x_m + 5, p.y_m + 5};
    GoalCheck circle;
    circle.kind = CheckKind::kCircle;
    circle.radius_min_m = 0.5;
    circle.radius_max_m = 2;
    const int repetitions = n <= 30 ? 10 : 2;
    std::printf("%8d %14.2f %14.3f %14.4f\n", n, MillisecondsPerEvaluation(shape, robots, workspace, repetitions),
                MillisecondsPerEvaluation(slots, robots, workspace, repetitions),
                MillisecondsPerEvaluation(circle, robots, workspace, repetitions));
  }
}
