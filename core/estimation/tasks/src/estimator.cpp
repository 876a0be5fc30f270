#include "syrof/estimation/estimator.h"

#include <cmath>

#include "syrof/estimation/imu_model.h"
#include "syrof/estimation/uwb_screen.h"
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

// The sweep policy is uwb_screen.h's; the task only keeps the counters and
// the time of the last fused range.
template <typename Scalar>
void Estimator<Scalar>::FuseSweep(const UwbReading& sweep, int64_t now_ns) {
  const SweepOutcome outcome = ApplySweep(filter_, inconsistent_sweeps_, sweep, config_);
  counters_.ranges_fused += static_cast<uint32_t>(outcome.fused);
  counters_.ranges_rejected += static_cast<uint32_t>(outcome.rejected);
  if (outcome.fixed) ++counters_.fixes;
  if (outcome.relocalized) ++counters_.relocalizations;
  if (outcome.fixed || outcome.fused > 0) last_range_fused_ns_ = now_ns;
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
    StartFilter(filter_, batch.pose, config_);
    zero_rate_detector_.Reset();
    initialized_ = true;
    last_step_ns_ = now_ns;
    last_range_fused_ns_ = now_ns;
  } else if (!initialized_) {
    for (; first_sweep < batch.sweep_count && !initialized_; ++first_sweep) {
      initialized_ = StartFilterFromSweep(filter_, batch.sweeps[first_sweep], config_);
      if (initialized_) ++counters_.fixes;
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
      zero_rate_detector_.Reset();
    } else {
      filter_.Predict(dt_s, imu);
      const Scalar turning_radps = imu.yaw_rate_radps - filter_.state()[kStateGyroBias];
      if (zero_rate_detector_.Step(config_.zero_rate, turning_radps, now_ns) &&
          FuseZeroRate(filter_, imu.yaw_rate_radps, config_.zero_rate) == EstimationError::kOk) {
        ++counters_.zero_rate_fused;
      }
    }
    for (int i = 0; i < batch.flow_count; ++i) {
      const EstimationError fused =
          FuseBodyVelocity(filter_, batch.flow[i], config_.flow_gate_sigma, config_.flow_heading_min_speed_mps);
      if (fused == EstimationError::kOk) {
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

template <typename Scalar>
void Estimator<Scalar>::AddToDigest(base::StateDigest& digest) const {
  // Field by field: the structs have padding, which equal states need not share.
  digest.AddBytes(std::as_bytes(std::span(filter_.state().data(), static_cast<size_t>(filter_.state().size()))));
  digest.AddBytes(
      std::as_bytes(std::span(filter_.covariance().data(), static_cast<size_t>(filter_.covariance().size()))));
  digest.AddValue(pending_.imu_sum.accel_forward_mps2);
  digest.AddValue(pending_.imu_sum.accel_left_mps2);
  digest.AddValue(pending_.imu_sum.yaw_rate_radps);
  digest.AddValue(pending_.imu_count);
  digest.AddValue(pending_.flow_count);
  for (int i = 0; i < pending_.flow_count && i < kMaxQueuedFlow; ++i) {
    digest.AddValue(pending_.flow[i].forward_mps);
    digest.AddValue(pending_.flow[i].left_mps);
    digest.AddValue(pending_.flow[i].sigma_mps);
  }
  digest.AddValue(pending_.sweep_count);
  for (int i = 0; i < pending_.sweep_count && i < kMaxQueuedSweeps; ++i) digest.AddValue(pending_.sweeps[i]);
  digest.AddValue(pending_.has_pose);
  if (pending_.has_pose) {
    digest.AddValue(pending_.pose.x_m);
    digest.AddValue(pending_.pose.y_m);
    digest.AddValue(pending_.pose.heading_rad);
    digest.AddValue(pending_.pose.position_sigma_m);
    digest.AddValue(pending_.pose.heading_sigma_rad);
  }
  digest.AddValue(initialized_);
  digest.AddValue(last_step_ns_);
  digest.AddValue(last_range_fused_ns_);
  digest.AddValue(inconsistent_sweeps_);
  zero_rate_detector_.AddToDigest(digest);
  digest.AddValue(last_estimate_);
}

template class Estimator<float>;
template class Estimator<double>;

}  // namespace syrof::estimation
