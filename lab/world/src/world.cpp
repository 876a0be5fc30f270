#include "syrof/lab/world/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "syrof/base/check.h"
#include "syrof/base/split_mix64.h"

namespace syrof::lab::world {
namespace {

// |(x, y)|. Plain sqrt rather than std::hypot, which guards against overflow
// no arena can reach and costs several times more (this runs for every pair
// of nearby bodies every physics step).
double Length(double x, double y) { return std::sqrt(x * x + y * y); }

// A holonomic body's commanded velocity, scaled down to its top speed.
std::pair<double, double> Setpoint(const motion::DriveCommand& drive, double max_speed_mps) {
  double vx = drive.vx_mps;
  double vy = drive.vy_mps;
  const double speed = Length(vx, vy);
  if (speed > max_speed_mps) {
    vx *= max_speed_mps / speed;
    vy *= max_speed_mps / speed;
  }
  return {vx, vy};
}

// Pairs closer than this (surface to surface) after integration are the
// candidates a step examines: every overlapping or touching pair is one.
// The margin also covers pairs that separation pushes into each other (with
// the default limits a step moves bodies by about a centimetre); one it
// misses overlaps at the next step and is handled there. Bodies are checked
// at the end of each step only, so a body that moves more than a diameter
// per step could pass through another (0.2 s steps at 1 m/s): keep steps short.
constexpr double kCandidateGapM = 0.05;

// Separation passes per step: piles of a few bodies settle in a few.
constexpr int kSeparationPasses = 6;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// What a step that moved anything takes off the gap floor beyond the bodies'
// displacements, per metre of the world's extent: Gap() and the displacement
// are each off by a few ulps of the coordinates (2.2e-16 per metre each), far
// below this.
constexpr double kFloorSlackPerM = 1e-9;

constexpr uint32_t PairKey(uint16_t a, uint16_t b) { return (static_cast<uint32_t>(a) << 16) | b; }
constexpr uint16_t FirstOf(uint32_t key) { return static_cast<uint16_t>(key >> 16); }
constexpr uint16_t SecondOf(uint32_t key) { return static_cast<uint16_t>(key & 0xFFFFu); }

double Wrap(double angle_rad) { return std::remainder(angle_rad, 2.0 * std::numbers::pi); }

// sin(h) / h, accurate near 0.
double Sinc(double h) {
  if (std::fabs(h) < 1e-6) {
    return 1.0 - h * h / 6.0;
  }
  return std::sin(h) / h;
}

// `value` moved toward `target` by at most `step`.
double Approach(double value, double target, double step) {
  return value + std::clamp(target - value, -step, step);
}

bool PositiveFinite(double value) { return std::isfinite(value) && value > 0; }
bool NonNegativeFinite(double value) { return std::isfinite(value) && value >= 0; }

// The purpose mixed into the seed for the drones' drift (no other stream
// draws from the world's seed yet).
constexpr uint64_t kDriftPurpose = 0x64726966745F7677ull;  // "drift_vw"

// Uniform in (0, 1) from the top 53 bits of a hash (never 0: the log below).
double OpenUniform(uint64_t hash) { return (static_cast<double>(hash >> 11) + 0.5) * 0x1.0p-53; }

bool IsFinite(const motion::DriveCommand& drive) {
  return std::isfinite(drive.vx_mps) && std::isfinite(drive.vy_mps) && std::isfinite(drive.yaw_rate_radps) &&
         std::isfinite(drive.left_mps) && std::isfinite(drive.right_mps);
}

}  // namespace

const char* ToString(BodyPresence presence) {
  switch (presence) {
    case BodyPresence::kAbsent:
      return "absent";
    case BodyPresence::kActive:
      return "active";
    case BodyPresence::kStopped:
      return "stopped";
  }
  return "?";
}

std::optional<Error> CheckWorldSpec(const ArenaSpec& arena, std::span<const BodySpec> bodies) {
  if (!PositiveFinite(arena.width_m) || !PositiveFinite(arena.height_m)) {
    return Error{.where = "arena", .message = "width and height must be > 0"};
  }
  if (bodies.size() > 0xFFFFu) return Error{.where = "bodies", .message = "at most 65535"};
  for (size_t i = 0; i < bodies.size(); ++i) {
    const BodySpec& spec = bodies[i];
    const std::string where = "body " + std::to_string(i);
    if (spec.id != i) return Error{.where = where, .message = "id " + std::to_string(spec.id) + " is not its index"};
    if (!PositiveFinite(spec.spec.body_radius_m) || !PositiveFinite(spec.spec.max_speed_mps) ||
        !PositiveFinite(spec.spec.max_accel_mps2) || !PositiveFinite(spec.spec.max_turn_rate_radps) ||
        !PositiveFinite(spec.spec.wheel_base_m)) {
      return Error{.where = where, .message = "radius and limits must be > 0"};
    }
    if (!NonNegativeFinite(spec.spec.tilt_time_constant_s) || !NonNegativeFinite(spec.spec.drift_sigma_mps) ||
        !NonNegativeFinite(spec.spec.flight_height_m)) {
      return Error{.where = where, .message = "tilt time constant, drift and flight height must be finite and >= 0"};
    }
    if (!std::isfinite(spec.x_m) || !std::isfinite(spec.y_m) || !std::isfinite(spec.heading_rad)) {
      return Error{.where = where, .message = "pose must be finite"};
    }
  }
  return std::nullopt;
}

World::World(const ArenaSpec& arena, std::span<const BodySpec> bodies, uint64_t seed)
    : width_m_(arena.width_m),
      height_m_(arena.height_m),
      seed_(seed),
      min_separation_m_(kInfinity),
      gap_floor_m_(-kInfinity) {
  if (const std::optional<Error> problem = CheckWorldSpec(arena, bodies)) {
    base::check_failed(("World: " + problem->ToString()).c_str(), __FILE__, __LINE__);
  }
  bodies_.reserve(bodies.size());
  double extent_m = std::max({1.0, width_m_, height_m_});
  for (const BodySpec& spec : bodies) {
    Body body;
    body.state.x_m = spec.x_m;
    body.state.y_m = spec.y_m;
    body.state.heading_rad = Wrap(spec.heading_rad);
    body.previous = body.state;
    body.kind = spec.kind;
    body.spec = spec.spec;
    body.presence = spec.presence;
    body.drive.kind = DriveKindFor(spec.kind);
    bodies_.push_back(body);
    max_radius_m_ = std::max(max_radius_m_, spec.spec.body_radius_m);
    extent_m = std::max({extent_m, std::fabs(spec.x_m), std::fabs(spec.y_m)});
  }
  // No coordinate ever exceeds extent_m: active bodies end every step inside
  // the walls, the others do not move.
  floor_slack_m_ = kFloorSlackPerM * extent_m;

  // About one cell per body, never narrower than a contact distance, so a
  // pair within kCandidateGapM always sits in neighbouring cells.
  const double body_count = static_cast<double>(std::max<size_t>(bodies_.size(), 1));
  cell_m_ = std::max(2 * max_radius_m_ + kCandidateGapM, std::sqrt(width_m_ * height_m_ / body_count));
  columns_ = static_cast<int>(std::clamp(std::ceil(width_m_ / cell_m_), 1.0, 32768.0));
  rows_ = static_cast<int>(std::clamp(std::ceil(height_m_ / cell_m_), 1.0, 32768.0));
  const size_t cells = static_cast<size_t>(columns_) * static_cast<size_t>(rows_);
  cell_start_.assign(cells + 1, 0);
  cell_cursor_.assign(cells, 0);
  cell_bodies_.assign(bodies_.size(), 0);
  body_cell_.assign(bodies_.size(), -1);
  candidates_.reserve(8 * bodies_.size());
  candidate_in_contact_.reserve(8 * bodies_.size());
  constraint_start_.assign(bodies_.size() + 1, 0);
  constraint_cursor_.assign(bodies_.size(), 0);
  constraints_.reserve(18 * bodies_.size());
  touching_.reserve(8 * bodies_.size());
  touching_next_.reserve(8 * bodies_.size());
  new_contacts_.reserve(bodies_.size());
  new_wall_contacts_.reserve(bodies_.size());

  // Contacts present at placement are not events.
  BuildGrid();
  FindCandidates();
  for (const uint32_t key : candidates_) {
    if (Gap(FirstOf(key), SecondOf(key)) <= 0) {
      touching_.push_back(key);
    }
  }
  for (Body& body : bodies_) {
    body.touching_wall = body.presence != BodyPresence::kAbsent && WallGap(body) <= 0;
  }
}

const World::Body& World::body(uint16_t robot) const {
  SYROF_CHECK(robot < bodies_.size());
  return bodies_[robot];
}

World::Body& World::body(uint16_t robot) {
  return const_cast<Body&>(static_cast<const World&>(*this).body(robot));
}

const BodyState& World::state(uint16_t robot) const { return body(robot).state; }

sensors::TrueState World::true_state(uint16_t robot) const {
  const BodyState& state = body(robot).state;
  sensors::TrueState truth;
  truth.x_m = state.x_m;
  truth.y_m = state.y_m;
  truth.vx_mps = state.vx_mps;
  truth.vy_mps = state.vy_mps;
  truth.ax_mps2 = state.ax_mps2;
  truth.ay_mps2 = state.ay_mps2;
  truth.heading_rad = state.heading_rad;
  truth.yaw_rate_radps = state.yaw_rate_radps;
  return truth;
}

BodyPresence World::presence(uint16_t robot) const { return body(robot).presence; }
double World::body_radius_m(uint16_t robot) const { return body(robot).spec.body_radius_m; }
double World::left_wheel_mps(uint16_t robot) const { return body(robot).left_mps; }
double World::right_wheel_mps(uint16_t robot) const { return body(robot).right_mps; }

void World::SetDrive(uint16_t robot, const motion::DriveCommand& drive) {
  Body& target = body(robot);
  const motion::DriveKind kind = DriveKindFor(target.kind);
  if (drive.kind == kind && IsFinite(drive)) {
    target.drive = drive;
    return;
  }
  ++rejected_drives_;
  target.drive = motion::DriveCommand{};
  target.drive.timestamp_ns = drive.timestamp_ns;
  target.drive.kind = kind;
}

void World::SetPresence(uint16_t robot, BodyPresence presence) {
  Body& target = body(robot);
  if (presence == target.presence) {
    return;
  }
  if (presence != BodyPresence::kStopped) {
    target.state.vx_mps = target.state.vy_mps = target.state.yaw_rate_radps = 0;
    target.state.ax_mps2 = target.state.ay_mps2 = 0;
    target.left_mps = target.right_mps = 0;
    target.drift_x_mps = target.drift_y_mps = 0;
  }
  if (presence == BodyPresence::kAbsent) {
    target.touching_wall = false;
  }
  target.presence = presence;
  // A body that appears may sit closer to another than any gap seen so far.
  gap_floor_m_ = -kInfinity;
}

void World::Integrate(Body& target, uint16_t robot, int64_t now_ns, double dt_s) const {
  if (target.presence == BodyPresence::kStopped) {
    target.state.vx_mps = target.state.vy_mps = target.state.yaw_rate_radps = 0;
    target.left_mps = target.right_mps = 0;
    target.drift_x_mps = target.drift_y_mps = 0;
    return;
  }
  if (target.kind == RobotKind::kRover) {
    IntegrateRover(target, dt_s);
  } else if (target.kind == RobotKind::kDrone) {
    IntegrateDrone(target, robot, now_ns, dt_s);
  } else {
    IntegrateOmni(target, dt_s);
  }
}

double World::DriftNormal(int64_t now_ns, uint16_t robot, int axis) const {
  // Box-Muller from two uniforms, each a hash of (seed, time, robot, axis,
  // which): independent of the order bodies and steps are visited in.
  const uint64_t base = base::SplitMix64Hash(base::SplitMix64Hash(seed_ ^ kDriftPurpose) ^
                                             static_cast<uint64_t>(now_ns));
  const uint64_t key = base::SplitMix64Hash(base ^ ((static_cast<uint64_t>(robot) << 8) | static_cast<uint64_t>(axis)));
  const double u1 = OpenUniform(key);
  const double u2 = OpenUniform(base::SplitMix64Hash(key));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

// A holonomic body's step to velocity (vx, vy): constant acceleration over
// the step, so the mean velocity moves it; it turns at its commanded rate.
void World::MoveHolonomic(Body& target, double vx, double vy, double dt_s) const {
  const KindSpec& spec = target.spec;
  BodyState& state = target.state;
  state.x_m += 0.5 * (state.vx_mps + vx) * dt_s;
  state.y_m += 0.5 * (state.vy_mps + vy) * dt_s;
  state.vx_mps = vx;
  state.vy_mps = vy;
  state.yaw_rate_radps = std::clamp(static_cast<double>(target.drive.yaw_rate_radps), -spec.max_turn_rate_radps,
                                    spec.max_turn_rate_radps);
  state.heading_rad = Wrap(state.heading_rad + state.yaw_rate_radps * dt_s);
}

void World::IntegrateDrone(Body& target, uint16_t robot, int64_t now_ns, double dt_s) const {
  const KindSpec& spec = target.spec;
  BodyState& state = target.state;
  const auto [set_vx, set_vy] = Setpoint(target.drive, spec.max_speed_mps);
  // The velocity the tilt gives (the body's, less its drift) follows the
  // setpoint as a first-order lag, exact for a setpoint held over the step,
  // and never faster than the tilt's acceleration limit.
  const double flown_vx = state.vx_mps - target.drift_x_mps;
  const double flown_vy = state.vy_mps - target.drift_y_mps;
  const double share = spec.tilt_time_constant_s > 0 ? -std::expm1(-dt_s / spec.tilt_time_constant_s) : 1.0;
  double dvx = (set_vx - flown_vx) * share;
  double dvy = (set_vy - flown_vy) * share;
  const double dv = Length(dvx, dvy);
  const double max_dv = spec.max_accel_mps2 * dt_s;
  if (dv > max_dv) {
    dvx *= max_dv / dv;
    dvy *= max_dv / dv;
  }
  // The drift: a first-order Gauss-Markov velocity, exact over the step, so
  // its standard deviation stays drift_sigma whatever the step.
  if (spec.drift_sigma_mps > 0) {
    const double keep = std::exp(-dt_s / kDriftCorrelationS);
    const double fresh = spec.drift_sigma_mps * std::sqrt(-std::expm1(-2.0 * dt_s / kDriftCorrelationS));
    target.drift_x_mps = keep * target.drift_x_mps + fresh * DriftNormal(now_ns, robot, 0);
    target.drift_y_mps = keep * target.drift_y_mps + fresh * DriftNormal(now_ns, robot, 1);
  }
  MoveHolonomic(target, flown_vx + dvx + target.drift_x_mps, flown_vy + dvy + target.drift_y_mps, dt_s);
}

void World::IntegrateOmni(Body& target, double dt_s) const {
  const KindSpec& spec = target.spec;
  BodyState& state = target.state;
  const auto [set_vx, set_vy] = Setpoint(target.drive, spec.max_speed_mps);
  double dvx = set_vx - state.vx_mps;
  double dvy = set_vy - state.vy_mps;
  const double dv = Length(dvx, dvy);
  const double max_dv = spec.max_accel_mps2 * dt_s;
  if (dv > max_dv) {
    dvx *= max_dv / dv;
    dvy *= max_dv / dv;
  }
  MoveHolonomic(target, state.vx_mps + dvx, state.vy_mps + dvy, dt_s);
}

void World::IntegrateRover(Body& target, double dt_s) const {
  const KindSpec& spec = target.spec;
  BodyState& state = target.state;
  const double max_step = spec.max_accel_mps2 * dt_s;
  const double set_left = std::clamp(static_cast<double>(target.drive.left_mps), -spec.max_speed_mps,
                                     spec.max_speed_mps);
  const double set_right = std::clamp(static_cast<double>(target.drive.right_mps), -spec.max_speed_mps,
                                      spec.max_speed_mps);
  const double left = Approach(target.left_mps, set_left, max_step);
  const double right = Approach(target.right_mps, set_right, max_step);
  // The unicycle along the arc of the mean wheel speeds over the step (exact
  // for constant wheel speeds): the chord has length v dt sinc(dtheta / 2)
  // and points along the mid-step heading.
  const double mean_speed = 0.25 * (target.left_mps + target.right_mps + left + right);
  const double mean_rate = 0.5 * ((target.right_mps - target.left_mps) + (right - left)) / spec.wheel_base_m;
  const double turn_rad = mean_rate * dt_s;
  const double chord_m = mean_speed * dt_s * Sinc(0.5 * turn_rad);
  const double mid_heading = state.heading_rad + 0.5 * turn_rad;
  state.x_m += chord_m * std::cos(mid_heading);
  state.y_m += chord_m * std::sin(mid_heading);
  state.heading_rad = Wrap(state.heading_rad + turn_rad);
  target.left_mps = left;
  target.right_mps = right;
  const double speed = 0.5 * (left + right);
  state.vx_mps = speed * std::cos(state.heading_rad);
  state.vy_mps = speed * std::sin(state.heading_rad);
  state.yaw_rate_radps = (right - left) / spec.wheel_base_m;
}

int World::CellOf(double x_m, double y_m) const {
  const int column = static_cast<int>(std::clamp(std::floor(x_m / cell_m_), 0.0, static_cast<double>(columns_ - 1)));
  const int row = static_cast<int>(std::clamp(std::floor(y_m / cell_m_), 0.0, static_cast<double>(rows_ - 1)));
  return row * columns_ + column;
}

void World::BuildGrid() {
  std::fill(cell_start_.begin(), cell_start_.end(), 0u);
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const Body& each = bodies_[i];
    if (each.presence == BodyPresence::kAbsent) {
      body_cell_[i] = -1;
      continue;
    }
    const int cell = CellOf(each.state.x_m, each.state.y_m);
    body_cell_[i] = cell;
    ++cell_start_[static_cast<size_t>(cell) + 1];
  }
  for (size_t cell = 1; cell < cell_start_.size(); ++cell) {
    cell_start_[cell] += cell_start_[cell - 1];
  }
  std::copy(cell_start_.begin(), cell_start_.end() - 1, cell_cursor_.begin());
  // Bodies in increasing id, so each cell lists its bodies in increasing id.
  for (size_t i = 0; i < bodies_.size(); ++i) {
    if (body_cell_[i] >= 0) {
      cell_bodies_[cell_cursor_[static_cast<size_t>(body_cell_[i])]++] = static_cast<uint16_t>(i);
    }
  }
}

double World::Gap(uint16_t a, uint16_t b) const {
  const BodyState& first = bodies_[a].state;
  const BodyState& second = bodies_[b].state;
  return Length(second.x_m - first.x_m, second.y_m - first.y_m) - bodies_[a].spec.body_radius_m -
         bodies_[b].spec.body_radius_m;
}

double World::WallGap(const Body& target) const {
  const double radius = target.spec.body_radius_m;
  const BodyState& state = target.state;
  return std::min({state.x_m - radius, width_m_ - radius - state.x_m, state.y_m - radius,
                   height_m_ - radius - state.y_m});
}

void World::FindCandidates() {
  candidates_.clear();
  for (size_t a = 0; a < bodies_.size(); ++a) {
    const int cell = body_cell_[a];
    if (cell < 0) {
      continue;
    }
    const BodyState& first = bodies_[a].state;
    const double reach_a = bodies_[a].spec.body_radius_m + kCandidateGapM;
    const int column = cell % columns_;
    const int row = cell / columns_;
    for (int neighbour_row = std::max(row - 1, 0); neighbour_row <= std::min(row + 1, rows_ - 1); ++neighbour_row) {
      for (int neighbour_column = std::max(column - 1, 0); neighbour_column <= std::min(column + 1, columns_ - 1);
           ++neighbour_column) {
        const size_t neighbour = static_cast<size_t>(neighbour_row * columns_ + neighbour_column);
        for (uint32_t k = cell_start_[neighbour]; k < cell_start_[neighbour + 1]; ++k) {
          const uint16_t b = cell_bodies_[k];
          if (b <= a) {
            continue;
          }
          const BodyState& second = bodies_[b].state;
          const double dx = second.x_m - first.x_m;
          const double dy = second.y_m - first.y_m;
          const double reach = reach_a + bodies_[b].spec.body_radius_m;
          if (dx * dx + dy * dy <= reach * reach) {
            candidates_.push_back(PairKey(static_cast<uint16_t>(a), b));
          }
        }
      }
    }
  }
  std::sort(candidates_.begin(), candidates_.end());
}

void World::RecordContacts(int64_t now_ns) {
  new_contacts_.clear();
  new_wall_contacts_.clear();
  touching_next_.clear();
  candidate_in_contact_.clear();
  // Both lists are sorted: walk them together. A touching pair missing from
  // the candidates is more than kCandidateGapM apart, so its contact ended.
  size_t previous = 0;
  for (const uint32_t key : candidates_) {
    while (previous < touching_.size() && touching_[previous] < key) {
      ++previous;
    }
    const bool was_touching = previous < touching_.size() && touching_[previous] == key;
    const double gap_m = Gap(FirstOf(key), SecondOf(key));
    bool in_contact = false;
    if (gap_m <= 0) {
      if (!was_touching) {
        new_contacts_.push_back(Contact{now_ns, FirstOf(key), SecondOf(key)});
        ++contacts_;
      }
      in_contact = true;
    } else if (was_touching && gap_m <= kContactHysteresisM) {
      in_contact = true;
    }
    if (in_contact) {
      touching_next_.push_back(key);
    }
    candidate_in_contact_.push_back(in_contact ? 1 : 0);
  }
  touching_.swap(touching_next_);

  for (size_t i = 0; i < bodies_.size(); ++i) {
    Body& each = bodies_[i];
    if (each.presence == BodyPresence::kAbsent) {
      continue;
    }
    const double gap_m = WallGap(each);
    if (gap_m <= 0) {
      if (!each.touching_wall) {
        new_wall_contacts_.push_back(WallContact{now_ns, static_cast<uint16_t>(i)});
        ++wall_contacts_;
      }
      each.touching_wall = true;
    } else if (gap_m > kContactHysteresisM) {
      each.touching_wall = false;
    }
  }
}

double World::ClampToWalls(Body& target) const {
  const double radius = target.spec.body_radius_m;
  BodyState& state = target.state;
  // An arena narrower than the body keeps it centred.
  const double low_x = std::min(radius, 0.5 * width_m_);
  const double low_y = std::min(radius, 0.5 * height_m_);
  const double x = std::clamp(state.x_m, low_x, width_m_ - low_x);
  const double y = std::clamp(state.y_m, low_y, height_m_ - low_y);
  const double moved = std::max(std::fabs(x - state.x_m), std::fabs(y - state.y_m));
  state.x_m = x;
  state.y_m = y;
  return moved;
}

double World::SeparateOnce() {
  double largest_move_m = 0;
  for (const uint32_t key : candidates_) {
    Body& first = bodies_[FirstOf(key)];
    Body& second = bodies_[SecondOf(key)];
    const bool first_moves = first.presence == BodyPresence::kActive;
    const bool second_moves = second.presence == BodyPresence::kActive;
    if (!first_moves && !second_moves) {
      continue;
    }
    const double dx = second.state.x_m - first.state.x_m;
    const double dy = second.state.y_m - first.state.y_m;
    const double distance = Length(dx, dy);
    const double overlap = first.spec.body_radius_m + second.spec.body_radius_m - distance;
    if (overlap <= 0) {
      continue;
    }
    // Coincident centres have no centre line: separate along +x, the same
    // way on every run.
    const double nx = distance > 1e-12 ? dx / distance : 1.0;
    const double ny = distance > 1e-12 ? dy / distance : 0.0;
    const double first_share = first_moves ? (second_moves ? 0.5 : 1.0) : 0.0;
    const double second_share = second_moves ? (first_moves ? 0.5 : 1.0) : 0.0;
    first.state.x_m -= nx * overlap * first_share;
    first.state.y_m -= ny * overlap * first_share;
    second.state.x_m += nx * overlap * second_share;
    second.state.y_m += ny * overlap * second_share;
    largest_move_m = std::max(largest_move_m, overlap * std::max(first_share, second_share));
  }
  for (Body& each : bodies_) {
    if (each.presence == BodyPresence::kActive) {
      largest_move_m = std::max(largest_move_m, ClampToWalls(each));
    }
  }
  return largest_move_m;
}

void World::AddConstraint(uint16_t robot, double nx, double ny) {
  constraints_[constraint_cursor_[robot]++] = Normal{nx, ny};
}

void World::DropApproachingVelocities() {
  // Gather, per active body, the unit normals toward everything it is in
  // contact with (compressed rows: constraint_start_ holds the offsets).
  const size_t count = bodies_.size();
  std::fill(constraint_start_.begin(), constraint_start_.end(), 0u);
  for (size_t i = 0; i < candidates_.size(); ++i) {
    if (candidate_in_contact_[i] != 0) {
      ++constraint_start_[FirstOf(candidates_[i]) + 1u];
      ++constraint_start_[SecondOf(candidates_[i]) + 1u];
    }
  }
  for (size_t robot = 0; robot < count; ++robot) {
    constraint_start_[robot + 1] += bodies_[robot].touching_wall ? 2u : 0u;  // a corner touches two walls
  }
  for (size_t robot = 1; robot <= count; ++robot) {
    constraint_start_[robot] += constraint_start_[robot - 1];
  }
  constraints_.resize(constraint_start_[count]);
  std::copy(constraint_start_.begin(), constraint_start_.end() - 1, constraint_cursor_.begin());
  for (size_t i = 0; i < candidates_.size(); ++i) {
    if (candidate_in_contact_[i] == 0) {
      continue;
    }
    const uint16_t a = FirstOf(candidates_[i]);
    const uint16_t b = SecondOf(candidates_[i]);
    const double dx = bodies_[b].state.x_m - bodies_[a].state.x_m;
    const double dy = bodies_[b].state.y_m - bodies_[a].state.y_m;
    const double distance = Length(dx, dy);
    const double nx = distance > 1e-12 ? dx / distance : 1.0;
    const double ny = distance > 1e-12 ? dy / distance : 0.0;
    AddConstraint(a, nx, ny);
    AddConstraint(b, -nx, -ny);
  }
  for (size_t robot = 0; robot < count; ++robot) {
    const Body& each = bodies_[robot];
    if (!each.touching_wall) {
      continue;
    }
    // The nearer wall of each axis; a body touching neither of an axis's
    // walls gets a zero normal there, which constrains nothing.
    const double radius = each.spec.body_radius_m;
    const double left = each.state.x_m - radius;
    const double right = width_m_ - radius - each.state.x_m;
    const double bottom = each.state.y_m - radius;
    const double top = height_m_ - radius - each.state.y_m;
    const auto id = static_cast<uint16_t>(robot);
    AddConstraint(id, std::min(left, right) <= kContactHysteresisM ? (left < right ? -1.0 : 1.0) : 0.0, 0.0);
    AddConstraint(id, 0.0, std::min(bottom, top) <= kContactHysteresisM ? (bottom < top ? -1.0 : 1.0) : 0.0);
  }

  for (size_t robot = 0; robot < count; ++robot) {
    Body& each = bodies_[robot];
    if (each.presence != BodyPresence::kActive) {
      continue;
    }
    const std::span<const Normal> normals(constraints_.data() + constraint_start_[robot],
                                          constraint_start_[robot + 1] - constraint_start_[robot]);
    const Normal velocity = NearestAllowed(Normal{each.state.vx_mps, each.state.vy_mps}, normals);
    each.state.vx_mps = velocity.x;
    each.state.vy_mps = velocity.y;
  }
}

World::Normal World::NearestAllowed(Normal velocity, std::span<const Normal> normals) {
  // The allowed velocities (no component toward any contact) form a convex
  // cone with its apex at 0. The nearest allowed velocity is the velocity
  // itself, its projection onto the boundary line of one violated
  // constraint (if that satisfies the others), or 0. Computing it per body,
  // not contact by contact, keeps a symmetric pile symmetric.
  constexpr double kSlack = 1e-12;
  auto allowed = [&](Normal candidate) {
    for (const Normal& normal : normals) {
      if (candidate.x * normal.x + candidate.y * normal.y > kSlack) {
        return false;
      }
    }
    return true;
  };
  if (allowed(velocity)) {
    return velocity;
  }
  Normal best{0, 0};
  double best_change = velocity.x * velocity.x + velocity.y * velocity.y;
  for (const Normal& normal : normals) {
    const double toward = velocity.x * normal.x + velocity.y * normal.y;
    if (toward <= kSlack) {
      continue;
    }
    const Normal candidate{velocity.x - toward * normal.x, velocity.y - toward * normal.y};
    if (toward * toward < best_change && allowed(candidate)) {
      best = candidate;
      best_change = toward * toward;
    }
  }
  return best;
}

void World::Step(int64_t now_ns, double dt_s) {
  SYROF_CHECK(dt_s > 0 && std::isfinite(dt_s));
  for (size_t i = 0; i < bodies_.size(); ++i) {
    Body& each = bodies_[i];
    each.previous = each.state;
    if (each.presence != BodyPresence::kAbsent) {
      Integrate(each, static_cast<uint16_t>(i), now_ns, dt_s);
    }
  }
  BuildGrid();
  FindCandidates();
  RecordContacts(now_ns);
  // Bound on how far any body moved while separating: pairs that were not
  // candidates may have closed by at most twice this.
  double total_move_m = 0;
  for (int pass = 0; pass < kSeparationPasses; ++pass) {
    const double moved_m = SeparateOnce();
    total_move_m += moved_m;
    if (moved_m == 0) {
      break;
    }
  }
  DropApproachingVelocities();
  double largest_step_squared_m2 = 0;
  for (Body& each : bodies_) {
    if (each.presence == BodyPresence::kAbsent) {
      each.state.ax_mps2 = each.state.ay_mps2 = 0;
      continue;
    }
    each.state.ax_mps2 = (each.state.vx_mps - each.previous.vx_mps) / dt_s;
    each.state.ay_mps2 = (each.state.vy_mps - each.previous.vy_mps) / dt_s;
    const double dx = each.state.x_m - each.previous.x_m;
    const double dy = each.state.y_m - each.previous.y_m;
    largest_step_squared_m2 = std::max(largest_step_squared_m2, dx * dx + dy * dy);
  }
  // A pair's gap shrank by at most the sum of its two displacements. When
  // nothing moved every Gap() is the same bits as before: no slack needed.
  if (largest_step_squared_m2 > 0) {
    gap_floor_m_ -= 2 * std::sqrt(largest_step_squared_m2) + floor_slack_m_;
  }
  UpdateMinSeparation(total_move_m);
}

void World::UpdateMinSeparation(double max_displacement_m) {
  size_t present = 0;
  for (const Body& each : bodies_) {
    present += each.presence != BodyPresence::kAbsent ? 1 : 0;
  }
  if (present < 2) {
    return;
  }
  double best_m = kInfinity;
  for (const uint32_t key : candidates_) {
    const double gap_m = Gap(FirstOf(key), SecondOf(key));
    // Candidates only: another pair would have to close by the whole
    // candidate gap within one step's separation to overlap.
    max_overlap_m_ = std::max(max_overlap_m_, -gap_m);
    best_m = std::min(best_m, std::max(0.0, gap_m));
  }
  // Every pair that was not a candidate is farther apart than this now.
  const double others_above_m = kCandidateGapM - 2 * max_displacement_m;
  // The search would return min(bound, smallest gap). With the floor at or
  // above the record, that is the record itself (every gap, the candidates'
  // best_m included, is >= floor >= record): the record stands, skip it.
  if (best_m > others_above_m && min_separation_m_ > others_above_m && gap_floor_m_ < min_separation_m_) {
    const double bound_m = std::min(best_m, min_separation_m_);
    // Searching up to any bound >= bound_m gives the same record, min(record,
    // best_m, smallest gap). Up to the largest bound the same cells cover, it
    // costs no more and may leave the floor above the record for later steps.
    const double cells = std::ceil((bound_m + 2 * max_radius_m_) / cell_m_);
    const double search_m = std::max(bound_m, (cells - 1e-6) * cell_m_ - 2 * max_radius_m_);
    gap_floor_m_ = SmallestGap(search_m);
    best_m = std::min(best_m, gap_floor_m_);
  }
  min_separation_m_ = std::min(min_separation_m_, best_m);
}

double World::SmallestGap(double best_m) {
  BuildGrid();
  const int widest = std::max(columns_, rows_);
  for (size_t a = 0; a < bodies_.size(); ++a) {
    const int cell = body_cell_[a];
    if (cell < 0) {
      continue;
    }
    // A body whose gap to `a` is below best_m has its centre within
    // best_m + 2 max radius, so its cell is at most this many cells away.
    const double reach_cells = std::ceil((best_m + 2 * max_radius_m_) / cell_m_);
    const int reach = std::isfinite(reach_cells) ? static_cast<int>(std::min<double>(reach_cells, widest)) : widest;
    const int column = cell % columns_;
    const int row = cell / columns_;
    for (int other_row = std::max(row - reach, 0); other_row <= std::min(row + reach, rows_ - 1); ++other_row) {
      for (int other_column = std::max(column - reach, 0); other_column <= std::min(column + reach, columns_ - 1);
           ++other_column) {
        const size_t other = static_cast<size_t>(other_row * columns_ + other_column);
        for (uint32_t k = cell_start_[other]; k < cell_start_[other + 1]; ++k) {
          const uint16_t b = cell_bodies_[k];
          if (b > a) {
            best_m = std::min(best_m, std::max(0.0, Gap(static_cast<uint16_t>(a), b)));
          }
        }
      }
    }
  }
  return best_m;
}

void World::AddToDigest(base::StateDigest& digest) const {
  for (const Body& body : bodies_) {
    digest.AddValue(body.state);
    digest.AddValue(body.previous);
    digest.AddValue(body.presence);
    digest.AddValue(body.drive);
    digest.AddValue(body.left_mps);
    digest.AddValue(body.right_mps);
    digest.AddValue(body.touching_wall);
    if (body.kind == RobotKind::kDrone) {  // only drones drift: the others' digests stay as they were
      digest.AddValue(body.drift_x_mps);
      digest.AddValue(body.drift_y_mps);
    }
  }
  digest.AddRange(std::span<const uint32_t>(touching_));
}

}  // namespace syrof::lab::world
