// The motion controller: turns the app's current command (syrof_car_command)
// and the robot's OWN state estimate into a DriveCommand for the actuators.
// The robot runtime calls Update() at the motion task's rate (100 Hz); it
// never sees ground truth, so what it does in the lab it does on a robot.
//
// Portable: no allocation, no exceptions, no I/O, float math only, constant
// time per call. One controller per robot; plain state, copyable.
//
// Control laws (d = distance to the target, e = heading error wrapped to
// [-pi, pi], a = braking_fraction * max_accel):
//
// With a response lag (limits.response_lag_s > 0: a drone, whose velocity
// follows the setpoint through its tilt) every braking curve sqrt(2 a d)
// below becomes BrakingSpeed(d, a, lag), the speed that still stops within
// d when braking starts one lag late.
//
// Omni (DriveKind::kOmni; also drones), velocity in the arena frame:
//   MOVE_TO   v = min(speed_mps, max_speed, sqrt(2 a d), position_gain * d)
//             along the unit vector to the target, yaw rate 0. The square
//             root is the braking curve: a body that brakes at a reaches the
//             target with zero speed, so it does not overshoot; the linear
//             term makes the last centimetres smooth (no infinite slope of
//             the square root at d = 0). Within position_tolerance the
//             controller holds (velocity 0) and reports arrived().
//   VELOCITY  (vx, vy) with its magnitude clamped to max_speed; yaw rate 0.
//   TURN_TO   yaw rate = clamp(heading_gain * e, +-max_turn_rate); velocity
//             0. Within heading_tolerance: yaw rate 0, arrived().
//   STOP      everything 0; always arrived().
//
// Rover (DriveKind::kWheels), differential drive with wheel base b:
//   omega and v are mapped to wheels as left = v - omega b/2,
//   right = v + omega b/2. The turn rate is capped at the smaller of
//   max_turn_rate and 2 max_speed / b, and by its own braking curve
//   sqrt(2 a_yaw |e|) with a_yaw = braking_fraction * 2 max_accel / b (the
//   angular deceleration the wheels can give), so turns stop on target.
//   When the wheels would exceed max_speed, the forward speed gives way
//   first, so steering is never lost.
//   MOVE_TO   e = bearing of the target relative to the heading. If
//             |e| > turn_in_place_rad the rover turns in place toward it;
//             otherwise it drives forward at
//             v = min(speed_mps, max_speed, sqrt(2 a d), position_gain * d) * cos(e)
//             while steering with omega = steer_gain * e. Near the target
//             this is the classic polar law (bearing error decays when
//             steer_gain > position_gain). Hold and arrived() within
//             position_tolerance.
//   VELOCITY  the vector's direction is the desired heading and its
//             magnitude (clamped to max_speed) the speed: turns in place
//             when the heading error exceeds turn_in_place_rad, else drives
//             at speed * cos(e) while steering. A zero vector is a stop.
//   TURN_TO   turns in place with the capped, braked law above.
//   STOP      both wheels 0.
//
// Holding (hold_position, drones): a body that drifts when its setpoint is
// zero is held where it should be. STOP and TURN_TO hold the position
// estimated at their first usable Update (kept across repeated STOPs), and
// an arrived MOVE_TO keeps steering to its target; each with the MOVE_TO law
// at the robot's top speed, so a drift of a few centimetres is corrected at
// a few centimetres a second. arrived() is unchanged by holding.
//
// Arrival latches: once within tolerance the controller holds until the
// error grows past release_factor * tolerance (pushed away by a neighbour,
// or estimate noise), so it does not twitch around the target.
//
// Without an initialized estimate (kEstimateInitialized clear, or any
// non-finite field used) the controller cannot tell where it is: it
// commands zero and counts a blind step.
#pragma once

#include <cmath>
#include <cstdint>

#include "syrof/app.h"
#include "syrof/estimation/messages.h"
#include "syrof/motion/drive.h"

namespace syrof::motion {

/// The kinematic limits of one robot kind. SI units; all > 0.
struct MotionLimits {
  float max_speed_mps = 0.5f;        ///< omni: |v|; rover: each wheel's ground speed
  float max_accel_mps2 = 1.0f;       ///< omni: |dv/dt|; rover: each wheel's
  float max_turn_rate_radps = 3.0f;  ///< yaw rate cap
  float wheel_base_m = 0.16f;        ///< rover only: distance between the wheels
  float body_radius_m = 0.1f;        ///< the body's disc (informational; apps keep clear)
  /// How long the velocity takes to follow a setpoint before braking takes
  /// hold (a drone's tilt time constant); 0: at once (omni, rover).
  float response_lag_s = 0.0f;
};

/// The largest speed from which a body that brakes at `braking_mps2` after
/// a response lag of `lag_s` stops within `distance_m` (>= 0): sqrt(2 a d)
/// without a lag (bit for bit), else the positive root of
/// v lag + v^2 / 2a = d, written 2d / (lag + sqrt(lag^2 + 2d / a)) so it
/// loses no digits for small d. Portable (float, sqrt only).
inline float BrakingSpeed(float distance_m, float braking_mps2, float lag_s) {
  if (lag_s <= 0.0f) return std::sqrt(2.0f * braking_mps2 * distance_m);
  return 2.0f * distance_m / (lag_s + std::sqrt(lag_s * lag_s + 2.0f * distance_m / braking_mps2));
}

/// Everything a controller needs. Gains are per second (1/s).
struct ControllerConfig {
  DriveKind kind = DriveKind::kOmni;
  MotionLimits limits{};
  float position_tolerance_m = 0.02f;  ///< MOVE_TO: arrived within this distance
  float heading_tolerance_rad = 0.05f; ///< TURN_TO: arrived within this heading error
  float release_factor = 2.0f;         ///< a held target is resumed beyond release_factor * tolerance
  float braking_fraction = 0.8f;       ///< share of max_accel the braking curves plan with (margin for lag)
  float position_gain_per_s = 4.0f;    ///< speed = gain * distance near the target
  float heading_gain_per_s = 4.0f;     ///< yaw rate = gain * heading error
  float steer_gain_per_s = 6.0f;       ///< rover: yaw rate = gain * bearing error while driving (> position gain)
  float turn_in_place_rad = 0.6f;      ///< rover: larger bearing errors turn in place first
  /// Omni drive only: hold the position actively instead of commanding zero
  /// (a drone, which drifts when it hovers; see the file comment).
  bool hold_position = false;
};

/// Where a holding controller keeps the robot (ControllerConfig::hold_position).
struct HoldPoint {
  float x_m = 0;
  float y_m = 0;
  bool set = false;  ///< taken from the estimate at the first usable Update of a STOP or TURN_TO
};

/// One robot's motion controller.
class MotionController {
 public:
  /// `config` must hold positive limits; a controller starts with STOP.
  explicit MotionController(const ControllerConfig& config);

  /// Replaces the current command (called when the app's newRound returns, and
  /// with STOP when the maneuver ends). Validated by app::CheckCommand: a
  /// command it refuses becomes STOP and counts in invalid_commands(). (The
  /// runtime checks and reports each command before it gets here.)
  void SetCommand(const syrof_car_command& command);

  /// The actuator setpoint for now, from the robot's own estimate. Stamped
  /// with `now_ns` and the config's DriveKind; the other kind's fields are 0.
  DriveCommand Update(const estimation::StateEstimate& estimate, int64_t now_ns);

  /// MOVE_TO or TURN_TO: within tolerance at the last Update (latched, see
  /// the file comment). STOP: always. VELOCITY: never.
  bool arrived() const;

  /// The command being carried out (after validation).
  const syrof_car_command& command() const { return command_; }
  const ControllerConfig& config() const { return config_; }
  /// Commands replaced by STOP since construction.
  uint32_t invalid_commands() const { return invalid_commands_; }
  /// Updates that commanded zero because the estimate was unusable.
  uint32_t blind_updates() const { return blind_updates_; }
  /// The point a holding controller keeps (unset without hold_position).
  const HoldPoint& hold() const { return hold_; }

 private:
  DriveCommand UpdateOmni(const estimation::StateEstimate& estimate, DriveCommand drive);
  DriveCommand UpdateWheels(const estimation::StateEstimate& estimate, DriveCommand drive);
  // Speed toward a target `distance_m` away, from the cruise speed and the braking curve.
  float ApproachSpeed(float distance_m, float cruise_mps) const;
  // Rover turn rate for a heading error, capped and braked.
  float WheelsTurnRate(float error_rad, float gain_per_s) const;
  // Rover wheel speeds for forward speed v and turn rate omega, within max_speed.
  void SetWheels(float speed_mps, float turn_rate_radps, DriveCommand& drive) const;
  // Updates the arrival latch for an error against its tolerance.
  bool Latch(float error, float tolerance);
  // Omni velocity toward (x, y) by the MOVE_TO law at `cruise_mps`, no latch.
  void SteerTo(const estimation::StateEstimate& estimate, float x_m, float y_m, float cruise_mps,
               DriveCommand& drive) const;
  // The hold point, taken from `estimate` if not yet set.
  const HoldPoint& HoldHere(const estimation::StateEstimate& estimate);

  ControllerConfig config_;
  syrof_car_command command_{};
  bool arrived_ = true;
  HoldPoint hold_{};
  uint32_t invalid_commands_ = 0;
  uint32_t blind_updates_ = 0;
};

/// The heading `angle_rad` wrapped to [-pi, pi].
float WrapAngle(float angle_rad);

}  // namespace syrof::motion
