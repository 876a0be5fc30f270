// The estimator's topic payloads: what the sensor drivers publish (the
// MPU-9250, the flow sensor, the DWM1000) and what the Kalman task publishes.
// Each is defined once, here, with its units; the firmware drivers and the
// lab's simulated sensors publish exactly these, so the estimator cannot tell
// which runtime it runs in. Topic ids are in topics.h.
//
// The structs have no padding (checked below), so a reading's bytes are its
// fields' bytes: identical runs give identical bytes.
#pragma once

#include <cstdint>

namespace syrof::estimation {

/// Anchors a UWB reading can carry (and an arena can hold).
inline constexpr int kMaxAnchors = 8;

/// One MPU-9250 sample in the units the paper's driver reads: acceleration
/// in g, angular rate in degrees per second. Body frame: x forward, y left,
/// z up.
struct ImuReading {
  int64_t timestamp_ns;  ///< port clock when the sample was taken
  float accel_g[3];      ///< specific force along body x, y, z, in g (about +1 on z at rest on the floor)
  float gyro_dps[3];     ///< angular rate about body x, y, z, deg/s, counter-clockwise positive
};

/// One optical-flow reading: the image motion accumulated since the previous
/// reading. The driver maps the sensor's axes (and signs) to the body axes,
/// so that moving forward gives a positive delta_x_px.
struct FlowReading {
  int64_t timestamp_ns;  ///< port clock at the end of the interval
  uint32_t interval_ns;  ///< length of the interval the deltas cover, > 0
  int16_t delta_x_px;    ///< image motion along body x over the interval, pixels
  int16_t delta_y_px;    ///< image motion along body y over the interval, pixels
};

/// One DWM1000 ranging sweep: two-way-ranging distances to the arena's
/// anchors, in the arena's anchor order.
struct UwbReading {
  int64_t timestamp_ns;         ///< port clock at the end of the sweep
  float range_m[kMaxAnchors];   ///< distance from the robot's antenna to anchor i, metres
  uint32_t valid_mask;          ///< bit i set: range_m[i] holds a fresh range (failed exchanges leave it clear)
  uint32_t sweep;               ///< the driver's sweep counter (wraps)
};

/// Status bits of a StateEstimate.
enum EstimateStatus : uint32_t {
  kEstimateInitialized = 1u << 0,  ///< the filter has a state (from the first UWB sweep or an explicit pose)
  kEstimateImuMissing = 1u << 1,   ///< no IMU sample in this step: predicted at constant velocity
  kEstimateUwbStale = 1u << 2,     ///< no range fused for more than EstimatorConfig::uwb_stale_ns
};

/// The Kalman task's output, once per step (100 Hz). Arena frame.
struct StateEstimate {
  int64_t timestamp_ns;     ///< port clock of the step
  float x_m;                ///< position, m
  float y_m;
  float vx_mps;             ///< velocity, m/s
  float vy_mps;
  float heading_rad;        ///< CCW from +x, in [-pi, pi]
  float yaw_rate_radps;     ///< gyro rate minus the estimated bias, rad/s
  float gyro_bias_radps;    ///< estimated gyro bias, rad/s
  float sigma_x_m;          ///< standard deviations from the covariance
  float sigma_y_m;
  float sigma_heading_rad;
  uint32_t status;          ///< EstimateStatus bits
  uint32_t ranges_fused;    ///< counters since start (wrap)
  uint32_t ranges_rejected;
  uint32_t flow_rejected;
};

static_assert(sizeof(ImuReading) == 8 + 6 * 4, "ImuReading has no padding");
static_assert(sizeof(FlowReading) == 8 + 4 + 2 * 2, "FlowReading has no padding");
static_assert(sizeof(UwbReading) == 8 + kMaxAnchors * 4 + 2 * 4, "UwbReading has no padding");
static_assert(sizeof(StateEstimate) == 8 + 10 * 4 + 4 * 4, "StateEstimate has no padding");

}  // namespace syrof::estimation
