// Ground truth for simulated sensors: where a robot is, how it moves and
// turns, at any instant of virtual time.
//
// The lab's own bodies will produce TrueState from their dynamics; these
// closed-form trajectories serve the estimator's tests and benchmarks, and
// scenarios that script a robot's path.
#pragma once

#include <cstdint>

namespace syrof::lab::sensors {

/// One robot's true state at one instant: arena frame, SI units, heading CCW
/// from +x in [-pi, pi]. The robot's antenna and flow sensor sit on its
/// rotation axis.
struct TrueState {
  double x_m = 0;
  double y_m = 0;
  double vx_mps = 0;
  double vy_mps = 0;
  double ax_mps2 = 0;  ///< acceleration, arena frame
  double ay_mps2 = 0;
  double heading_rad = 0;
  double yaw_rate_radps = 0;
};

/// A path in time. Implementations are immutable and safe to share between
/// robots and threads.
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  /// The state at `time_ns` (virtual time since the run started, >= 0).
  virtual TrueState At(int64_t time_ns) const = 0;
};

/// A figure eight at constant speed: two circles of radius loop_radius_m
/// that touch at the centre, the right one driven clockwise, the left one
/// counter-clockwise, the robot facing along its path. It starts at the
/// centre heading +y (into the right loop). Position and velocity are smooth;
/// acceleration and yaw rate switch sign at the centre. Spans
/// centre_x +- 2 radius by centre_y +- radius; one lap takes
/// 4 pi radius / speed.
class FigureEight final : public Trajectory {
 public:
  struct Params {
    double centre_x_m = 2.0;
    double centre_y_m = 2.0;
    double loop_radius_m = 0.8;
    double speed_mps = 0.5;
  };

  explicit FigureEight(const Params& params);
  TrueState At(int64_t time_ns) const override;
  /// Seconds per lap.
  double lap_s() const;
  const Params& params() const { return params_; }

 private:
  Params params_;
};

/// Constant velocity along a heading from a start point; speed 0 is a robot
/// standing still (see Stationary()).
class StraightLine final : public Trajectory {
 public:
  struct Params {
    double start_x_m = 0;
    double start_y_m = 0;
    double heading_rad = 0;
    double speed_mps = 0;
  };

  explicit StraightLine(const Params& params);
  TrueState At(int64_t time_ns) const override;
  const Params& params() const { return params_; }

 private:
  Params params_;
};

/// A robot that stands at (x, y) facing heading.
StraightLine Stationary(double x_m, double y_m, double heading_rad);

}  // namespace syrof::lab::sensors
