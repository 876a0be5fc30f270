// One robot's estimator on the simulation port, fed by simulated sensors
// along a scripted trajectory, scored against the truth: the harness behind
// the estimator's accuracy benchmark and tests, and a template for how the
// lab wires sensors and estimator on a robot's broker.
#pragma once

#include <cstdint>
#include <functional>

#include "syrof/estimation/estimator.h"
#include "syrof/estimation/messages.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/sensors/trajectory.h"

namespace syrof::lab::sensors {

enum class Initialization : uint8_t {
  kFromFirstSweep,  ///< the estimator places itself from its first UWB sweep; heading = the true initial heading
  kFromTruePose,    ///< SetInitialPose with the true pose at time 0 plus initial_position_offset_m
};

struct EstimationRunOptions {
  const Trajectory* trajectory = nullptr;  ///< required
  double duration_s = 60;
  double warmup_s = 5;  ///< estimates before this time are not scored
  uint64_t seed = 1;
  SensorBankConfig sensors{};
  Initialization initialization = Initialization::kFromFirstSweep;
  /// With kFromTruePose: the pose given is off by this much in x and y, and
  /// claims initial_position_sigma_m of uncertainty.
  double initial_position_offset_x_m = 0;
  double initial_position_offset_y_m = 0;
  double initial_position_sigma_m = 0.1;
  /// UWB silent in [start, end) seconds; no outage when end <= start.
  double uwb_outage_start_s = 0;
  double uwb_outage_end_s = 0;
  /// Called for every published estimate with the truth at its timestamp.
  std::function<void(const TrueState&, const estimation::StateEstimate&)> on_estimate;
};

struct EstimationRunReport {
  double position_rmse_m = 0;   ///< over scored estimates
  double heading_rmse_rad = 0;
  double velocity_rmse_mps = 0;
  double max_position_error_m = 0;
  double final_position_error_m = 0;
  uint64_t scored = 0;          ///< estimates scored (initialized, after warm-up)
  uint64_t outliers_injected = 0;
  estimation::EstimatorCounters counters{};
};

/// Runs the estimator (Estimator<Scalar>, its state and Kalman tasks) with a
/// SensorBank on one SimPort for options.duration_s of virtual time.
/// Deterministic for given options.
template <typename Scalar>
EstimationRunReport RunEstimation(const EstimationRunOptions& options,
                                  const estimation::EstimatorConfig<Scalar>& config = {});

/// The standard run of the accuracy benchmark: a figure eight at 0.5 m/s
/// (loops of 0.8 m in the default 4 m arena), the default noise models,
/// 120 s, scored after 5 s.
EstimationRunOptions StandardRunOptions(const FigureEight& trajectory, uint64_t seed);

}  // namespace syrof::lab::sensors
