// Declarative goal checks: what a scenario (or an assignment) says the swarm
// must achieve, judged by the lab on true poses, never on the robots' own
// estimates. docs/scenarios.md ("goal") defines every check; this header is
// the vocabulary the scenario loader fills and the engine evaluates.
//
// A check is geometry on the positions of the robots running at a moment
// (MeasurePoses, a pure function), and a schedule saying which moments
// count (GoalMonitor): the final poses, every epoch's, or "from some epoch
// before a deadline on". Coverage is the one check over the whole run.
//
// Determinism: every computation is a fixed sequence of double operations
// on poses in increasing id order; assignments use the queries'
// MinWeightedMatching (ties broken by id); the shape's rotation is searched
// on a fixed grid. The same poses give the same result, bit for bit.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>
#include "syrof/base/state_digest.h"

namespace syrof::lab::goals {

/// A point in the arena frame (or a shape's own frame), metres.
struct Point {
  double x_m = 0;
  double y_m = 0;
  friend bool operator==(const Point&, const Point&) = default;
};

enum class CheckKind : uint8_t {
  kSlots = 0,     ///< each robot within tolerance of a given point (by id, or any assignment)
  kShape = 1,     ///< the robots form a shape up to translation and rotation
  kLine = 2,      ///< a line sorted by id: spacing apart along a direction
  kGathered = 3,  ///< every robot within a radius of one centre (free or given)
  kCircle = 4,    ///< evenly spaced on a circle (centre free or given, radius range)
  kCoverage = 5,  ///< a fraction of a rectangle's grid cells visited by a body over the run
};

/// "slots", "shape", "line", "gathered", "circle", "coverage": the names a
/// scenario file uses.
std::string_view ToString(CheckKind kind);
/// Every kind's name, in enum order.
std::span<const std::string_view> CheckKindNames();

/// Which poses a geometric check is judged on.
enum class When : uint8_t {
  kFinal = 0,       ///< the final poses
  kEveryEpoch = 1,  ///< every epoch's poses from `from_s` on, and the final ones
};

std::string_view ToString(When when);

/// One check, resolved and validated (the scenario loader's job; the
/// monitor SYROF_CHECKs the invariants it relies on).
struct GoalCheck {
  CheckKind kind = CheckKind::kGathered;
  std::string name;  ///< a label for reports; the loader defaults it to "<kind>" or "<kind>#<index>"
  When when = When::kFinal;
  double from_s = 0;                  ///< kEveryEpoch: samples before this time do not count
  std::optional<double> deadline_s;   ///< must hold from an epoch at or before this time to the end

  // kSlots: the points (arena frame); `by_id`: robot i goes to points[i],
  // else any assignment (bottleneck matching). kShape: the shape's points in
  // its own frame (as many as running robots).
  std::vector<Point> points;
  bool by_id = false;
  double tolerance_m = 0.1;           ///< slots, shape, line

  std::optional<double> direction_rad;  ///< line: the direction from the lowest id on; free when unset
  double spacing_m = 0.5;               ///< line

  double radius_m = 0.5;              ///< gathered: the largest radius holding every robot
  std::optional<Point> centre;        ///< gathered, circle: given centre; free when unset

  double radius_min_m = 0;            ///< circle: every robot's distance from the centre in [min, max]
  double radius_max_m = 0;
  double angle_tolerance_rad = 0.1;   ///< circle: largest deviation of a gap from 2*pi/n

  /// A private input the check reads (the scenario's `inputs`), and how:
  /// line `order_by` places the robots in increasing order of it (ties by
  /// id) instead of by id; gathered `centre_at_max` centres the circle on
  /// the running robot with the largest value (ties: the lowest id);
  /// gathered `group_by` gathers each group of robots sharing a value on
  /// its own, within radius_m of its own centre, the groups' centres at
  /// least groups_apart_m apart.
  enum class InputUse : uint8_t { kNone, kOrderBy, kCentreAtMax, kGroupBy };
  InputUse input_use = InputUse::kNone;
  std::string input;                  ///< its name, for reasons
  std::vector<double> input_values;   ///< by robot id (the loader resolves them)
  double groups_apart_m = 0;          ///< gathered with group_by

  Point area_min;                     ///< coverage: the rectangle [min, max]
  Point area_max;
  double cell_m = 0.25;               ///< coverage: side of a grid cell
  double min_fraction = 0.9;          ///< coverage: fraction of cells that must be visited
};

/// Most grid cells a coverage check may have (bounded memory).
inline constexpr int64_t kMaxCoverageCells = 1'000'000;

/// A running robot at one moment: true position and body radius.
struct RobotPose {
  uint16_t id = 0;
  double x_m = 0;
  double y_m = 0;
  double radius_m = 0.1;
};

/// What one geometric check says of one set of poses.
struct Measure {
  bool holds = false;
  double value = 0;    ///< the measured quantity (see MeasurePoses); may be NaN when unjudgeable
  std::string reason;  ///< one line a student understands
};

/// Scratch space for the matchings (a queries workspace, about 4 MB).
class Workspace {
 public:
  Workspace();
  ~Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
  struct Impl;
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// Judges `check` (not kCoverage) on `poses` (the running robots, any order).
/// The measured value and its unit (Unit()):
///   slots     the largest robot-to-slot distance, m
///   shape     the largest robot-to-point distance at the best alignment, m
///   line      the largest distance of a robot from its place on the line, m
///   gathered  the radius of the smallest circle holding every robot (or
///             the largest distance from the given centre, or from the
///             robot with the largest input; with group_by the largest
///             group's circle), m
///   circle    the largest deviation of a gap between neighbours from
///             2*pi/n, rad (a radius out of range fails with its reason)
/// No running robot never holds ("no robot is running").
Measure MeasurePoses(const GoalCheck& check, std::span<const RobotPose> poses, Workspace& workspace);

/// "m", "rad" or "fraction": the unit of a check's measured value.
std::string_view Unit(CheckKind kind);
/// The limit the measured value is compared with (tolerance, radius,
/// angle tolerance, minimum fraction).
double Limit(const GoalCheck& check);

/// A check's verdict over the run.
struct CheckResult {
  std::string name;
  CheckKind kind = CheckKind::kGathered;
  When when = When::kFinal;
  bool passed = false;
  double value = 0;            ///< final value (coverage: fraction), or the worst over the samples that count
  double limit = 0;
  std::string reason;          ///< why it passed or failed
  int64_t samples = 0;         ///< epoch samples judged (kEveryEpoch, deadlines)
  std::optional<double> deadline_s;
  /// Deadline checks: the epoch from which the goal held to the end, and
  /// when (the final moment when only the final poses held).
  std::optional<uint16_t> held_from_epoch;
  std::optional<double> held_from_s;
};

/// Feeds checks with the run as it goes, in bounded memory (a coverage grid
/// per coverage check, a few numbers per check).
///
/// Call order: OnRound at every radio round end (coverage), OnEpoch when an
/// epoch newer than every earlier one starts (its poses are a sample), then
/// Finish once with the final poses. Times never decrease.
class GoalMonitor {
 public:
  explicit GoalMonitor(std::vector<GoalCheck> checks);
  ~GoalMonitor();
  GoalMonitor(GoalMonitor&&) noexcept;

  bool empty() const { return checks_.empty(); }
  void OnRound(double time_s, std::span<const RobotPose> running);
  void OnEpoch(uint16_t epoch, double time_s, std::span<const RobotPose> running);
  /// The verdicts, one per check in the order given.
  std::vector<CheckResult> Finish(double time_s, std::span<const RobotPose> running);

  /// What the checks have seen so far into `digest` (base/state_digest.h).
  void AddToDigest(base::StateDigest& digest) const;

 private:
  struct Track;
  std::vector<GoalCheck> checks_;
  std::vector<Track> tracks_;
  std::unique_ptr<Workspace> workspace_;
};

}  // namespace syrof::lab::goals
