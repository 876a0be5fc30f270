#include "syrof/motion/controller.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "syrof/app/command_check.h"

namespace syrof::motion {
namespace {

constexpr float kTwoPi = 6.28318530717958647692f;

// Below this a velocity vector has no usable direction (m/s).
constexpr float kMinDirectionSpeedMps = 1e-4f;

bool AllFinite(std::initializer_list<float> values) {
  for (const float value : values) {
    if (!std::isfinite(value)) {
      return false;
    }
  }
  return true;
}

float Clamp(float value, float limit) { return std::clamp(value, -limit, limit); }

float Sign(float value) { return value < 0.0f ? -1.0f : 1.0f; }

}  // namespace

float WrapAngle(float angle_rad) {
  if (!std::isfinite(angle_rad)) {
    return 0.0f;
  }
  return std::remainder(angle_rad, kTwoPi);
}

MotionController::MotionController(const ControllerConfig& config) : config_(config) {}

void MotionController::SetCommand(const syrof_car_command& command) {
  const bool was_stop = command_.kind == SYROF_COMMAND_STOP;
  if (app::CheckCommand(command).ok()) {
    command_ = command;
  } else {
    ++invalid_commands_;
    command_ = syrof_car_command{};
    command_.kind = SYROF_COMMAND_STOP;
  }
  arrived_ = command_.kind == SYROF_COMMAND_STOP;
  // A new command holds anew; a STOP after a STOP keeps holding where it was.
  if (!(was_stop && command_.kind == SYROF_COMMAND_STOP)) hold_.set = false;
}

bool MotionController::arrived() const {
  switch (command_.kind) {
    case SYROF_COMMAND_STOP:
      return true;
    case SYROF_COMMAND_VELOCITY:
      return false;
    default:
      return arrived_;
  }
}

DriveCommand MotionController::Update(const estimation::StateEstimate& estimate, int64_t now_ns) {
  DriveCommand drive;
  drive.timestamp_ns = now_ns;
  drive.kind = config_.kind;
  if (command_.kind == SYROF_COMMAND_STOP && !config_.hold_position) {
    return drive;
  }
  const bool usable = (estimate.status & estimation::kEstimateInitialized) != 0 &&
                      AllFinite({estimate.x_m, estimate.y_m, estimate.heading_rad});
  if (!usable) {
    ++blind_updates_;
    return drive;
  }
  if (command_.kind == SYROF_COMMAND_STOP) {  // holding: a drone hovers where it stopped
    const HoldPoint& hold = HoldHere(estimate);
    SteerTo(estimate, hold.x_m, hold.y_m, config_.limits.max_speed_mps, drive);
    return drive;
  }
  return config_.kind == DriveKind::kWheels ? UpdateWheels(estimate, drive) : UpdateOmni(estimate, drive);
}

bool MotionController::Latch(float error, float tolerance) {
  if (arrived_) {
    arrived_ = error <= config_.release_factor * tolerance;
  } else {
    arrived_ = error <= tolerance;
  }
  return arrived_;
}

float MotionController::ApproachSpeed(float distance_m, float cruise_mps) const {
  const MotionLimits& limits = config_.limits;
  const float braking_mps2 = config_.braking_fraction * limits.max_accel_mps2;
  const float braking_speed = BrakingSpeed(distance_m, braking_mps2, limits.response_lag_s);
  const float linear_speed = config_.position_gain_per_s * distance_m;
  return std::min({cruise_mps, limits.max_speed_mps, braking_speed, linear_speed});
}

const HoldPoint& MotionController::HoldHere(const estimation::StateEstimate& estimate) {
  if (!hold_.set) {
    hold_.x_m = estimate.x_m;
    hold_.y_m = estimate.y_m;
    hold_.set = true;
  }
  return hold_;
}

void MotionController::SteerTo(const estimation::StateEstimate& estimate, float x_m, float y_m, float cruise_mps,
                               DriveCommand& drive) const {
  const float dx = x_m - estimate.x_m;
  const float dy = y_m - estimate.y_m;
  const float distance_m = std::sqrt(dx * dx + dy * dy);
  if (!(distance_m > 0.0f)) return;
  const float speed = ApproachSpeed(distance_m, cruise_mps);
  drive.vx_mps = speed * dx / distance_m;
  drive.vy_mps = speed * dy / distance_m;
}

DriveCommand MotionController::UpdateOmni(const estimation::StateEstimate& estimate, DriveCommand drive) {
  const MotionLimits& limits = config_.limits;
  switch (command_.kind) {
    case SYROF_COMMAND_MOVE_TO: {
      const float dx = command_.x_m - estimate.x_m;
      const float dy = command_.y_m - estimate.y_m;
      const float distance_m = std::sqrt(dx * dx + dy * dy);
      if (Latch(distance_m, config_.position_tolerance_m)) {
        if (config_.hold_position) SteerTo(estimate, command_.x_m, command_.y_m, command_.speed_mps, drive);
        return drive;
      }
      const float speed = ApproachSpeed(distance_m, command_.speed_mps);
      drive.vx_mps = speed * dx / distance_m;
      drive.vy_mps = speed * dy / distance_m;
      return drive;
    }
    case SYROF_COMMAND_VELOCITY: {
      const float speed = std::sqrt(command_.vx_mps * command_.vx_mps + command_.vy_mps * command_.vy_mps);
      const float scale = speed > limits.max_speed_mps ? limits.max_speed_mps / speed : 1.0f;
      drive.vx_mps = command_.vx_mps * scale;
      drive.vy_mps = command_.vy_mps * scale;
      return drive;
    }
    case SYROF_COMMAND_TURN_TO: {
      const float error_rad = WrapAngle(command_.heading_rad - estimate.heading_rad);
      if (config_.hold_position) {
        const HoldPoint& hold = HoldHere(estimate);
        SteerTo(estimate, hold.x_m, hold.y_m, limits.max_speed_mps, drive);
      }
      if (Latch(std::fabs(error_rad), config_.heading_tolerance_rad)) {
        return drive;
      }
      drive.yaw_rate_radps = Clamp(config_.heading_gain_per_s * error_rad, limits.max_turn_rate_radps);
      return drive;
    }
    default:
      return drive;
  }
}

float MotionController::WheelsTurnRate(float error_rad, float gain_per_s) const {
  const MotionLimits& limits = config_.limits;
  const float wheel_rate_radps = 2.0f * limits.max_speed_mps / limits.wheel_base_m;
  const float angular_braking = config_.braking_fraction * 2.0f * limits.max_accel_mps2 / limits.wheel_base_m;
  const float magnitude = std::fabs(error_rad);
  const float rate = std::min({gain_per_s * magnitude, limits.max_turn_rate_radps, wheel_rate_radps,
                               std::sqrt(2.0f * angular_braking * magnitude)});
  return Sign(error_rad) * rate;
}

void MotionController::SetWheels(float speed_mps, float turn_rate_radps, DriveCommand& drive) const {
  const float max_speed = config_.limits.max_speed_mps;
  const float half_difference = Clamp(turn_rate_radps * 0.5f * config_.limits.wheel_base_m, max_speed);
  const float forward = Clamp(speed_mps, max_speed - std::fabs(half_difference));
  drive.left_mps = forward - half_difference;
  drive.right_mps = forward + half_difference;
}

DriveCommand MotionController::UpdateWheels(const estimation::StateEstimate& estimate, DriveCommand drive) {
  switch (command_.kind) {
    case SYROF_COMMAND_MOVE_TO: {
      const float dx = command_.x_m - estimate.x_m;
      const float dy = command_.y_m - estimate.y_m;
      const float distance_m = std::sqrt(dx * dx + dy * dy);
      if (Latch(distance_m, config_.position_tolerance_m)) {
        return drive;
      }
      const float error_rad = WrapAngle(std::atan2(dy, dx) - estimate.heading_rad);
      if (std::fabs(error_rad) > config_.turn_in_place_rad) {
        SetWheels(0.0f, WheelsTurnRate(error_rad, config_.heading_gain_per_s), drive);
        return drive;
      }
      const float speed = ApproachSpeed(distance_m, command_.speed_mps) * std::cos(error_rad);
      SetWheels(speed, WheelsTurnRate(error_rad, config_.steer_gain_per_s), drive);
      return drive;
    }
    case SYROF_COMMAND_VELOCITY: {
      const float speed = std::min(
          std::sqrt(command_.vx_mps * command_.vx_mps + command_.vy_mps * command_.vy_mps),
          config_.limits.max_speed_mps);
      if (speed < kMinDirectionSpeedMps) {
        return drive;
      }
      const float error_rad = WrapAngle(std::atan2(command_.vy_mps, command_.vx_mps) - estimate.heading_rad);
      if (std::fabs(error_rad) > config_.turn_in_place_rad) {
        SetWheels(0.0f, WheelsTurnRate(error_rad, config_.heading_gain_per_s), drive);
        return drive;
      }
      SetWheels(speed * std::cos(error_rad), WheelsTurnRate(error_rad, config_.steer_gain_per_s), drive);
      return drive;
    }
    case SYROF_COMMAND_TURN_TO: {
      const float error_rad = WrapAngle(command_.heading_rad - estimate.heading_rad);
      if (Latch(std::fabs(error_rad), config_.heading_tolerance_rad)) {
        return drive;
      }
      SetWheels(0.0f, WheelsTurnRate(error_rad, config_.heading_gain_per_s), drive);
      return drive;
    }
    default:
      return drive;
  }
}

}  // namespace syrof::motion
