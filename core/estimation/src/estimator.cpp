#include "syrof/estimation/estimator.h"

#include <cmath>

#include "syrof/estimation/imu_model.h"
#include "syrof/estimation/multilateration.h"
#include "syrof/estimation/range_model.h"
#include "syrof/registry/tasks.h"

namespace syrof::estimation {

const char* ToString(EstimatorSetupError error) {
  switch (error) {
    case EstimatorSetupError::kOk: return "Ok";
    case EstimatorSetupError::kAlreadyAttached: return "AlreadyAttached";
    case EstimatorSetupError::kAddTaskFailed: return "AddTaskFailed";
    case EstimatorSetupError::kSubscribeFailed: return "SubscribeFailed";
    case EstimatorSetupError::kAdvertiseFailed: return "AdvertiseFailed";
  }
  return "?";
}

namespace {

// The flow scale is fixed by the geometry; computing it once keeps two
// tangents out of every flow reading. An invalid geometry gives 0, which
// makes every reading invalid (counted as dropped).
template <typename Scalar>
Scalar MetresPerPixel(const FlowGeometry<Scalar>& geometry) {
  FlowReading probe{};
  probe.interval_ns = 1;
  if (!FlowToBodyVelocity(probe, geometry, Scalar{1})) return 0;
  return FlowMetresPerPixel(geometry);
}

}  // namespace

template <typename Scalar>
Estimator<Scalar>::Estimator(const EstimatorConfig<Scalar>& config)
    : config_(config),
      flow_metres_per_pixel_(MetresPerPixel(config.flow_geometry)),
      filter_(config.filter),
      state_task_(*this),
      kalman_task_(*this) {}

template <typename Scalar>
EstimatorSetupError Estimator<Scalar>::Attach(os::Port& port, pubsub::Broker& broker) {
  if (port_ != nullptr) return EstimatorSetupError::kAlreadyAttached;
  const auto state_id =
      port.AddTask(state_task_, {"estimation.state", os::Trigger::notified(), registry::kStateTaskPriority});
  if (!state_id) return EstimatorSetupError::kAddTaskFailed;
  const auto kalman_id = port.AddTask(
      kalman_task_, {"estimation.kalman", os::Trigger::periodic(registry::kKalmanPeriodNs), registry::kKalmanTaskPriority});
  if (!kalman_id) return EstimatorSetupError::kAddTaskFailed;
  if (imu_subscriber_.Subscribe(broker, kImuTopic, state_id.value()) != pubsub::BrokerError::kOk ||
      flow_subscriber_.Subscribe(broker, kFlowTopic, state_id.value()) != pubsub::BrokerError::kOk ||
      uwb_subscriber_.Subscribe(broker, kUwbTopic, state_id.value()) != pubsub::BrokerError::kOk) {
    return EstimatorSetupError::kSubscribeFailed;
  }
  if (estimate_publisher_.Advertise(broker, kStateEstimateTopic) != pubsub::BrokerError::kOk) {
    return EstimatorSetupError::kAdvertiseFailed;
  }
  port_ = &port;
  return EstimatorSetupError::kOk;
}

template <typename Scalar>
void Estimator<Scalar>::SetInitialPose(const InitialPose<Scalar>& pose) {
  if (port_ == nullptr) {
    pending_.pose = pose;
    pending_.has_pose = true;
    return;
  }
  os::CriticalSection lock(*port_);
  pending_.pose = pose;
  pending_.has_pose = true;
}

template <typename Scalar>
void Estimator<Scalar>::StateTask::Step(int64_t /*now_ns*/) {
  owner_.CollectReadings();
}

template <typename Scalar>
void Estimator<Scalar>::KalmanTask::Step(int64_t now_ns) {
  owner_.RunKalmanStep(now_ns);
}

// The paper's state task: take every new reading, convert it to SI with its
// noise, and queue it for the Kalman task. Conversion happens outside the
// critical section; only the copy into the queue is inside.
template <typename Scalar>
void Estimator<Scalar>::CollectReadings() {
  ImuReading imu{};
  while (imu_subscriber_.Take(imu)) {
    const auto sample = ConvertImuReading<Scalar>(imu);
    os::CriticalSection lock(*port_);
    if (!sample) {
      ++pending_.dropped;
      continue;
    }
    const ImuInput<Scalar> input = PlanarImuInput(sample.value());
    pending_.imu_sum.accel_forward_mps2 += input.accel_forward_mps2;
    pending_.imu_sum.accel_left_mps2 += input.accel_left_mps2;
    pending_.imu_sum.yaw_rate_radps += input.yaw_rate_radps;
    ++pending_.imu_count;
  }
  FlowReading flow{};
  while (flow_subscriber_.Take(flow)) {
    const auto velocity = FlowToBodyVelocity(flow, flow_metres_per_pixel_, config_.flow_sigma_px);
    os::CriticalSection lock(*port_);
    if (!velocity || pending_.flow_count == kMaxQueuedFlow) {
      ++pending_.dropped;
      continue;
    }
    pending_.flow[pending_.flow_count++] = velocity.value();
  }
  UwbReading sweep{};
  while (uwb_subscriber_.Take(sweep)) {
    os::CriticalSection lock(*port_);
    if (pending_.sweep_count == kMaxQueuedSweeps) {
      ++pending_.dropped;
      continue;
    }
    pending_.sweeps[pending_.sweep_count++] = sweep;
  }
}

template <typename Scalar>
bool Estimator<Scalar>::FixFromSweep(const UwbReading& sweep, Vector2<Scalar>& position) const {
  Vector3<Scalar> anchors[kMaxAnchors];
  Scalar ranges[kMaxAnchors];
  size_t count = 0;
  for (int i = 0; i < config_.arena.anchor_count && i < kMaxAnchors; ++i) {
    if ((sweep.valid_mask & (1u << i)) == 0) continue;
    anchors[count] = config_.arena.anchors[i];
    ranges[count] = static_cast<Scalar>(sweep.range_m[i]);
    ++count;
  }
  const auto fix = MultilaterateOnPlaneRobust<Scalar>(std::span<const Vector3<Scalar>>(anchors, count),
                                                      std::span<const Scalar>(ranges, count),
                                                      config_.arena.tag_height_m,
                                                      config_.fix_residual_sigma * config_.range_sigma_m);
  if (!fix) return false;
  position = fix.value();
  return true;
}

template <typename Scalar>
bool Estimator<Scalar>::InitializeFromSweep(const UwbReading& sweep) {
  Vector2<Scalar> position;
  if (!FixFromSweep(sweep, position)) return false;
  StateVector<Scalar> state;
  state << position[0], position[1], 0, 0, config_.initial_heading_rad, 0;
  StateVector<Scalar> sigma;
  sigma << config_.initial_position_sigma_m, config_.initial_position_sigma_m, config_.initial_velocity_sigma_mps,
      config_.initial_velocity_sigma_mps, config_.initial_heading_sigma_rad, config_.initial_gyro_bias_sigma_radps;
  filter_.Reset(state, sigma);
  ++counters_.fixes;
  return true;
}

template <typename Scalar>
void Estimator<Scalar>::FuseSweep(const UwbReading& sweep, int64_t now_ns) {
  const StateCovariance<Scalar>& covariance = filter_.covariance();
  const Scalar largest_variance = covariance(kStateX, kStateX) > covariance(kStateY, kStateY)
                                      ? covariance(kStateX, kStateX)
                                      : covariance(kStateY, kStateY);
  if (largest_variance > config_.fix_above_sigma_m * config_.fix_above_sigma_m) {
    // Lost: only a consistent fix may place the robot; linearized updates
    // from this far could settle anywhere.
    Vector2<Scalar> position;
    if (FixFromSweep(sweep, position)) {
      filter_.ResetPosition(position[0], position[1], config_.initial_position_sigma_m);
      ++counters_.fixes;
      inconsistent_sweeps_ = 0;
      last_range_fused_ns_ = now_ns;
    }
    return;
  }
  int excluded = -1;  // anchor index the sweep screen throws out
  if (largest_variance > config_.screen_above_sigma_m * config_.screen_above_sigma_m) {
    Vector3<Scalar> anchors[kMaxAnchors];
    Scalar ranges[kMaxAnchors];
    int anchor_of[kMaxAnchors];
    size_t count = 0;
    for (int i = 0; i < config_.arena.anchor_count && i < kMaxAnchors; ++i) {
      if ((sweep.valid_mask & (1u << i)) == 0) continue;
      anchors[count] = config_.arena.anchors[i];
      ranges[count] = static_cast<Scalar>(sweep.range_m[i]);
      anchor_of[count] = i;
      ++count;
    }
    const int worst = FindInconsistentRange<Scalar>(
        filter_.state(), std::span<const Vector3<Scalar>>(anchors, count), std::span<const Scalar>(ranges, count),
        config_.arena.tag_height_m, config_.range_sigma_m, config_.range_gate_sigma);
    if (worst >= 0) excluded = anchor_of[worst];
  }
  int fused = 0;
  int gated = 0;
  for (int i = 0; i < config_.arena.anchor_count && i < kMaxAnchors; ++i) {
    if ((sweep.valid_mask & (1u << i)) == 0) continue;
    if (i == excluded) {
      ++counters_.ranges_rejected;
      ++gated;
      continue;
    }
    const EstimationError error =
        FuseRange(filter_, config_.arena.anchors[i], config_.arena.tag_height_m, static_cast<Scalar>(sweep.range_m[i]),
                  config_.range_sigma_m, config_.range_gate_sigma);
    if (error == EstimationError::kOk) {
      ++fused;
      continue;
    }
    ++counters_.ranges_rejected;
    if (error == EstimationError::kRejectedByGate) ++gated;
  }
  counters_.ranges_fused += static_cast<uint32_t>(fused);
  if (fused > 0) last_range_fused_ns_ = now_ns;
  // One outlier in a sweep is common (a person walks by an anchor); two or
  // more, sweep after sweep, means the estimate is wrong.
  const bool inconsistent = gated >= 2;
  inconsistent_sweeps_ = inconsistent ? inconsistent_sweeps_ + 1 : 0;
  if (inconsistent_sweeps_ >= config_.max_inconsistent_sweeps) {
    filter_.InflatePositionVariance(config_.relocalization_variance_m2);
    ++counters_.relocalizations;
    inconsistent_sweeps_ = 0;
  }
}

template <typename Scalar>
void Estimator<Scalar>::RunKalmanStep(int64_t now_ns) {
  Pending batch;
  {
    os::CriticalSection lock(*port_);
    batch = pending_;
    pending_ = Pending{};
  }
  ++counters_.steps;
  counters_.imu_samples += batch.imu_count;
  counters_.readings_dropped += batch.dropped;

  int first_sweep = 0;
  if (batch.has_pose) {
    const InitialPose<Scalar>& pose = batch.pose;
    StateVector<Scalar> state;
    state << pose.x_m, pose.y_m, 0, 0, pose.heading_rad, 0;
    StateVector<Scalar> sigma;
    sigma << pose.position_sigma_m, pose.position_sigma_m, config_.initial_velocity_sigma_mps,
        config_.initial_velocity_sigma_mps, pose.heading_sigma_rad, config_.initial_gyro_bias_sigma_radps;
    filter_.Reset(state, sigma);
    initialized_ = true;
    last_step_ns_ = now_ns;
    last_range_fused_ns_ = now_ns;
  } else if (!initialized_) {
    for (; first_sweep < batch.sweep_count && !initialized_; ++first_sweep) {
      initialized_ = InitializeFromSweep(batch.sweeps[first_sweep]);
    }
    if (initialized_) {
      // The sweep that placed the robot is not fused again: its ranges are
      // already in the position and its covariance.
      last_step_ns_ = now_ns;
      last_range_fused_ns_ = now_ns;
    }
  }

  ImuInput<Scalar> imu{};
  const bool imu_missing = batch.imu_count == 0;
  if (!imu_missing) {
    const Scalar count = static_cast<Scalar>(batch.imu_count);
    imu = ImuInput<Scalar>{batch.imu_sum.accel_forward_mps2 / count, batch.imu_sum.accel_left_mps2 / count,
                           batch.imu_sum.yaw_rate_radps / count};
  }
  if (initialized_) {
    int64_t step_ns = now_ns - last_step_ns_;
    if (step_ns > config_.max_step_ns) step_ns = config_.max_step_ns;
    const Scalar dt_s = static_cast<Scalar>(step_ns) / static_cast<Scalar>(1e9);
    if (imu_missing) {
      filter_.PredictWithoutImu(dt_s);
    } else {
      filter_.Predict(dt_s, imu);
    }
    for (int i = 0; i < batch.flow_count; ++i) {
      if (FuseBodyVelocity(filter_, batch.flow[i], config_.flow_gate_sigma) == EstimationError::kOk) {
        ++counters_.flow_fused;
      } else {
        ++counters_.flow_rejected;
      }
    }
    for (int i = first_sweep; i < batch.sweep_count; ++i) FuseSweep(batch.sweeps[i], now_ns);
  }
  last_step_ns_ = now_ns;
  PublishEstimate(now_ns, imu, imu_missing);
}

template <typename Scalar>
void Estimator<Scalar>::PublishEstimate(int64_t now_ns, const ImuInput<Scalar>& imu, bool imu_missing) {
  StateEstimate estimate{};
  estimate.timestamp_ns = now_ns;
  if (initialized_) {
    const StateVector<Scalar>& state = filter_.state();
    const StateCovariance<Scalar>& covariance = filter_.covariance();
    estimate.x_m = static_cast<float>(state[kStateX]);
    estimate.y_m = static_cast<float>(state[kStateY]);
    estimate.vx_mps = static_cast<float>(state[kStateVx]);
    estimate.vy_mps = static_cast<float>(state[kStateVy]);
    estimate.heading_rad = static_cast<float>(state[kStateHeading]);
    estimate.gyro_bias_radps = static_cast<float>(state[kStateGyroBias]);
    estimate.yaw_rate_radps = imu_missing ? 0.0f : static_cast<float>(imu.yaw_rate_radps - state[kStateGyroBias]);
    estimate.sigma_x_m = static_cast<float>(std::sqrt(covariance(kStateX, kStateX)));
    estimate.sigma_y_m = static_cast<float>(std::sqrt(covariance(kStateY, kStateY)));
    estimate.sigma_heading_rad = static_cast<float>(std::sqrt(covariance(kStateHeading, kStateHeading)));
    estimate.status |= kEstimateInitialized;
    if (now_ns - last_range_fused_ns_ > config_.uwb_stale_ns) estimate.status |= kEstimateUwbStale;
  }
  if (imu_missing) estimate.status |= kEstimateImuMissing;
  estimate.ranges_fused = counters_.ranges_fused;
  estimate.ranges_rejected = counters_.ranges_rejected;
  estimate.flow_rejected = counters_.flow_rejected;
  last_estimate_ = estimate;
  // Publishing fails only before Attach(), which is what started this task.
  (void)estimate_publisher_.Publish(estimate);
}

template class Estimator<float>;
template class Estimator<double>;

}  // namespace syrof::estimation
