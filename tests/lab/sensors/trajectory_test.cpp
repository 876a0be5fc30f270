#include "syrof/lab/sensors/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace syrof::lab::sensors {
namespace {

constexpr int64_t kTrajectoryMs = 1'000'000;

double Wrap(double radians) { return std::remainder(radians, 2 * std::numbers::pi); }

// Central differences of position, velocity and heading over +-1 ms.
void ExpectDerivativesAgree(const Trajectory& trajectory, int64_t time_ns) {
  constexpr int64_t kStep = kTrajectoryMs;
  constexpr double kStepS = 1e-3;
  const TrueState before = trajectory.At(time_ns - kStep);
  const TrueState now = trajectory.At(time_ns);
  const TrueState after = trajectory.At(time_ns + kStep);
  EXPECT_NEAR((after.x_m - before.x_m) / (2 * kStepS), now.vx_mps, 1e-6) << time_ns;
  EXPECT_NEAR((after.y_m - before.y_m) / (2 * kStepS), now.vy_mps, 1e-6) << time_ns;
  EXPECT_NEAR((after.vx_mps - before.vx_mps) / (2 * kStepS), now.ax_mps2, 1e-5) << time_ns;
  EXPECT_NEAR((after.vy_mps - before.vy_mps) / (2 * kStepS), now.ay_mps2, 1e-5) << time_ns;
  EXPECT_NEAR(Wrap(after.heading_rad - before.heading_rad) / (2 * kStepS), now.yaw_rate_radps, 1e-6) << time_ns;
}

TEST(FigureEightTest, StartsAtTheCentreHeadingUpAndKeepsItsSpeed) {
  const FigureEight eight(FigureEight::Params{2.0, 2.0, 0.8, 0.5});
  const TrueState start = eight.At(0);
  EXPECT_DOUBLE_EQ(start.x_m, 2.0);
  EXPECT_DOUBLE_EQ(start.y_m, 2.0);
  EXPECT_NEAR(start.heading_rad, std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(eight.lap_s(), 4 * std::numbers::pi * 0.8 / 0.5, 1e-12);
  for (int64_t t = 0; t < 45'000 * kTrajectoryMs; t += 37 * kTrajectoryMs) {
    const TrueState state = eight.At(t);
    EXPECT_NEAR(std::hypot(state.vx_mps, state.vy_mps), 0.5, 1e-12);
    EXPECT_NEAR(std::hypot(state.ax_mps2, state.ay_mps2), 0.5 * 0.5 / 0.8, 1e-12);
    EXPECT_NEAR(Wrap(state.heading_rad - std::atan2(state.vy_mps, state.vx_mps)), 0.0, 1e-12);  // faces its path
    EXPECT_GE(state.x_m, 0.4 - 1e-9);
    EXPECT_LE(state.x_m, 3.6 + 1e-9);
    EXPECT_GE(state.y_m, 1.2 - 1e-9);
    EXPECT_LE(state.y_m, 2.8 + 1e-9);
  }
}

TEST(FigureEightTest, VelocityAccelerationAndYawRateAreTheDerivatives) {
  const FigureEight eight(FigureEight::Params{});
  const int64_t half_lap_ns = static_cast<int64_t>(eight.lap_s() / 2 * 1e9);
  for (int64_t t = 100 * kTrajectoryMs; t < 40'000 * kTrajectoryMs; t += 173 * kTrajectoryMs) {
    // Acceleration and yaw rate switch sign at the centre, every half lap.
    const int64_t from_switch = t % half_lap_ns;
    if (from_switch < 2 * kTrajectoryMs || half_lap_ns - from_switch < 2 * kTrajectoryMs) continue;
    ExpectDerivativesAgree(eight, t);
  }
}

TEST(FigureEightTest, DrivesTheRightLoopClockwiseAndTheLeftLoopCounterClockwise) {
  const FigureEight eight(FigureEight::Params{});
  EXPECT_LT(eight.At(1000 * kTrajectoryMs).yaw_rate_radps, 0.0);
  EXPECT_GT(eight.At(1000 * kTrajectoryMs).x_m, 2.0);
  const int64_t three_quarters = static_cast<int64_t>(eight.lap_s() * 0.75 * 1e9);
  EXPECT_GT(eight.At(three_quarters).yaw_rate_radps, 0.0);
  EXPECT_LT(eight.At(three_quarters).x_m, 2.0);
  // Back at the start after a lap.
  const TrueState lap = eight.At(static_cast<int64_t>(std::llround(eight.lap_s() * 1e9)));
  EXPECT_NEAR(lap.x_m, 2.0, 1e-6);
  EXPECT_NEAR(lap.y_m, 2.0, 1e-6);
}

TEST(StraightLineTest, MovesAtConstantVelocity) {
  const StraightLine line(StraightLine::Params{0.5, 1.0, std::numbers::pi / 4, 0.2});
  const TrueState state = line.At(10'000 * kTrajectoryMs);
  EXPECT_NEAR(state.x_m, 0.5 + 2.0 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(state.y_m, 1.0 + 2.0 / std::sqrt(2.0), 1e-12);
  EXPECT_DOUBLE_EQ(state.ax_mps2, 0.0);
  EXPECT_DOUBLE_EQ(state.yaw_rate_radps, 0.0);
  ExpectDerivativesAgree(line, 5000 * kTrajectoryMs);
}

TEST(StationaryTest, StandsStill) {
  const StraightLine standing = Stationary(1.0, 3.0, -2.0);
  const TrueState state = standing.At(60'000 * kTrajectoryMs);
  EXPECT_DOUBLE_EQ(state.x_m, 1.0);
  EXPECT_DOUBLE_EQ(state.y_m, 3.0);
  EXPECT_DOUBLE_EQ(state.vx_mps, 0.0);
  EXPECT_DOUBLE_EQ(state.heading_rad, -2.0);
}

}  // namespace
}  // namespace syrof::lab::sensors
