// What a run's page says first: how the run went (docs/viewer.md, "The
// verdict"), and the goal's target the arena draws.
//
// The verdict is made from the run's metrics (lab/metrics: the goal, P3,
// the app's agreement, collisions, app faults) and the beacons a scripted
// channel lost (the replay's BEACON_LOST events: what a search's
// counterexample lost). `syrof run --html` and `syrof search` hand the
// metrics they computed; `syrof view` reads the run's metrics.json beside
// the replay (ReadVerdictMetrics: an untrusted file, every field it uses
// checked). Without metrics the page judges what the replay alone shows
// (collisions, app faults) and says the goal was not judged.
#pragma once

#include <cstdint>
#include <istream>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::view {

/// How the run went, in increasing order of trouble.
enum class VerdictState : uint8_t {
  kOk = 0,        ///< goal met, nothing broken
  kUnjudged = 1,  ///< no metrics: nothing broken that the replay shows, goal unknown
  kMissed = 2,    ///< goal missed, nothing broken
  kBroken = 3,    ///< P3, the app's agreement, a collision or the app broke
};

/// "ok", "unjudged", "missed", "broken": the banner's class.
std::string_view ToString(VerdictState state);

/// One line under the banner's headline: a property and what became of it.
struct VerdictLine {
  std::string topic;  ///< "goal", "collisions", "P3", "agreement", "app", "lost beacons"
  bool ok = true;     ///< false: this line is why the run is not ok
  std::string text;   ///< a sentence a student can act on
};

struct Verdict {
  VerdictState state = VerdictState::kUnjudged;
  std::string headline;  ///< "Goal met: ...", "Goal missed: ...", "BROKEN: agreement split in epoch 3: ..."
  std::vector<VerdictLine> lines;
};

/// A beacon a scripted channel lost: `from`'s beacon of `round` did not
/// reach `to` (a replay's BEACON_LOST event).
struct LostBeaconSeen {
  int64_t round = 0;
  uint16_t from = 0;
  uint16_t to = 0;
};

/// What the replay itself shows of the run's troubles.
struct ReplayFacts {
  int64_t collisions = 0;
  int64_t app_faults = 0;
  int64_t join_waits = 0;
  std::vector<LostBeaconSeen> lost;  ///< in the replay's order
};

/// The verdict of a run from its metrics and the replay's lost beacons.
Verdict VerdictOf(const metrics::Metrics& metrics, const ReplayFacts& facts);
/// The verdict of a replay alone (no metrics): broken by what it shows,
/// else unjudged.
Verdict VerdictOfReplay(const ReplayFacts& facts);

/// The page's form: {"state", "headline", "lines": [[topic, ok, text]...]}.
nlohmann::json VerdictData(const Verdict& verdict);

/// The metrics fields a verdict uses, from an untrusted metrics.json
/// (`name` names it in errors). A missing or mistyped field is an error
/// naming its key path ("metrics.json: goal.reached: expected true or
/// false"); fields the verdict does not use are not looked at.
std::optional<metrics::Metrics> ReadVerdictMetrics(std::istream& in, const std::string& name, Error& error);

/// The goal's target as the arena draws it, for `scenario` with
/// `goal_robots` robots running at the end (a built-in app's formation
/// depends on their number). A list of shapes, metres, arena frame:
///   {"shape": "ring", "name", "x", "y", "r_min", "r_max"}  a circle (r_min == r_max) or an annulus
///   {"shape": "free_ring", "name", "r_min", "r_max"}       the same, centred where the robots are
///   {"shape": "points", "name", "r", "points": [[x, y, id or -1]...]}  slots with their tolerance
///   {"shape": "rect", "name", "x0", "y0", "x1", "y1"}      a coverage area
///   {"shape": "none", "name", "why"}                       a check with no place in the arena (line, shape)
/// Empty for a goal with nothing to draw (idle).
nlohmann::json GoalTargets(const scenario::Scenario& scenario, size_t goal_robots);

}  // namespace syrof::lab::view
