#include "syrof/lab/sensors/trajectory.h"

#include <cmath>
#include <numbers>

#include "units.h"

namespace syrof::lab::sensors {
namespace {

double WrapAngle(double radians) { return std::remainder(radians, 2 * std::numbers::pi); }

}  // namespace

FigureEight::FigureEight(const Params& params) : params_(params) {}

double FigureEight::lap_s() const { return 4 * std::numbers::pi * params_.loop_radius_m / params_.speed_mps; }

TrueState FigureEight::At(int64_t time_ns) const {
  const double radius = params_.loop_radius_m;
  const double speed = params_.speed_mps;
  const double time_s = static_cast<double>(time_ns) / kNanosecondsPerSecond;
  // Angle travelled around the current loop; a lap is two loops of 2 pi.
  const double lap_angle = std::fmod(speed * time_s / radius, 4 * std::numbers::pi);
  const double centripetal = speed * speed / radius;
  TrueState state;
  if (lap_angle < 2 * std::numbers::pi) {
    // Right loop, clockwise around (cx + r, cy), starting at its west point.
    const double phi = lap_angle;
    const double centre_x = params_.centre_x_m + radius;
    state.x_m = centre_x - radius * std::cos(phi);
    state.y_m = params_.centre_y_m + radius * std::sin(phi);
    state.vx_mps = speed * std::sin(phi);
    state.vy_mps = speed * std::cos(phi);
    state.ax_mps2 = centripetal * std::cos(phi);
    state.ay_mps2 = -centripetal * std::sin(phi);
    state.heading_rad = WrapAngle(std::numbers::pi / 2 - phi);
    state.yaw_rate_radps = -speed / radius;
  } else {
    // Left loop, counter-clockwise around (cx - r, cy), starting at its east point.
    const double psi = lap_angle - 2 * std::numbers::pi;
    const double centre_x = params_.centre_x_m - radius;
    state.x_m = centre_x + radius * std::cos(psi);
    state.y_m = params_.centre_y_m + radius * std::sin(psi);
    state.vx_mps = -speed * std::sin(psi);
    state.vy_mps = speed * std::cos(psi);
    state.ax_mps2 = -centripetal * std::cos(psi);
    state.ay_mps2 = -centripetal * std::sin(psi);
    state.heading_rad = WrapAngle(std::numbers::pi / 2 + psi);
    state.yaw_rate_radps = speed / radius;
  }
  return state;
}

StraightLine::StraightLine(const Params& params) : params_(params) {}

TrueState StraightLine::At(int64_t time_ns) const {
  const double time_s = static_cast<double>(time_ns) / kNanosecondsPerSecond;
  const double vx = params_.speed_mps * std::cos(params_.heading_rad);
  const double vy = params_.speed_mps * std::sin(params_.heading_rad);
  TrueState state;
  state.x_m = params_.start_x_m + vx * time_s;
  state.y_m = params_.start_y_m + vy * time_s;
  state.vx_mps = vx;
  state.vy_mps = vy;
  state.heading_rad = WrapAngle(params_.heading_rad);
  return state;
}

StraightLine Stationary(double x_m, double y_m, double heading_rad) {
  return StraightLine(StraightLine::Params{x_m, y_m, heading_rad, 0.0});
}

}  // namespace syrof::lab::sensors
