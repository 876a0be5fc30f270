// The filter against simulated sensors (lab/sensors): consistency (NEES over
// seeded Monte Carlo runs), convergence, an outage, outliers, long runs and
// the accuracy bound of the standard run. Host only: it links the lab's
// simulated sensors and runs many seconds of virtual time.
#include <gtest/gtest.h>

#include <algorithm>
#include <Eigen/Cholesky>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "syrof/estimation/ekf.h"
#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/imu_model.h"
#include "syrof/estimation/range_model.h"
#include "syrof/lab/sensors/estimation_run.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sensors/trajectory.h"

namespace syrof::estimation {
namespace {

using lab::sensors::EstimationRunOptions;
using lab::sensors::EstimationRunReport;
using lab::sensors::FigureEight;
using lab::sensors::Initialization;
using lab::sensors::ReadingSink;
using lab::sensors::SensorBank;
using lab::sensors::SensorBankConfig;
using lab::sensors::TrueState;

constexpr int64_t kStepNs = 10'000'000;
constexpr double kStepS = 0.01;

// Holds what a bank emitted at one instant.
struct LatestReadings final : ReadingSink {
  void OnImu(const ImuReading& reading) override { imu = reading; }
  void OnFlow(const FlowReading& reading) override { flow = reading; }
  void OnUwb(const UwbReading& reading) override { uwb = reading; }
  void Clear() {
    imu.reset();
    flow.reset();
    uwb.reset();
  }
  std::optional<ImuReading> imu;
  std::optional<FlowReading> flow;
  std::optional<UwbReading> uwb;
};

// A bank and an Ekf<double> whose models match exactly: no accelerometer
// bias (the filter has no state for it), no outliers, and process noise
// densities equal to the simulated per-sample noise over the IMU period.
SensorBankConfig MatchedSensors() {
  SensorBankConfig sensors;
  sensors.imu.accel_bias_sigma_mps2 = 0;
  sensors.imu.accel_bias_walk_mps2_per_sqrt_s = 0;
  sensors.uwb.outlier_probability = 0;
  return sensors;
}

EkfParams<double> MatchedParams(const SensorBankConfig& sensors) {
  const double period_s = static_cast<double>(sensors.imu.period_ns) * 1e-9;
  EkfParams<double> params;
  params.process_noise.accel_noise_density = sensors.imu.accel_sigma_mps2 * std::sqrt(period_s);
  params.process_noise.gyro_noise_density = sensors.imu.gyro_sigma_radps * std::sqrt(period_s);
  params.process_noise.gyro_bias_walk = sensors.imu.gyro_bias_walk_radps_per_sqrt_s;
  return params;
}

// Wilson-Hilferty: the chi-square quantile with `dof` degrees of freedom at
// the standard normal quantile z (accurate to a fraction of a percent here).
double ChiSquareQuantile(double dof, double z) {
  const double a = 2.0 / (9.0 * dof);
  const double cube = 1.0 - a + z * std::sqrt(a);
  return dof * cube * cube * cube;
}

// One Monte Carlo run: the filter starts from the truth plus an error drawn
// from its own initial covariance, and NEES is recorded every kNeesEvery
// steps (consecutive values hardly differ, and each costs a factorization).
constexpr int kNeesEvery = 5;

std::vector<double> NeesRun(uint64_t seed, int steps) {
  const FigureEight trajectory(FigureEight::Params{});
  const SensorBankConfig sensors = MatchedSensors();
  SensorBank bank(sensors, seed);
  LatestReadings readings;
  const Arena<double>& arena = sensors.arena;
  const double metres_per_pixel = FlowMetresPerPixel(sensors.flow.geometry);
  // Rounding to whole pixels adds 1/12 px^2 to the noise.
  const double flow_sigma_px = std::sqrt(sensors.flow.sigma_px * sensors.flow.sigma_px + 1.0 / 12.0);

  StateVector<double> sigma;
  sigma << 0.1, 0.1, 0.05, 0.05, 0.05, sensors.imu.gyro_bias_sigma_radps;
  std::mt19937_64 random(seed ^ 0x5eedULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  const TrueState start = trajectory.At(0);
  StateVector<double> initial;
  initial << start.x_m, start.y_m, start.vx_mps, start.vy_mps, start.heading_rad, 0.0;
  for (int i = 0; i < kStateSize - 1; ++i) initial[i] += sigma[i] * normal(random);
  Ekf<double> filter(MatchedParams(sensors));
  filter.Reset(initial, sigma);

  std::vector<double> nees;
  nees.reserve(static_cast<size_t>(steps / kNeesEvery + 1));
  for (int k = 0; k < steps; ++k) {
    const int64_t now_ns = k * kStepNs;
    const TrueState truth = trajectory.At(now_ns);
    readings.Clear();
    bank.Sample(now_ns, truth, readings);
    if (k > 0 && readings.imu) {
      filter.Predict(kStepS, PlanarImuInput(ConvertImuReading<double>(*readings.imu).value()));
    }
    if (readings.flow) {
      const auto velocity = FlowToBodyVelocity(*readings.flow, metres_per_pixel, flow_sigma_px);
      EXPECT_EQ(FuseBodyVelocity(filter, velocity.value(), 0.0), EstimationError::kOk);
    }
    if (readings.uwb) {
      for (int i = 0; i < arena.anchor_count; ++i) {
        if ((readings.uwb->valid_mask & (1u << i)) == 0) continue;
        EXPECT_EQ(FuseRange(filter, arena.anchors[i], arena.tag_height_m,
                            static_cast<double>(readings.uwb->range_m[i]), sensors.uwb.sigma_m, 0.0),
                  EstimationError::kOk);
      }
    }
    if (k % kNeesEvery != 0) continue;
    StateVector<double> error;
    error << filter.state()[kStateX] - truth.x_m, filter.state()[kStateY] - truth.y_m,
        filter.state()[kStateVx] - truth.vx_mps, filter.state()[kStateVy] - truth.vy_mps,
        WrapAngle(filter.state()[kStateHeading] - truth.heading_rad),
        filter.state()[kStateGyroBias] - bank.imu_bias().gyro_radps[2];
    nees.push_back(error.dot(filter.covariance().ldlt().solve(error)));
  }
  return nees;
}

// For a consistent filter, NEES averaged over N independent runs at one step
// is chi-square with 6 N degrees of freedom, divided by N. Consecutive steps
// are strongly correlated (the gyro bias error of a run hardly changes), so
// the share of steps inside the bounds scatters from seed to seed; the test
// asks for 85 % inside the 99 % bounds, and, as a second check that accounts
// for the correlation, that the runs' time-averaged NEES (independent across
// runs) average to 6 within three of their own standard errors.
TEST(FilterConsistencyTest, NeesStaysWithinItsChiSquareBoundsOverMonteCarloRuns) {
  constexpr int kRuns = 40;
  constexpr int kSteps = 1250;  // 12.5 s: the first loop and into the second
  constexpr int kSamples = (kSteps + kNeesEvery - 1) / kNeesEvery;
  std::vector<double> average(kSamples, 0.0);
  std::vector<double> run_means;
  for (int run = 0; run < kRuns; ++run) {
    const std::vector<double> nees = NeesRun(1000 + run, kSteps);
    EXPECT_EQ(nees.size(), static_cast<size_t>(kSamples));
    double run_mean = 0;
    for (int k = 0; k < kSamples; ++k) {
      average[k] += nees[k] / kRuns;
      run_mean += nees[k] / kSamples;
    }
    run_means.push_back(run_mean);
  }
  const double dof = static_cast<double>(kRuns * kStateSize);
  const double lower = ChiSquareQuantile(dof, -2.576) / kRuns;  // 99 % two-sided
  const double upper = ChiSquareQuantile(dof, 2.576) / kRuns;
  int inside = 0;
  for (const double value : average) inside += value >= lower && value <= upper ? 1 : 0;
  const double fraction_inside = static_cast<double>(inside) / kSamples;

  double mean = 0;
  for (const double value : run_means) mean += value / kRuns;
  double variance = 0;
  for (const double value : run_means) variance += (value - mean) * (value - mean) / (kRuns - 1);
  const double standard_error = std::sqrt(variance / kRuns);

  RecordProperty("nees_mean", std::to_string(mean));
  RecordProperty("nees_standard_error", std::to_string(standard_error));
  RecordProperty("nees_fraction_inside", std::to_string(fraction_inside));
  EXPECT_GT(fraction_inside, 0.85) << "bounds [" << lower << ", " << upper << "]";
  EXPECT_LT(standard_error, 0.5);
  EXPECT_NEAR(mean, static_cast<double>(kStateSize), 3 * standard_error);
}

EstimationRunOptions FigureEightRun(const FigureEight& trajectory, uint64_t seed, double duration_s) {
  EstimationRunOptions options = lab::sensors::StandardRunOptions(trajectory, seed);
  options.duration_s = duration_s;
  return options;
}

TEST(FilterConvergenceTest, ConvergesFromAOneMetreInitialError) {
  const FigureEight trajectory(FigureEight::Params{});
  EstimationRunOptions options = FigureEightRun(trajectory, 7, 20);
  options.initialization = Initialization::kFromTruePose;
  options.initial_position_offset_x_m = 0.8;  // 1 m off
  options.initial_position_offset_y_m = -0.6;
  options.initial_position_sigma_m = 1.0;
  double error_after_1_s = -1;
  double error_after_5_s = -1;
  options.on_estimate = [&](const TrueState& truth, const StateEstimate& estimate) {
    const double error = std::hypot(estimate.x_m - truth.x_m, estimate.y_m - truth.y_m);
    if (estimate.timestamp_ns == 1'000'000'000) error_after_1_s = error;
    if (estimate.timestamp_ns == 5'000'000'000) error_after_5_s = error;
  };
  const EstimationRunReport report = lab::sensors::RunEstimation<float>(options);
  EXPECT_GE(error_after_1_s, 0.0);
  EXPECT_LT(error_after_1_s, 0.15);
  EXPECT_GE(error_after_5_s, 0.0);
  EXPECT_LT(error_after_5_s, 0.15);
  EXPECT_LT(report.position_rmse_m, 0.06);  // scored from 5 s to 20 s
  EXPECT_EQ(report.counters.relocalizations, 0u);
  EXPECT_EQ(report.counters.fixes, 1u);  // 1 m of doubt: the first sweep places the robot
}

TEST(FilterConvergenceTest, ConvergesThroughTheFilterFromAHalfMetreError) {
  const FigureEight trajectory(FigureEight::Params{});
  EstimationRunOptions options = FigureEightRun(trajectory, 17, 20);
  options.initialization = Initialization::kFromTruePose;
  options.initial_position_offset_x_m = -0.3;  // 0.5 m off, within the filter's own reach
  options.initial_position_offset_y_m = 0.4;
  options.initial_position_sigma_m = 0.45;
  double error_after_2_s = -1;
  options.on_estimate = [&](const TrueState& truth, const StateEstimate& estimate) {
    if (estimate.timestamp_ns == 2'000'000'000) {
      error_after_2_s = std::hypot(estimate.x_m - truth.x_m, estimate.y_m - truth.y_m);
    }
  };
  const EstimationRunReport report = lab::sensors::RunEstimation<float>(options);
  EXPECT_EQ(report.counters.fixes, 0u);
  EXPECT_GE(error_after_2_s, 0.0);
  EXPECT_LT(error_after_2_s, 0.15);
  EXPECT_LT(report.position_rmse_m, 0.06);  // scored from 5 s to 20 s
}

TEST(FilterConvergenceTest, RelocalizesAfterTheRobotIsCarriedAway) {
  const FigureEight trajectory(FigureEight::Params{});
  EstimationRunOptions options = FigureEightRun(trajectory, 8, 20);
  options.initialization = Initialization::kFromTruePose;
  options.initial_position_offset_x_m = 2.0;  // far outside the gate of its claimed 5 cm
  options.initial_position_sigma_m = 0.05;
  double error_after_2_s = -1;
  options.on_estimate = [&](const TrueState& truth, const StateEstimate& estimate) {
    if (estimate.timestamp_ns == 2'000'000'000) {
      error_after_2_s = std::hypot(estimate.x_m - truth.x_m, estimate.y_m - truth.y_m);
    }
  };
  const EstimationRunReport report = lab::sensors::RunEstimation<float>(options);
  EXPECT_EQ(report.counters.relocalizations, 1u);  // after five sweeps that all fail the gate
  EXPECT_EQ(report.counters.fixes, 1u);            // the sixth places the robot
  EXPECT_GE(error_after_2_s, 0.0);
  EXPECT_LT(error_after_2_s, 0.15);
  EXPECT_LT(report.position_rmse_m, 0.06);  // scored from 5 s to 20 s
}

TEST(FilterOutageTest, SurvivesFiveSecondsWithoutUwbAndRecovers) {
  const FigureEight trajectory(FigureEight::Params{});
  EstimationRunOptions options = FigureEightRun(trajectory, 9, 35);
  options.uwb_outage_start_s = 20;
  options.uwb_outage_end_s = 25;
  double worst_during_outage = 0;
  double worst_after_recovery = 0;
  bool stale_reported = false;
  bool stale_after_recovery = false;
  options.on_estimate = [&](const TrueState& truth, const StateEstimate& estimate) {
    const double t = static_cast<double>(estimate.timestamp_ns) * 1e-9;
    const double error = std::hypot(estimate.x_m - truth.x_m, estimate.y_m - truth.y_m);
    if (t >= 20 && t < 25) {
      worst_during_outage = std::max(worst_during_outage, error);
      stale_reported = stale_reported || (estimate.status & kEstimateUwbStale) != 0;
    }
    if (t >= 28) {
      worst_after_recovery = std::max(worst_after_recovery, error);
      stale_after_recovery = stale_after_recovery || (estimate.status & kEstimateUwbStale) != 0;
    }
  };
  const EstimationRunReport report = lab::sensors::RunEstimation<float>(options);
  EXPECT_LT(worst_during_outage, 0.3);  // dead reckoning on flow and IMU
  EXPECT_TRUE(stale_reported);
  EXPECT_LT(worst_after_recovery, 0.15);
  EXPECT_FALSE(stale_after_recovery);
  EXPECT_EQ(report.counters.relocalizations, 0u);
}

TEST(FilterOutlierTest, GateRejectsOutliersThatWouldOtherwiseSpoilThePosition) {
  const FigureEight trajectory(FigureEight::Params{});
  EstimationRunOptions options = FigureEightRun(trajectory, 10, 60);
  options.sensors.uwb.outlier_probability = 0.10;
  const EstimationRunReport gated = lab::sensors::RunEstimation<float>(options);
  EstimatorConfig<float> ungated_config;
  ungated_config.range_gate_sigma = 0;  // no gate
  const EstimationRunReport ungated = lab::sensors::RunEstimation<float>(options, ungated_config);

  ASSERT_GT(gated.outliers_injected, 100u);
  // Nearly every outlier is rejected, and few good ranges are (under 2 %).
  const uint32_t ranges = gated.counters.ranges_fused + gated.counters.ranges_rejected;
  EXPECT_GE(gated.counters.ranges_rejected, gated.outliers_injected * 95 / 100);
  EXPECT_LE(gated.counters.ranges_rejected, gated.outliers_injected + ranges / 50);
  EXPECT_LT(gated.position_rmse_m, 0.06);
  EXPECT_GT(ungated.position_rmse_m, 2 * gated.position_rmse_m);
}

TEST(FilterLongRunTest, CovarianceStaysSymmetricPositiveDefiniteForTenMinutesInFloat) {
  const FigureEight trajectory(FigureEight::Params{});
  const SensorBankConfig sensors;  // defaults: biases, outliers, dropouts
  SensorBank bank(sensors, 11);
  LatestReadings readings;
  const Arena<float> arena = DefaultArena<float>();
  const float metres_per_pixel = FlowMetresPerPixel(FlowGeometry<float>{});
  Ekf<float> filter;
  const TrueState start = trajectory.At(0);
  StateVector<float> initial;
  initial << static_cast<float>(start.x_m), static_cast<float>(start.y_m), 0, 0,
      static_cast<float>(start.heading_rad), 0;
  filter.Reset(initial, (StateVector<float>() << 0.3f, 0.3f, 0.5f, 0.5f, 0.1f, 0.01f).finished());
  int asymmetric = 0;
  int not_positive_definite = 0;
  double worst_error = 0;
  for (int k = 0; k < 60'000; ++k) {  // 600 s
    const int64_t now_ns = k * kStepNs;
    const TrueState truth = trajectory.At(now_ns);
    readings.Clear();
    bank.Sample(now_ns, truth, readings);
    if (k > 0 && readings.imu) filter.Predict(0.01f, PlanarImuInput(ConvertImuReading<float>(*readings.imu).value()));
    if (readings.flow) {
      (void)FuseBodyVelocity(filter, FlowToBodyVelocity(*readings.flow, metres_per_pixel, 2.0f).value(), 5.0f);
    }
    if (readings.uwb) {
      for (int i = 0; i < arena.anchor_count; ++i) {
        if ((readings.uwb->valid_mask & (1u << i)) == 0) continue;
        (void)FuseRange(filter, arena.anchors[i], arena.tag_height_m, readings.uwb->range_m[i], 0.1f, 3.5f);
      }
    }
    const StateCovariance<float>& covariance = filter.covariance();
    asymmetric += covariance == covariance.transpose() ? 0 : 1;
    // Factorized every tenth step (6000 times): the M4 test factorizes every step of a shorter run.
    if (k % 10 == 0) {
      not_positive_definite += Eigen::LLT<StateCovariance<float>>(covariance).info() == Eigen::Success ? 0 : 1;
    }
    if (k > 500) {
      worst_error = std::max(worst_error, std::hypot(filter.state()[kStateX] - truth.x_m,
                                                     filter.state()[kStateY] - truth.y_m));
    }
  }
  EXPECT_EQ(asymmetric, 0);
  EXPECT_EQ(not_positive_definite, 0);
  EXPECT_LT(worst_error, 0.2);
}

TEST(FilterAccuracyTest, StandardRunPositionRmseIsAtMostFiveCentimetres) {
  const FigureEight trajectory(FigureEight::Params{});
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const EstimationRunReport report =
        lab::sensors::RunEstimation<float>(lab::sensors::StandardRunOptions(trajectory, seed));
    EXPECT_LE(report.position_rmse_m, 0.05) << "seed " << seed;
    EXPECT_LT(report.heading_rmse_rad, 0.05) << "seed " << seed;
    EXPECT_GT(report.scored, 11'000u);
  }
}

TEST(FilterAccuracyTest, StandingRobotKeepsItsPosition) {
  const lab::sensors::StraightLine standing = lab::sensors::Stationary(1.2, 2.7, 0.4);
  EstimationRunOptions options;
  options.trajectory = &standing;
  options.duration_s = 60;
  options.seed = 12;
  const EstimationRunReport report = lab::sensors::RunEstimation<float>(options);
  EXPECT_LT(report.position_rmse_m, 0.05);
  EXPECT_LT(report.velocity_rmse_mps, 0.05);
}

// At rest nothing but the gyro speaks of the heading. Without zero-rate
// updates the bias estimate wanders and the heading with it (a parked robot
// in mixed_gather believed itself 1.9 rad off after a minute); with the flow
// allowed to "see" the heading at a near-zero speed, velocity noise moved it
// too. The heading's drift from 10 s (the start-up settled) to 120 s.
struct HeadingAtRest {
  double drift_rad = 0;       // |error(120 s) - error(10 s)|
  double final_error_rad = 0;
  double final_sigma_rad = 0;
};

HeadingAtRest RunAtRest(uint64_t seed, bool at_rest_rules) {
  const lab::sensors::StraightLine standing = lab::sensors::Stationary(2.2, 1.4, 1.0);
  EstimationRunOptions options;
  options.trajectory = &standing;
  options.duration_s = 120;
  options.seed = seed;
  options.sensors.imu.gyro_bias_sigma_radps = 0.01;  // twice the default: a worse part
  double error_at_10_s = 0;
  HeadingAtRest result;
  options.on_estimate = [&](const TrueState& truth, const StateEstimate& estimate) {
    const double error = std::remainder(estimate.heading_rad - truth.heading_rad, 2 * kPi<double>);
    if (estimate.timestamp_ns == 10'000'000'000) error_at_10_s = error;
    result.drift_rad = std::fabs(error - error_at_10_s);
    result.final_error_rad = std::fabs(error);
    result.final_sigma_rad = estimate.sigma_heading_rad;
  };
  EstimatorConfig<float> config;
  config.zero_rate.enabled = at_rest_rules;
  config.flow_heading_min_speed_mps = at_rest_rules ? 0.1f : 0.0f;
  const EstimationRunReport report = lab::sensors::RunEstimation<float>(options, config);
  if (at_rest_rules) {
    EXPECT_GT(report.counters.zero_rate_fused, 11'000u) << "seed " << seed;
  }
  return result;
}

TEST(FilterAccuracyTest, StandingRobotKeepsItsHeadingForTwoMinutes) {
  double worst_without = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const HeadingAtRest with = RunAtRest(seed, true);
    EXPECT_LT(with.drift_rad, 0.03) << "seed " << seed;
    EXPECT_LT(with.final_error_rad, 3 * with.final_sigma_rad) << "seed " << seed;  // and it knows its doubt
    worst_without = std::max(worst_without, RunAtRest(seed, false).drift_rad);
  }
  // The same runs without the two rules: what they prevent.
  EXPECT_GT(worst_without, 0.2);
}

TEST(FilterAccuracyTest, SameOptionsGiveTheSameRun) {
  const FigureEight trajectory(FigureEight::Params{});
  const EstimationRunOptions options = FigureEightRun(trajectory, 13, 10);
  const EstimationRunReport first = lab::sensors::RunEstimation<float>(options);
  const EstimationRunReport second = lab::sensors::RunEstimation<float>(options);
  EXPECT_EQ(first.position_rmse_m, second.position_rmse_m);
  EXPECT_EQ(first.heading_rmse_rad, second.heading_rmse_rad);
  EXPECT_EQ(first.counters.ranges_fused, second.counters.ranges_fused);
}

}  // namespace
}  // namespace syrof::estimation
