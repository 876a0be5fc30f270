// The paper's two estimation tasks on the broker: a thin wrapper around the
// filter (ekf.h), the measurement models and the sweep policy (uwb_screen.h),
// like the Crazyflie's estimator_kalman around kalman_core. This is the
// target core_estimation_tasks; the math it wraps (core_estimation) includes
// no OS or broker header.
//
//   state task   notified by the IMU, flow and UWB topics. Takes every new
//                reading, converts it with its sensor model (MPU-9250 units,
//                the paper's flow formula) and queues it, with its noise, for
//                the Kalman task (the paper's "updates Z and sets R").
//   Kalman task  periodic (syrof/registry/tasks.h, 100 Hz). Predicts to now with the
//                mean of the IMU samples queued since its last step (constant
//                velocity if none came), folds in each queued flow reading
//                (two scalar updates) and each range (one scalar update per
//                anchor, gated), and publishes a StateEstimate.
// Readings are thus fused at their own rates, at the first Kalman step after
// they arrive (at most one period late). The paper's reset of R to "high
// uncertainty" after every step is not needed: a sensor that sent nothing is
// simply not fused.
//
// Until it has a pose, the Kalman task waits for a UWB sweep whose ranges
// agree on a position (least squares on the antenna plane, tolerating one
// outlier it can name), and takes the heading from the configuration;
// SetInitialPose() gives a pose instead. The same fix replaces the range
// updates whenever the position is very uncertain, and the estimate declares
// itself lost (and waits for a fix) when sweep after sweep fails the gate
// (EstimatorConfig has the thresholds, uwb_screen.h the rules as pure
// functions; this task only calls them and counts). Nothing is allocated; a step takes bounded
// time (at most kMaxQueuedFlow flow readings and kMaxQueuedSweeps sweeps).
#pragma once

#include <cstdint>

#include "syrof/base/state_digest.h"
#include "syrof/estimation/ekf.h"
#include "syrof/estimation/estimator_config.h"
#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/messages.h"
#include "syrof/estimation/topics.h"
#include "syrof/os/port.h"
#include "syrof/pubsub/broker.h"
#include "syrof/pubsub/topic.h"

namespace syrof::estimation {

/// Counters since start, for tests, logs and the lab's metrics. Ranges count
/// as fused or rejected when they went to the filter's updates (or the sweep
/// screen dropped them); sweeps that placed the robot count in `fixes`.
struct EstimatorCounters {
  uint32_t steps = 0;
  uint32_t imu_samples = 0;
  uint32_t flow_fused = 0;
  uint32_t flow_rejected = 0;  ///< gated or invalid
  uint32_t ranges_fused = 0;
  uint32_t ranges_rejected = 0;  ///< gated, screened out or invalid
  uint32_t relocalizations = 0;  ///< position variance inflated after inconsistent sweeps
  uint32_t fixes = 0;            ///< sweeps that placed the robot by least squares (the first one included)
  uint32_t zero_rate_fused = 0;  ///< steps that measured the gyro bias at rest (zero_rate_model.h)
  uint32_t readings_dropped = 0;  ///< invalid readings, or queues full because the Kalman task fell behind
};

enum class [[nodiscard]] EstimatorSetupError : uint8_t {
  kOk = 0,
  kAlreadyAttached,   ///< Attach() was called before
  kAddTaskFailed,     ///< the port refused a task (capacity, or already started)
  kSubscribeFailed,   ///< a sensor topic has no publisher yet, or the broker is full
  kAdvertiseFailed,   ///< the estimate topic already has a publisher, or the broker is full
};

/// The enumerator's name without the k; "?" for an unknown value.
const char* ToString(EstimatorSetupError error);

template <typename Scalar>
class Estimator {
 public:
  static constexpr int kMaxQueuedFlow = 4;
  static constexpr int kMaxQueuedSweeps = 2;

  explicit Estimator(const EstimatorConfig<Scalar>& config = {});
  Estimator(const Estimator&) = delete;
  Estimator& operator=(const Estimator&) = delete;

  /// Adds the state task and the Kalman task to `port` (priorities and
  /// period from syrof/registry/tasks.h), subscribes the state task to kImuTopic,
  /// kFlowTopic and kUwbTopic, and advertises kStateEstimateTopic. The
  /// sensor topics must already be advertised (the broker registers
  /// publishers first). Before port.Start().
  EstimatorSetupError Attach(os::Port& port, pubsub::Broker& broker);

  /// Gives the filter a pose (velocity zero, bias zero) at the next Kalman
  /// step, replacing whatever it had. Safe from any task.
  void SetInitialPose(const InitialPose<Scalar>& pose);

  /// The filter as the Kalman task left it. Read between steps (on SimPort,
  /// any time outside a step).
  const Ekf<Scalar>& filter() const { return filter_; }
  bool initialized() const { return initialized_; }
  const StateEstimate& last_estimate() const { return last_estimate_; }
  const EstimatorCounters& counters() const { return counters_; }
  const EstimatorConfig<Scalar>& config() const { return config_; }

  /// The filter, what waits to be fused and the last estimate into `digest`
  /// (base/state_digest.h); the counters stay out.
  void AddToDigest(base::StateDigest& digest) const;

 private:
  // What the state task hands to the Kalman task; guarded by the port's
  // critical section.
  struct Pending {
    ImuInput<Scalar> imu_sum{};
    uint32_t imu_count = 0;
    BodyVelocity<Scalar> flow[kMaxQueuedFlow] = {};
    int flow_count = 0;
    UwbReading sweeps[kMaxQueuedSweeps] = {};
    int sweep_count = 0;
    InitialPose<Scalar> pose{};
    bool has_pose = false;
    uint32_t dropped = 0;
  };

  class StateTask final : public os::Task {
   public:
    explicit StateTask(Estimator& owner) : owner_(owner) {}
    void Step(int64_t now_ns) override;

   private:
    Estimator& owner_;
  };

  class KalmanTask final : public os::Task {
   public:
    explicit KalmanTask(Estimator& owner) : owner_(owner) {}
    void Step(int64_t now_ns) override;

   private:
    Estimator& owner_;
  };

  void CollectReadings();
  void RunKalmanStep(int64_t now_ns);
  void FuseSweep(const UwbReading& sweep, int64_t now_ns);
  void PublishEstimate(int64_t now_ns, const ImuInput<Scalar>& imu, bool imu_missing);

  EstimatorConfig<Scalar> config_;
  Scalar flow_metres_per_pixel_;  // from config_.flow_geometry, once; 0 if the geometry is invalid
  Ekf<Scalar> filter_;
  StateTask state_task_;
  KalmanTask kalman_task_;
  os::Port* port_ = nullptr;
  pubsub::Subscriber<ImuReading, 4> imu_subscriber_;
  pubsub::Subscriber<FlowReading, 2> flow_subscriber_;
  pubsub::Subscriber<UwbReading, 2> uwb_subscriber_;
  pubsub::Publisher<StateEstimate> estimate_publisher_;
  Pending pending_;
  bool initialized_ = false;
  int64_t last_step_ns_ = 0;
  int64_t last_range_fused_ns_ = 0;
  int inconsistent_sweeps_ = 0;
  ZeroRateDetector<Scalar> zero_rate_detector_;
  EstimatorCounters counters_;
  StateEstimate last_estimate_{};
};

extern template class Estimator<float>;
extern template class Estimator<double>;

}  // namespace syrof::estimation
