// A scenario: everything the simulated lab needs to run one swarm, as read
// from a YAML file (docs/scenarios.md) and resolved: defaults filled in,
// command-line overrides applied, robot placement computed. The simulator
// reads only this struct; it never sees YAML.
//
// Units are in the names. Arena frame: origin at the arena's lower-left
// corner, x right, y up, z up from the floor, headings counter-clockwise
// from +x in radians.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/goals/goals.h"
#include "syrof/lab/message/message_format.h"
#include "syrof/lab/sensors/sensor_bank.h"
#include "syrof/lab/world/arena.h"
#include "syrof/lab/world/channel.h"
#include "syrof/sync/activation.h"

namespace syrof::lab::scenario {

/// One robot, resolved.
struct RobotSpec {
  uint16_t id = 0;            ///< 0 .. robots.size() - 1, in order
  world::RobotKind kind = world::RobotKind::kOmni;
  double x_m = 0;             ///< initial true pose
  double y_m = 0;
  double heading_rad = 0;
  bool present_at_start = true;  ///< false when a `join` fault switches it on later
};

/// How robots are placed when the file gives no explicit poses.
enum class Placement : uint8_t {
  kExplicit = 0,  ///< robots.poses lists every robot
  kGrid = 1,      ///< rows centred in the arena, `spacing_m` apart
  kCircle = 2,    ///< evenly on a circle (centre, radius), facing outwards
  kRandom = 3,    ///< uniform in the arena, seeded by the scenario seed, at least min_separation_m apart
};

const char* ToString(Placement placement);

/// Timing of the synchronizer and the simulation.
struct TimingSpec {
  double radio_round_s = 0.05;   ///< alpha: one beacon per robot per round
  double app_round_s = 1.0;      ///< how long PROGRESS (the maneuver) lasts; a whole number of radio rounds >= K
  int vote_rounds = 3;           ///< K
  int silence_rounds = 6;        ///< F > K
  double duration_s = 60;        ///< simulated time
  double physics_step_s = 0.01;  ///< world integration and collision step
};

/// Every robot's own clock (docs/clocks.md). Without a `clocks` section the
/// lab keeps one perfect clock for all (enabled false).
struct ClockSpec {
  bool enabled = false;            ///< the scenario has a `clocks` section
  /// Start offset of each robot, ms in [0, radio round]: its rounds begin
  /// this much after the lab's (it boots later). Resolved: one per robot,
  /// fixed (`offset_ms`) or drawn from the seed (`offset_max_ms`).
  std::vector<double> offset_ms;
  /// Rate error of each robot's crystal, ppm (positive: fast). Resolved: one
  /// per robot, fixed (`drift_ppm`) or drawn from the seed (`drift_max_ppm`).
  std::vector<double> drift_ppm;
  double jitter_ms = 0;            ///< a beacon leaves up to this long after its boundary (uniform, seeded)
  bool alignment = true;           ///< robots align their rounds (`alignment: on|off`)
};

/// Largest |drift| a scenario may give, ppm.
inline constexpr double kMaxDriftPpm = 2000;

enum class FaultKind : uint8_t {
  kCrash = 0,  ///< the robot stops for good at `at_s` (it stays where it is, as an obstacle)
  kPause = 1,  ///< the robot's software stops at `at_s` and restarts at `until_s` (it rejoins)
  kJoin = 2,   ///< the robot is switched on at `at_s` (absent before; it joins the swarm)
  kDeaf = 3,   ///< from `at_s` to `until_s` the robot hears no beacon (it is still heard)
  kMute = 4,   ///< from `at_s` to `until_s` no robot hears the robot's beacons (it still hears)
};

/// Whether `kind` acts on the radio only (deaf, mute) rather than on the software.
constexpr bool IsRadioFault(FaultKind kind) { return kind == FaultKind::kDeaf || kind == FaultKind::kMute; }

const char* ToString(FaultKind kind);

struct FaultSpec {
  FaultKind kind = FaultKind::kCrash;
  uint16_t robot = 0;
  double at_s = 0;
  double until_s = 0;  ///< pause, deaf and mute only; > at_s
};

/// `activation:` (docs/activation.md): which robots look, compute and move
/// in each epoch. Every robot's sync::ActivationConfig is this with the
/// scenario's seed.
struct ActivationSpec {
  sync::ActivationModel model = sync::ActivationModel::kFsync;
  sync::ActivationSchedule schedule = sync::ActivationSchedule::kRandom;  ///< ssync and async
  /// Random schedule: every robot active at least once in any this many
  /// consecutive epochs; 1 .. the run's epochs (RunEpochs).
  uint16_t fair_within = 3;
  /// Scripted schedule: (epoch, robot) pairs, sorted, each epoch listed
  /// naming at least one robot; the epochs not listed activate every member.
  std::vector<sync::ScriptedActivation> script;
  /// ASYNC: the start delay and the move's extra epochs are each at most
  /// this (1 .. sync::kMaxAsyncDelayEpochs).
  uint8_t max_delay_epochs = 1;
  /// ASYNC non-rigid moves: a cut move stops once it covered this; 0 rigid.
  double min_move_m = 0;
  /// ASYNC scripted: each listed look's timing, sorted by epoch then robot.
  std::vector<sync::ScriptedCycle> cycles;
};

/// fair_within when the file gives none (or the run's epochs, if fewer).
inline constexpr int64_t kDefaultFairWithinEpochs = 3;

/// The most epochs a run of `timing` can hold (an epoch lasts at least its
/// maneuver): floor(duration_s / app_round_s), at least 1. Bounds
/// activation.fair_within and the scripted schedule's epochs.
int64_t RunEpochs(const TimingSpec& timing);

/// The app every robot runs: a built-in app ("builtin:NAME", with its
/// parameters) or a student's shared library (run by the app host, one
/// sandboxed process per robot).
struct AppSpec {
  std::string name = "builtin:idle";     ///< "builtin:NAME"; for a library the path as written
  /// A built-in app's numbers (docs/scenarios.md lists each app's), or what a
  /// library's syrofAppParameter answers (any names, at most
  /// SYROF_APP_MAX_PARAMETERS).
  std::map<std::string, double> params;
  /// The library to open, empty for a built-in app. A relative path in a
  /// file is resolved against the scenario file's folder; one on the command
  /// line (Overrides::app) against the working directory. The loader checks
  /// that it is a file; the app host checks the rest (entry symbol, ABI).
  std::string library;
  std::optional<uint32_t> cpu_budget_ms;  ///< a library's CPU time per callback; unset: the host's default
  std::optional<uint32_t> wall_cap_ms;    ///< a library's wall time per callback; unset: the host's default

  bool is_library() const { return !library.empty(); }
};

/// Whether an app name given as text names a shared library (it contains a
/// '/' or ends in ".so", as in "./libmyapp.so") rather than "builtin:NAME".
bool IsLibraryPath(std::string_view name);

/// Bounds of the library limits a scenario may set, milliseconds.
inline constexpr uint32_t kMaxCpuBudgetMs = 60000;
inline constexpr uint32_t kMaxWallCapMs = 600000;

struct Scenario {
  std::string name;         ///< the file's stem unless the file sets `name`
  std::string source;       ///< the path it was read from ("" when read from a string)
  uint64_t seed = 1;
  world::ArenaSpec arena;
  world::KindSpec omni = world::DefaultKindSpec(world::RobotKind::kOmni);
  world::KindSpec rover = world::DefaultKindSpec(world::RobotKind::kRover);
  world::KindSpec drone = world::DefaultKindSpec(world::RobotKind::kDrone);
  Placement placement = Placement::kGrid;
  std::vector<RobotSpec> robots;  ///< resolved; at least 1
  TimingSpec timing;
  sensors::SensorBankConfig sensors;  ///< noise models; its arena is set from `arena` (and arena.tag_height_m)
  world::ChannelSpec channel;
  ClockSpec clocks;
  std::vector<FaultSpec> faults;      ///< sorted by at_s, then robot
  ActivationSpec activation;          ///< FSYNC unless the file says otherwise
  AppSpec app;
  /// `inputs:`: each robot's private values by name (docs/scenarios.md,
  /// "Private inputs"), one per robot in id order, listed in the file or
  /// drawn from the seed when it was loaded. Robot i's syrofAppInput(name)
  /// answers inputs[name][i]; the other robots learn it only from i's
  /// payloads. At most SYROF_APP_MAX_INPUTS names.
  std::map<std::string, std::vector<double>> inputs;
  /// The platform's safety filter on every robot (docs/safety.md), with
  /// presence beacons for joiners and the joiners' start-disc wait.
  /// `safety: off` switches all three off, so a course can teach collisions.
  bool safety = true;
  /// `goal:`: the declarative checks the lab judges on true poses
  /// (lab/goals); empty when the file declares none (the built-in app's own
  /// goal is then reported).
  std::vector<goals::GoalCheck> goal;
  /// `message:`: what the robots' payloads mean (docs/grading.md, "The
  /// message format"), so the replay's viewer decodes them; absent when the
  /// file declares none. The grader puts its assignment's here.
  std::optional<message::MessageFormat> message;

  const world::KindSpec& kind_spec(world::RobotKind kind) const {
    if (kind == world::RobotKind::kRover) return rover;
    return kind == world::RobotKind::kDrone ? drone : omni;
  }
};

/// Command-line values that replace the file's.
struct Overrides {
  std::optional<uint64_t> seed;
  std::optional<int> robots;        ///< robot count; placement is recomputed
  std::optional<double> duration_s;
  std::optional<std::string> app;   ///< "builtin:NAME" or a library's path (IsLibraryPath)
};

/// What is wrong with a scenario, and where: lab's error value, with
/// `where` the file's path (or "<string>") and `line` and `column` 1-based,
/// 0 when the error is not at one place in the file (an override, an I/O
/// failure).
using ScenarioError = lab::Error;

/// Largest scenario file accepted, and deepest nesting of maps and lists.
inline constexpr size_t kMaxScenarioBytes = 1 << 20;
inline constexpr int kMaxScenarioDepth = 16;
/// Most robots a scenario may hold (the synchronizer's capacity).
int MaxRobots();
/// Longest run a scenario may ask for, in simulated seconds (a day).
inline constexpr double kMaxDurationS = 86400;

/// Either a scenario or the first error found.
struct LoadResult {
  std::optional<Scenario> scenario;    ///< set on success
  std::optional<ScenarioError> error;  ///< set on failure
  bool ok() const { return scenario.has_value(); }
};

/// Reads, validates and resolves a scenario file.
LoadResult LoadScenarioFile(const std::string& path, const Overrides& overrides = {});

/// The same from text; `file` names it in errors.
LoadResult LoadScenarioText(const std::string& text, const std::string& file, const Overrides& overrides = {});

}  // namespace syrof::lab::scenario
