#include "syrof/lab/sensors/estimation_run.h"

#include <cmath>

#include "syrof/base/check.h"
#include "syrof/estimation/topics.h"
#include "syrof/lab/sensors/sensor_publishers.h"
#include "syrof/os/sim_port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"
#include "units.h"

namespace syrof::lab::sensors {
namespace {

int64_t ToNanoseconds(double seconds) { return static_cast<int64_t>(std::llround(seconds * kNanosecondsPerSecond)); }

// The simulated drivers, with the UWB outage of the options.
class DriversTask final : public os::Task {
 public:
  DriversTask(const EstimationRunOptions& options, SensorBank& bank, ReadingSink& sink)
      : options_(options), bank_(bank), sink_(sink) {}

  void Step(int64_t now_ns) override {
    const double now_s = static_cast<double>(now_ns) / kNanosecondsPerSecond;
    const bool outage = now_s >= options_.uwb_outage_start_s && now_s < options_.uwb_outage_end_s;
    bank_.set_enabled(SensorKind::kUwb, !outage);
    bank_.Sample(now_ns, options_.trajectory->At(now_ns), sink_);
  }

 private:
  const EstimationRunOptions& options_;
  SensorBank& bank_;
  ReadingSink& sink_;
};

// Scores every published estimate against the truth at its timestamp.
class ScoringTask final : public os::Task {
 public:
  explicit ScoringTask(const EstimationRunOptions& options) : options_(options) {}

  void Step(int64_t /*now_ns*/) override {
    estimation::StateEstimate estimate{};
    while (estimates.Take(estimate)) Score(estimate);
  }

  void Fill(EstimationRunReport& report) const {
    if (scored_ > 0) {
      const double count = static_cast<double>(scored_);
      report.position_rmse_m = std::sqrt(position_sum_ / count);
      report.heading_rmse_rad = std::sqrt(heading_sum_ / count);
      report.velocity_rmse_mps = std::sqrt(velocity_sum_ / count);
    }
    report.max_position_error_m = max_position_error_;
    report.final_position_error_m = final_position_error_;
    report.scored = scored_;
  }

  pubsub::Subscriber<estimation::StateEstimate, 4> estimates;

 private:
  void Score(const estimation::StateEstimate& estimate) {
    const TrueState truth = options_.trajectory->At(estimate.timestamp_ns);
    if (options_.on_estimate) options_.on_estimate(truth, estimate);
    if ((estimate.status & estimation::kEstimateInitialized) == 0) return;
    const double position_error = std::hypot(estimate.x_m - truth.x_m, estimate.y_m - truth.y_m);
    final_position_error_ = position_error;
    if (static_cast<double>(estimate.timestamp_ns) < options_.warmup_s * kNanosecondsPerSecond) return;
    const double heading_error = std::remainder(estimate.heading_rad - truth.heading_rad, 2 * 3.14159265358979323846);
    const double velocity_error = std::hypot(estimate.vx_mps - truth.vx_mps, estimate.vy_mps - truth.vy_mps);
    position_sum_ += position_error * position_error;
    heading_sum_ += heading_error * heading_error;
    velocity_sum_ += velocity_error * velocity_error;
    if (position_error > max_position_error_) max_position_error_ = position_error;
    ++scored_;
  }

  const EstimationRunOptions& options_;
  double position_sum_ = 0;
  double heading_sum_ = 0;
  double velocity_sum_ = 0;
  double max_position_error_ = 0;
  double final_position_error_ = 0;
  uint64_t scored_ = 0;
};

}  // namespace

template <typename Scalar>
EstimationRunReport RunEstimation(const EstimationRunOptions& options,
                                  const estimation::EstimatorConfig<Scalar>& config) {
  SYROF_CHECK(options.trajectory != nullptr);
  const TrueState start = options.trajectory->At(0);
  estimation::EstimatorConfig<Scalar> estimator_config = config;
  if (options.initialization == Initialization::kFromFirstSweep) {
    estimator_config.initial_heading_rad = static_cast<Scalar>(start.heading_rad);
  }

  os::SimScheduler scheduler(8);
  os::SimPort port(scheduler, "robot");
  pubsub::StaticBroker<8, 8> broker(port);
  SensorBank bank(options.sensors, options.seed);
  SensorPublishers publishers;
  DriversTask drivers(options, bank, publishers);
  estimation::Estimator<Scalar> estimator(estimator_config);
  ScoringTask scoring(options);

  SYROF_CHECK(port.AddTask(drivers, SimulatedSensorsTask::Config()).ok());
  SYROF_CHECK(publishers.Advertise(broker) == pubsub::BrokerError::kOk);
  SYROF_CHECK(estimator.Attach(port, broker) == estimation::EstimatorSetupError::kOk);
  const auto scoring_id = port.AddTask(scoring, {"scoring", os::Trigger::notified(), 0});
  SYROF_CHECK(scoring_id.ok());
  SYROF_CHECK(scoring.estimates.Subscribe(broker, estimation::kStateEstimateTopic, scoring_id.value()) ==
              pubsub::BrokerError::kOk);
  if (options.initialization == Initialization::kFromTruePose) {
    estimation::InitialPose<Scalar> pose;
    pose.x_m = static_cast<Scalar>(start.x_m + options.initial_position_offset_x_m);
    pose.y_m = static_cast<Scalar>(start.y_m + options.initial_position_offset_y_m);
    pose.heading_rad = static_cast<Scalar>(start.heading_rad);
    pose.position_sigma_m = static_cast<Scalar>(options.initial_position_sigma_m);
    estimator.SetInitialPose(pose);
  }

  SYROF_CHECK(port.Start() == os::PortError::kOk);
  scheduler.RunUntil(ToNanoseconds(options.duration_s));
  SYROF_CHECK(port.Stop() == os::PortError::kOk);

  EstimationRunReport report;
  scoring.Fill(report);
  report.outliers_injected = bank.uwb_outliers();
  report.counters = estimator.counters();
  return report;
}

EstimationRunOptions StandardRunOptions(const FigureEight& trajectory, uint64_t seed) {
  EstimationRunOptions options;
  options.trajectory = &trajectory;
  options.duration_s = 120;
  options.warmup_s = 5;
  options.seed = seed;
  return options;
}

template EstimationRunReport RunEstimation<float>(const EstimationRunOptions&,
                                                  const estimation::EstimatorConfig<float>&);
template EstimationRunReport RunEstimation<double>(const EstimationRunOptions&,
                                                   const estimation::EstimatorConfig<double>&);

}  // namespace syrof::lab::sensors
