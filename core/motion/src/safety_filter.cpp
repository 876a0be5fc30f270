#include "syrof/motion/safety_filter.h"

#include <algorithm>
#include <cmath>

namespace syrof::motion {
namespace {

// A command changed by less than this (m/s) counts as unchanged: rounding.
constexpr float kLimitedThresholdMps = 1e-3f;
// A final velocity may break a constraint by this much (m/s) before the
// filter falls back to stopping: float rounding of the projections.
constexpr float kFeasibilityToleranceMps = 1e-4f;
// Below this distance (m) a centre gives no direction: the robot stops.
constexpr float kMinDistanceM = 1e-4f;
// Directions with |h . n| below this do not constrain a rover's forward speed.
constexpr float kParallelEpsilon = 1e-6f;
constexpr float kPiF = 3.14159265f;
// Below this speed (m/s) a command gives no direction to turn.
constexpr float kMinSpeedMps = 1e-6f;

float Dot(float ax, float ay, float bx, float by) { return ax * bx + ay * by; }

}  // namespace

namespace {

// Half the margin, or `sigmas` of the estimate's larger position sigma.
float ErrorAllowanceM(const SafetyConfig& config, float sigmas, const estimation::StateEstimate& estimate) {
  // A sigma that is not a number says nothing good: the largest doubt.
  const float position_sigma_m = std::max(estimate.sigma_x_m, estimate.sigma_y_m);
  const float own_sigma_m = std::isfinite(position_sigma_m)
                                ? std::clamp(position_sigma_m, 0.0f, config.max_own_sigma_m)
                                : config.max_own_sigma_m;
  return std::max(0.5f * config.margin_m, sigmas * own_sigma_m);
}

}  // namespace

float OwnErrorAllowanceM(const SafetyConfig& config, const estimation::StateEstimate& estimate) {
  return ErrorAllowanceM(config, config.own_sigmas, estimate);
}

// A braking distance in millimetres: v^2 / 2a, v in mm/s, a in mm/s^2.
uint16_t SafetyReports::BrakingMillimetres(int16_t vx_mm_s, int16_t vy_mm_s, float braking_mps2, float lag_s) {
  const float vx = static_cast<float>(vx_mm_s);
  const float vy = static_cast<float>(vy_mm_s);
  const float braking_mm_s2 = std::max(braking_mps2, 1e-3f) * 1000.0f;
  float distance_mm = (vx * vx + vy * vy) / (2.0f * braking_mm_s2);
  // The sender may go on at its frozen speed for one lag before braking.
  if (lag_s > 0.0f) distance_mm += lag_s * std::sqrt(vx * vx + vy * vy);
  const float allowance = std::ceil(distance_mm);
  return static_cast<uint16_t>(std::min(allowance, 65535.0f));
}

bool SafetyFilter::NeedsReports(const DriveCommand& desired) const {
  if (!config_.enabled) return false;
  if (kind_ == DriveKind::kWheels) return desired.left_mps + desired.right_mps != 0.0f;
  return desired.vx_mps != 0.0f || desired.vy_mps != 0.0f;
}

void SafetyReports::ReportMetres(uint16_t id, int64_t time_ns, float x_m, float y_m, bool parked, float vx_mps,
                                 float vy_mps, float braking_mps2, float lag_s) {
  const auto millimetres = [](float metres) {
    if (!std::isfinite(metres)) return int16_t{0};
    return static_cast<int16_t>(std::lround(std::clamp(metres * 1000.0f, -32768.0f, 32767.0f)));
  };
  Report(id, time_ns, millimetres(x_m), millimetres(y_m), parked, millimetres(vx_mps), millimetres(vy_mps),
         braking_mps2, lag_s);
  if (!std::isfinite(x_m) || !std::isfinite(y_m) || id >= wire::kMaxSwarmSize) {
    if (id < wire::kMaxSwarmSize) entries_[id].valid = false;
  }
}

uint16_t SafetyReports::NextSilent(uint16_t& cursor, uint16_t self, size_t count, int64_t before_ns,
                                   size_t limit) const {
  const size_t n = std::min(count, entries_.size());
  if (n == 0) return kNoSilentReport;
  size_t id = cursor % n;
  for (size_t step = 0; step < std::min(limit, n); ++step) {
    id = (id + 1) % n;
    const SafetyReport& entry = entries_[id];
    if (id != self && entry.valid && entry.time_ns < before_ns) {
      cursor = static_cast<uint16_t>(id);
      return cursor;
    }
  }
  cursor = static_cast<uint16_t>(id);
  return kNoSilentReport;
}

void SafetyReports::CopyFrom(const SafetyReports& other, size_t count) {
  const size_t n = std::min(count, entries_.size());
  std::copy(other.entries_.begin(), other.entries_.begin() + static_cast<std::ptrdiff_t>(n), entries_.begin());
  gap_start_ns_ = other.gap_start_ns_;
  gap_end_ns_ = other.gap_end_ns_;
}

SafetyFilter::SafetyFilter(const SafetyConfig& config, const ControllerConfig& controller, uint16_t swarm_size)
    : config_(config),
      own_radius_m_(controller.limits.body_radius_m),
      own_max_speed_mps_(controller.limits.max_speed_mps),
      own_braking_mps2_(controller.braking_fraction * controller.limits.max_accel_mps2),
      own_lag_s_(std::max(controller.limits.response_lag_s, 0.0f)),
      kind_(controller.kind),
      swarm_size_(std::min<uint16_t>(swarm_size, wire::kMaxSwarmSize)) {}

float SafetyFilter::ApproachBound(float gap_m, float braking_mps2, float lag_s) const {
  if (gap_m <= 0.0f) return 0.0f;
  return std::min(config_.gain_per_s * gap_m, BrakingSpeed(gap_m, braking_mps2, lag_s));
}

void SafetyFilter::Keep(const Constraint& constraint, float slack) {
  if (count_ < constraints_.size()) {
    constraints_[count_] = constraint;
    slack_[count_] = slack;
    ++count_;
    return;
  }
  // Full: replace the loosest one if this one is tighter.
  size_t loosest = 0;
  for (size_t i = 1; i < count_; ++i) {
    if (slack_[i] > slack_[loosest]) loosest = i;
  }
  if (slack < slack_[loosest]) {
    constraints_[loosest] = constraint;
    slack_[loosest] = slack;
  }
}

// A robot's disc before the other's growth: both bodies, the margin, and
// what this robot's allowance for its own error exceeds half the margin by.
float SafetyFilter::DiscBaseM(float own_allowance_m) const {
  const float own_excess_m = own_allowance_m - 0.5f * config_.margin_m;
  return own_radius_m_ + config_.others_radius_m + config_.margin_m + own_excess_m;
}

// A robot's disc of `radius_m` (the other's growth, constraint.sigma_m, in
// it) at constraint.distance_m along the constraint's direction: outside,
// the approach bound; inside, the cone away from it; on top of its centre,
// a stop. Inline: Collect builds every robot constraint with it (the host's
// -O3 build inlines it; -Os for the Teensy keeps one copy).
inline void SafetyFilter::RobotConstraint(Constraint& constraint, float radius_m) const {
  const float distance_m = constraint.distance_m;
  if (distance_m < kMinDistanceM) {
    constraint.cone = true;
    constraint.bound = 2.0f;  // above 1: only u = 0
    return;
  }
  const float gap_m = distance_m - radius_m;
  if (gap_m > 0.0f) {
    // Against another robot this one brakes with half its deceleration
    // and its half of the gap holds its whole lag (Collect).
    constraint.bound = ApproachBound(gap_m, 0.5f * own_braking_mps2_, 2.0f * own_lag_s_);
    constraint.cone = false;
  } else {
    // sigma >= d: this robot stands where the other may be; every
    // direction may lead towards it (a bound above 1 admits only u = 0).
    constraint.bound = constraint.sigma_m / distance_m;
    constraint.cone = true;
  }
}

void SafetyFilter::Collect(float x, float y, float own_allowance_m, const SafetyReports& reports, int64_t now_ns) {
  count_ = 0;
  // Against another robot this one brakes with half its deceleration: the
  // other may be closing in too, and brakes with half of its own, so the two
  // stop within the gap between them (docs/safety.md, "Proof sketch").
  const float shared_braking_mps2 = 0.5f * own_braking_mps2_;
  // A linear constraint whose bound reaches the speed limit cannot bind.
  // Its half of the gap holds its whole lag: in terms of the shared
  // braking, v (2 lag) + v^2 / 2 (a / 2) <= h.
  const float shared_lag_s = 2.0f * own_lag_s_;
  float braking_reach_m = own_max_speed_mps_ * own_max_speed_mps_ / (2.0f * shared_braking_mps2);
  if (shared_lag_s > 0.0f) braking_reach_m += shared_lag_s * own_max_speed_mps_;
  const float reach_m = std::max(own_max_speed_mps_ / config_.gain_per_s, braking_reach_m);
  reach_m_ = reach_m;
  // The margin covers each robot's error up to half of it; this robot's own
  // doubt beyond that grows every disc.
  const float base_m = DiscBaseM(own_allowance_m);
  // A first, integer-only test in millimetres against the largest disc any
  // report can have (a full horizon's growth): on a soft-float core most
  // robots are rejected without one float operation.
  const float largest_m = base_m + config_.others_max_speed_mps * config_.horizon_s + reach_m;
  const auto largest_mm = static_cast<int32_t>(largest_m * 1000.0f) + 1;
  // Clamped: an estimate far outside any arena must not overflow the cast.
  const auto own_x_mm = static_cast<int32_t>(std::clamp(x * 1000.0f, -1e6f, 1e6f));
  const auto own_y_mm = static_cast<int32_t>(std::clamp(y * 1000.0f, -1e6f, 1e6f));
  // Reports fresh when this robot stopped listening may belong to robots
  // that moved all through its gap: their discs grow for the gap too.
  const auto horizon_ns = static_cast<int64_t>(config_.horizon_s * 1e9f);
  const int64_t gap_ns = reports.gap_end_ns() - reports.gap_start_ns();
  const float gap_s = static_cast<float>(gap_ns) * 1e-9f;
  const auto gap_mm = static_cast<int32_t>(std::min(config_.others_max_speed_mps * gap_s * 1000.0f, 1e6f));
  for (uint16_t id = 0; id < swarm_size_; ++id) {
    const SafetyReport& report = reports[id];
    if (!report.valid || id == config_.self_id) continue;
    const bool across_gap = gap_ns > 0 && report.time_ns < reports.gap_end_ns() &&
                            report.time_ns >= reports.gap_start_ns() - horizon_ns;
    const int32_t reach_mm = largest_mm + report.allowance_mm + (across_gap ? gap_mm : 0);
    const int32_t dx_mm = int32_t{report.x_mm} - own_x_mm;
    const int32_t dy_mm = int32_t{report.y_mm} - own_y_mm;
    if (dx_mm > reach_mm || dx_mm < -reach_mm || dy_mm > reach_mm || dy_mm < -reach_mm) continue;
    const float cap_s = config_.horizon_s + (across_gap ? gap_s : 0.0f);
    const float age_s = std::clamp(static_cast<float>(now_ns - report.time_ns) * 1e-9f, 0.0f, cap_s);
    const float sigma_m = config_.others_max_speed_mps * age_s + 0.001f * static_cast<float>(report.allowance_mm);
    const float radius_m = base_m + sigma_m;
    const float dx = 0.001f * static_cast<float>(report.x_mm) - x;
    const float dy = 0.001f * static_cast<float>(report.y_mm) - y;
    const float squared = dx * dx + dy * dy;
    const float far_m = radius_m + reach_m;
    if (squared > far_m * far_m) continue;
    const float distance_m = std::sqrt(squared);
    Constraint constraint{};
    constraint.other = id;
    constraint.nx = 1.0f;  // on top of the centre no direction leads away (RobotConstraint stops)
    if (distance_m >= kMinDistanceM) {
      constraint.nx = dx / distance_m;
      constraint.ny = dy / distance_m;
    }
    constraint.squared_m2 = squared;
    constraint.distance_m = distance_m;
    constraint.sigma_m = sigma_m;
    RobotConstraint(constraint, radius_m);
    Keep(constraint, distance_m < kMinDistanceM ? -radius_m : distance_m - radius_m);
  }
  if (config_.arena_width_m > 0 && config_.arena_height_m > 0) {
    const float inset_m = own_radius_m_ + config_.margin_m;
    const float gaps[4] = {x - inset_m, config_.arena_width_m - x - inset_m, y - inset_m,
                           config_.arena_height_m - y - inset_m};
    const float normals[4][2] = {{-1.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, -1.0f}, {0.0f, 1.0f}};
    for (int wall = 0; wall < 4; ++wall) {
      if (gaps[wall] > reach_m) continue;
      Constraint constraint{};
      constraint.nx = normals[wall][0];
      constraint.ny = normals[wall][1];
      constraint.bound = ApproachBound(gaps[wall], own_braking_mps2_, own_lag_s_);
      constraint.cone = false;
      constraint.other = kWallObstacle;
      Keep(constraint, gaps[wall]);
    }
  }
}

// The largest s in [0, 1] such that s u keeps every constraint when the
// body moves along u turned by any angle up to doubt_rad (< pi/2). With a
// the angle between u and n, a linear constraint's worst turn brings u
// closest to n: |u| cos(max(0, a - doubt)), which is |u| when a <= doubt and
// |u| (cos a cos doubt + sin a sin doubt) otherwise. A cone (inside a disc,
// u . -n >= bound |u|) admits u only if every turn of it stays inside: the
// cosine of the angle between u and -n at least cos(acos(bound) - doubt) =
// bound cos doubt + sqrt(1 - bound^2) sin doubt; otherwise only a stop does.
// Square roots and one sine and cosine of the doubt (computed only when the
// doubt is above zero): fine on a soft-float core.
float SafetyFilter::HeadingRobustScale(float ux, float uy, float doubt_rad) const {
  const float speed = std::sqrt(ux * ux + uy * uy);
  if (speed < kMinSpeedMps || doubt_rad <= 0.0f) return 1.0f;
  const float dx = ux / speed;
  const float dy = uy / speed;
  const float cos_doubt = std::cos(doubt_rad);
  const float sin_doubt = std::sin(doubt_rad);
  float scale = 1.0f;
  for (size_t i = 0; i < count_; ++i) {
    const Constraint& c = constraints_[i];
    const float cos_a = Dot(dx, dy, c.nx, c.ny);
    const float sin_a = std::fabs(dx * c.ny - dy * c.nx);
    if (c.cone) {
      if (c.bound >= 1.0f) return 0.0f;
      const float sin_phi = std::sqrt(std::max(0.0f, 1.0f - c.bound * c.bound));
      // acos(bound) - doubt < 0: no direction is inside every turn.
      if (sin_phi < sin_doubt && c.bound >= 0.0f) return 0.0f;
      if (-cos_a < c.bound * cos_doubt + sin_phi * sin_doubt) return 0.0f;
      continue;
    }
    const float worst_cos = cos_a >= cos_doubt ? 1.0f : cos_a * cos_doubt + sin_a * sin_doubt;
    const float worst_along = speed * worst_cos;
    if (worst_along <= c.bound) continue;
    if (c.bound <= 0.0f) return 0.0f;
    scale = std::min(scale, c.bound / worst_along);
  }
  return scale;
}

void SafetyFilter::LimitOmni(float& vx, float& vy) const {
  float ux = vx;
  float uy = vy;
  // A pass that changes nothing leaves the next one nothing to change.
  bool changed = true;
  for (int pass = 0; pass < kSafetyPasses && changed; ++pass) {
    changed = false;
    for (size_t i = 0; i < count_; ++i) {
      const Constraint& c = constraints_[i];
      const float along = Dot(ux, uy, c.nx, c.ny);
      if (!c.cone) {
        const float excess = along - c.bound;
        if (excess > 0.0f) {
          ux -= excess * c.nx;
          uy -= excess * c.ny;
          changed = true;
        }
        continue;
      }
      // The cone of directions at least phi away from every point of the
      // other's disc: axis -n, u . (-n) >= sin(phi) |u|.
      const float speed = std::sqrt(ux * ux + uy * uy);
      if (-along >= c.bound * speed) continue;
      changed = true;
      // Project onto the cone's edge on u's side: w = s (-n) + sqrt(1 - s^2) t.
      float tx = ux - along * c.nx;
      float ty = uy - along * c.ny;
      const float tangent = std::sqrt(tx * tx + ty * ty);
      if (tangent < kMinDistanceM) {
        ux = 0.0f;
        uy = 0.0f;
        continue;
      }
      tx /= tangent;
      ty /= tangent;
      if (c.bound >= 1.0f) {
        ux = 0.0f;
        uy = 0.0f;
        continue;
      }
      const float s = c.bound;
      const float c_side = std::sqrt(std::max(0.0f, 1.0f - s * s));
      const float wx = -s * c.nx + c_side * tx;
      const float wy = -s * c.ny + c_side * ty;
      const float length = std::max(0.0f, Dot(ux, uy, wx, wy));
      ux = length * wx;
      uy = length * wy;
    }
  }
  // Whatever the passes left unsatisfied, stopping satisfies.
  const float speed = std::sqrt(ux * ux + uy * uy);
  for (size_t i = 0; i < count_; ++i) {
    const Constraint& c = constraints_[i];
    const float along = Dot(ux, uy, c.nx, c.ny);
    const float limit = c.cone ? -c.bound * speed : c.bound;
    if (along > limit + kFeasibilityToleranceMps) {
      ux = 0.0f;
      uy = 0.0f;
      break;
    }
  }
  vx = ux;
  vy = uy;
}

float SafetyFilter::LimitForward(float speed, float hx, float hy) const {
  float lowest = -own_max_speed_mps_;
  float highest = own_max_speed_mps_;
  bool forward_ok = true;
  bool backward_ok = true;
  for (size_t i = 0; i < count_; ++i) {
    const Constraint& c = constraints_[i];
    const float along = Dot(hx, hy, c.nx, c.ny);
    if (c.cone) {
      // v > 0 moves along h, v < 0 along -h: each is allowed only inside the cone.
      if (along > -c.bound) forward_ok = false;
      if (-along > -c.bound) backward_ok = false;
      continue;
    }
    if (along > kParallelEpsilon) {
      highest = std::min(highest, c.bound / along);
    } else if (along < -kParallelEpsilon) {
      lowest = std::max(lowest, c.bound / along);
    }
  }
  float limited = std::clamp(speed, std::min(lowest, 0.0f), std::max(highest, 0.0f));
  if ((limited > 0.0f && !forward_ok) || (limited < 0.0f && !backward_ok)) limited = 0.0f;
  return limited;
}

// The command limited against the constraints Collect kept; `change` is
// how far it moved (m/s: a rover's forward speed, an omni robot's velocity).
// (hx, hy): a rover's heading's cosine and sine (Apply's; unused for omni).
DriveCommand SafetyFilter::Limit(const DriveCommand& desired, float hx, float hy, float heading_doubt_rad,
                                 float& change) const {
  DriveCommand limited = desired;
  if (kind_ == DriveKind::kWheels) {
    const float desired_forward = 0.5f * (desired.left_mps + desired.right_mps);
    const float half_difference = 0.5f * (desired.right_mps - desired.left_mps);
    float forward = LimitForward(desired_forward, hx, hy);
    forward *= HeadingRobustScale(forward * hx, forward * hy, heading_doubt_rad);
    limited.left_mps = forward - half_difference;
    limited.right_mps = forward + half_difference;
    change = std::fabs(forward - desired_forward);
    return limited;
  }
  float vx = desired.vx_mps;
  float vy = desired.vy_mps;
  LimitOmni(vx, vy);
  const float scale = HeadingRobustScale(vx, vy, heading_doubt_rad);
  vx *= scale;
  vy *= scale;
  limited.vx_mps = vx;
  limited.vy_mps = vy;
  change = std::sqrt((vx - desired.vx_mps) * (vx - desired.vx_mps) + (vy - desired.vy_mps) * (vy - desired.vy_mps));
  return limited;
}

// Whether a filter at charged_sigmas would have limited `desired` too. Its
// discs are smaller by the difference of the two allowances, so its
// constraints are the kept ones rebuilt as its Collect builds them (those
// out of its reach dropped, the order kept), not another pass over the
// reports; walls do not depend on the allowance. Only for a limited step,
// so most steps pay nothing. Overwrites the kept constraints.
bool SafetyFilter::BreaksChargedRule(const DriveCommand& desired, const estimation::StateEstimate& estimate,
                                     float own_allowance_m, float hx, float hy, float heading_doubt_rad) {
  const float charged_allowance_m = ErrorAllowanceM(config_, config_.charged_sigmas, estimate);
  if (charged_allowance_m >= own_allowance_m) return true;
  const float base_m = DiscBaseM(charged_allowance_m);
  size_t kept = 0;
  for (size_t i = 0; i < count_; ++i) {
    Constraint c = constraints_[i];
    if (c.other != kWallObstacle) {
      const float radius_m = base_m + c.sigma_m;
      const float far_m = radius_m + reach_m_;
      if (c.squared_m2 > far_m * far_m) continue;
      RobotConstraint(c, radius_m);
    }
    constraints_[kept++] = c;
  }
  count_ = kept;
  if (count_ == 0) return false;
  float change = 0.0f;
  (void)Limit(desired, hx, hy, heading_doubt_rad, change);
  return change > kLimitedThresholdMps;
}

DriveCommand SafetyFilter::Apply(const DriveCommand& desired, const estimation::StateEstimate& estimate,
                                 const SafetyReports& reports, int64_t now_ns, SafetyOutcome& outcome) {
  outcome = SafetyOutcome{};
  const bool usable = (estimate.status & estimation::kEstimateInitialized) != 0 && std::isfinite(estimate.x_m) &&
                      std::isfinite(estimate.y_m) && std::isfinite(estimate.heading_rad);
  if (!config_.enabled || !usable || !NeedsReports(desired)) return desired;
  count_ = 0;
  const float own_allowance_m = OwnErrorAllowanceM(config_, estimate);
  const float heading_doubt_rad =
      std::isfinite(estimate.sigma_heading_rad)
          ? std::clamp(config_.heading_sigmas * estimate.sigma_heading_rad - config_.heading_free_rad, 0.0f,
                       0.5f * kPiF)
          : 0.5f * kPiF;
  Collect(estimate.x_m, estimate.y_m, own_allowance_m, reports, now_ns);
  if (count_ == 0) return desired;

  // A rover's heading, once for every Limit of this step.
  const bool wheels = kind_ == DriveKind::kWheels;
  const float hx = wheels ? std::cos(estimate.heading_rad) : 0.0f;
  const float hy = wheels ? std::sin(estimate.heading_rad) : 0.0f;
  float change = 0.0f;
  const DriveCommand limited = Limit(desired, hx, hy, heading_doubt_rad, change);
  outcome.limited = change > kLimitedThresholdMps;
  if (!outcome.limited) return desired;
  // The obstacle the desired velocity pressed hardest against.
  const float desired_forward = 0.5f * (desired.left_mps + desired.right_mps);
  const float ux = wheels ? desired_forward * hx : desired.vx_mps;
  const float uy = wheels ? desired_forward * hy : desired.vy_mps;
  const float desired_speed = std::sqrt(ux * ux + uy * uy);
  float worst = -1e30f;
  for (size_t i = 0; i < count_; ++i) {
    const Constraint& c = constraints_[i];
    const float along = Dot(ux, uy, c.nx, c.ny);
    const float violation = c.cone ? along + c.bound * desired_speed : along - c.bound;
    if (violation > worst) {
      worst = violation;
      outcome.other = c.other;
    }
  }
  const bool new_hold = !ever_limited_ || now_ns - last_limited_ns_ > kInterventionReleaseNs;
  if (new_hold) hold_charged_ = false;
  // A hold already charged stays an intervention whatever its later steps
  // are: they need no second answer (most limited steps, in a packed swarm).
  outcome.charged = hold_charged_ || BreaksChargedRule(desired, estimate, own_allowance_m, hx, hy, heading_doubt_rad);
  outcome.precaution_started = new_hold && !outcome.charged;
  outcome.started = outcome.charged && !hold_charged_;
  if (outcome.charged) hold_charged_ = true;
  if (outcome.started) ++interventions_;
  if (outcome.precaution_started) ++precautions_;
  ever_limited_ = true;
  last_limited_ns_ = now_ns;
  ++limited_steps_;
  return limited;
}

}  // namespace syrof::motion
