// The estimator's accuracy on the standard run: a figure eight at 0.5 m/s in
// the default 4 m arena (the paper's anchor layout, scaled), default sensor
// noise (IMU 100 Hz with bias walk, flow 50 Hz at 2 px, UWB 10 Hz at 0.10 m
// with 2 % outliers), 120 s per run, scored after 5 s. Runs the robot's own
// code: Estimator<float> on the simulation port, fed through the broker.
// Prints position RMSE (the target is at most 0.05 m) and heading RMSE, per
// seed and over all seeds, for float (the Teensy) and double.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "syrof/lab/sensors/estimation_run.h"

namespace {

using syrof::lab::sensors::EstimationRunReport;
using syrof::lab::sensors::FigureEight;

constexpr int kSeeds = 5;
constexpr double kTargetRmseM = 0.05;

template <typename Scalar>
double Report(const char* name) {
  const FigureEight trajectory(FigureEight::Params{});
  double position_sum = 0;
  double heading_sum = 0;
  double worst = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const EstimationRunReport report =
        syrof::lab::sensors::RunEstimation<Scalar>(syrof::lab::sensors::StandardRunOptions(trajectory, seed));
    std::printf("  %-6s seed %d: position RMSE %.4f m (max %.3f m), heading RMSE %.4f rad (%.2f deg), "
                "velocity RMSE %.4f m/s, ranges fused %u, rejected %u (outliers injected %llu)\n",
                name, seed, report.position_rmse_m, report.max_position_error_m, report.heading_rmse_rad,
                report.heading_rmse_rad * 180.0 / 3.14159265358979, report.velocity_rmse_mps,
                report.counters.ranges_fused, report.counters.ranges_rejected,
                static_cast<unsigned long long>(report.outliers_injected));
    position_sum += report.position_rmse_m * report.position_rmse_m;
    heading_sum += report.heading_rmse_rad * report.heading_rmse_rad;
    if (report.position_rmse_m > worst) worst = report.position_rmse_m;
  }
  const double position = std::sqrt(position_sum / kSeeds);
  std::printf("  %-6s all %d seeds: position RMSE %.4f m (worst seed %.4f m, target <= %.2f m: %s), heading RMSE "
              "%.4f rad (%.2f deg)\n",
              name, kSeeds, position, worst, kTargetRmseM, worst <= kTargetRmseM ? "met" : "MISSED",
              std::sqrt(heading_sum / kSeeds), std::sqrt(heading_sum / kSeeds) * 180.0 / 3.14159265358979);
  return worst;
}

}  // namespace

int main() {
  std::printf("estimation accuracy, standard run (figure eight at 0.5 m/s, default arena and noise, 120 s)\n");
  const double worst_float = Report<float>("float");
  const double worst_double = Report<double>("double");
  return worst_float <= kTargetRmseM && worst_double <= kTargetRmseM ? EXIT_SUCCESS : EXIT_FAILURE;
}
