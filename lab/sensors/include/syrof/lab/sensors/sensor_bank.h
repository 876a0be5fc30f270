// Simulated sensors for one robot: the MPU-9250, the optical-flow sensor and
// the DWM1000, turning the robot's true state into the readings the real
// drivers publish (core/estimation's messages.h), with documented noise, bias
// and rate models.
//
// A lab steps many robots in virtual time: each robot owns a SensorBank.
// Whenever the clock reaches bank.next_due_ns(), the lab passes the robot's
// true state at that instant to Sample(), which emits every reading due then
// to a ReadingSink (SensorPublishers puts them on the robot's broker).
//
// Determinism: every bank draws from its own generators, seeded from the
// bank's seed (each sensor from its own stream, so switching one sensor off
// does not change the others' noise). The same seed and the same calls give
// the same readings, byte for byte, on the same platform. Gaussian samples
// come from GaussianSource (gaussian.h), not from std::normal_distribution,
// whose algorithm differs between standard libraries.
#pragma once

#include <cstdint>

#include "syrof/estimation/arena.h"
#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/messages.h"
#include "syrof/registry/tasks.h"
#include "syrof/lab/sensors/gaussian.h"
#include "syrof/lab/sensors/trajectory.h"
#include "syrof/base/state_digest.h"

namespace syrof::lab::sensors {

/// The gravity the simulated accelerometer feels, m/s^2 (standard gravity;
/// the estimator's MPU-9250 model converts with the paper's 9.81).
inline constexpr double kStandardGravity = 9.80665;

/// MPU-9250 model. Each axis: reading = truth + bias + white noise, the bias
/// starting at a Gaussian draw and then a random walk (its increment over one
/// period T is walk * sqrt(T) * N(0, 1)). Accelerometer values leave in g
/// (divided by standard gravity), rates in deg/s. The defaults follow the
/// datasheet's noise densities (300 ug/sqrt(Hz), 0.01 dps/sqrt(Hz)) at a
/// 41 Hz bandwidth, and the biases left after a bench calibration.
struct ImuModel {
  int64_t period_ns = registry::kImuPeriodNs;  ///< 100 Hz
  int64_t offset_ns = 0;                                   ///< first sample at this time
  double accel_sigma_mps2 = 0.02;                          ///< white noise per sample, each axis
  double accel_bias_sigma_mps2 = 0.02;                     ///< initial bias, each axis
  double accel_bias_walk_mps2_per_sqrt_s = 2e-4;
  double gyro_sigma_radps = 0.0015;                        ///< white noise per sample, each axis
  double gyro_bias_sigma_radps = 0.005;                    ///< initial bias, each axis
  double gyro_bias_walk_radps_per_sqrt_s = 2e-5;
};

/// Optical-flow model: the body-frame displacement over the interval since
/// the previous reading (the true body velocity at the sample instant times
/// the interval), in pixels of the paper's geometry, plus white noise, and
/// rounded to whole pixels as the sensor counts them.
struct FlowModel {
  int64_t period_ns = registry::kFlowPeriodNs;  ///< 50 Hz
  int64_t offset_ns = 0;
  double sigma_px = 2.0;                                    ///< white noise per reading, each axis
  estimation::FlowGeometry<double> geometry{};              ///< must match the estimator's
};

/// DWM1000 model: one sweep over every anchor per period. Each range is the
/// true distance from the antenna (x, y, tag height) to the anchor plus white
/// noise; with outlier_probability it carries an extra non-line-of-sight
/// excess drawn uniformly from [outlier_min_m, outlier_max_m] (UWB outliers
/// are long, never short); with dropout_probability the exchange fails and
/// the range is missing from the sweep.
struct UwbModel {
  int64_t period_ns = registry::kUwbPeriodNs;  ///< 10 Hz
  int64_t offset_ns = 0;
  double sigma_m = 0.10;
  double outlier_probability = 0.02;
  double outlier_min_m = 0.5;
  double outlier_max_m = 2.0;
  double dropout_probability = 0.01;
};

/// Everything a bank needs; the arena gives the anchors and the antenna height.
struct SensorBankConfig {
  ImuModel imu{};
  FlowModel flow{};
  UwbModel uwb{};
  estimation::Arena<double> arena = estimation::DefaultArena<double>();
};

enum class SensorKind : uint8_t { kImu, kFlow, kUwb };

/// Receives a bank's readings (see SensorPublishers for the broker).
class ReadingSink {
 public:
  virtual void OnImu(const estimation::ImuReading& reading) = 0;
  virtual void OnFlow(const estimation::FlowReading& reading) = 0;
  virtual void OnUwb(const estimation::UwbReading& reading) = 0;

 protected:
  ~ReadingSink() = default;
};

/// The true biases of a bank's IMU at the last sample (for tests and metrics).
struct ImuBias {
  double accel_mps2[3] = {};
  double gyro_radps[3] = {};
};

class SensorBank {
 public:
  /// The configuration must be valid (periods > 0, offsets >= 0, sigmas >= 0,
  /// probabilities in [0, 1], outlier_min_m <= outlier_max_m); checked.
  SensorBank(const SensorBankConfig& config, uint64_t seed);

  /// The earliest time at which a reading is due.
  int64_t next_due_ns() const;

  /// Emits every reading due at or before now_ns, computed from `truth` (the
  /// true state at now_ns) and stamped now_ns, in the order IMU, flow, UWB.
  /// A sensor that fell more than a period behind emits one reading and skips
  /// to its next due time after now_ns (counted in missed()). A disabled
  /// sensor emits nothing but keeps its schedule (and its bias keeps walking).
  void Sample(int64_t now_ns, const TrueState& truth, ReadingSink& sink);

  /// Switches a sensor off (a failure, an occluded anchor set) or on again.
  void set_enabled(SensorKind kind, bool enabled);
  bool enabled(SensorKind kind) const;

  const ImuBias& imu_bias() const { return imu_bias_; }
  /// Due readings skipped because Sample() was called late.
  uint64_t missed() const { return missed_; }
  /// Ranges that carried an outlier excess, and ranges dropped, so far.
  uint64_t uwb_outliers() const { return uwb_outliers_; }
  uint64_t uwb_dropouts() const { return uwb_dropouts_; }

  /// The noise generators, the schedules and the biases into `digest`
  /// (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest) const {
    digest.AddValue(imu_noise_);
    digest.AddValue(flow_noise_);
    digest.AddValue(uwb_noise_);
    for (const Schedule* schedule : {&imu_, &flow_, &uwb_}) {  // field by field: Schedule has padding
      digest.AddValue(schedule->period_ns);
      digest.AddValue(schedule->next_due_ns);
      digest.AddValue(schedule->enabled);
    }
    digest.AddValue(imu_bias_);
    digest.AddValue(last_flow_ns_);
  }
  const SensorBankConfig& config() const { return config_; }

 private:
  using Gaussian = GaussianSource;

  struct Schedule {
    int64_t period_ns;
    int64_t next_due_ns;
    bool enabled = true;
  };

  bool Due(Schedule& schedule, int64_t now_ns);
  void EmitImu(int64_t now_ns, const TrueState& truth, ReadingSink& sink);
  void EmitFlow(int64_t now_ns, const TrueState& truth, ReadingSink& sink);
  void EmitUwb(int64_t now_ns, const TrueState& truth, ReadingSink& sink);

  SensorBankConfig config_;
  double flow_metres_per_pixel_;
  Gaussian imu_noise_;
  Gaussian flow_noise_;
  Gaussian uwb_noise_;
  Schedule imu_;
  Schedule flow_;
  Schedule uwb_;
  ImuBias imu_bias_;
  int64_t last_flow_ns_;
  uint32_t uwb_sweeps_ = 0;
  uint64_t missed_ = 0;
  uint64_t uwb_outliers_ = 0;
  uint64_t uwb_dropouts_ = 0;
};

}  // namespace syrof::lab::sensors
