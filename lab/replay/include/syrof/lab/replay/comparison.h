// Do two runs agree? The same scenario and seed in the lab, the DDS swarm and
// the firmware swarm must give the same epochs, modes and members; this
// compares two replays' epoch tables (epoch_table.h) and, on request, the
// apps' payloads in those maps and the robots' true positions round by round. `syrof compare` prints the result
// (docs/replay.md, "Comparing two runs").
//
//   std::ifstream a(path_a, std::ios::binary), b(path_b, std::ios::binary);
//   ReplayComparison result = CompareReplays(a, b, {.pose_tolerance_m = 0.01});
//   if (result.a.error || result.b.error) ...;       // a file is unreadable
//   else if (!result.robots.same()) ...;             // different swarms
//   else if (result.epochs.first_difference) ...;    // they disagree there
//
// CompareEpochs and ComparePositions are pure; CompareReplays reads the two
// streams side by side, one round of each at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <optional>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/replay/epoch_table.h"
#include "syrof/lab/replay/replay.h"

namespace syrof::lab::replay {

/// What can differ for one robot in one epoch; bits of RobotDifference::fields.
enum EpochField : uint8_t {
  kStartedField = 1,  ///< started it in one run and not the other, or a different number of times
  kModeField = 2,     ///< started it in both, in different modes
  kMembersField = 4,  ///< started it in both, with maps of different members (both runs record maps)
  /// started it in both with maps of the same members, and some member's
  /// payload differs (compared on request: ComparisonOptions::compare_payloads)
  kPayloadsField = 8,
};

/// One robot that differs in an epoch.
struct RobotDifference {
  uint16_t robot = 0;  ///< its id
  uint8_t fields = 0;  ///< EpochField bits, never 0
};

/// The first epoch where two runs differ, with both sides' rows.
struct EpochDisagreement {
  int64_t number = 0;  ///< unwrapped (EpochRow::number)
  /// Each side's row of the epoch, restricted to the rounds both runs hold
  /// (a start after them counts as none); a row of no starts where that run
  /// has no robot starting the epoch.
  EpochRow a;
  EpochRow b;
  std::vector<RobotDifference> robots;  ///< the robots that differ, by increasing id
  uint8_t fields = 0;                   ///< the union of the robots' fields
};

/// The outcome of comparing two epoch tables of the same robots.
struct EpochComparison {
  /// Rounds both runs hold: those up to the shorter run's last round. Only
  /// starts in these rounds are compared (a run cut a round earlier is not
  /// a disagreement). False when a run has no round.
  bool any_common_round = false;
  uint32_t last_common_round = 0;  ///< when any_common_round
  /// The epochs compared: every number some run started within the common
  /// rounds, from the smallest to the largest (EpochRow::number).
  size_t epochs_compared = 0;
  int64_t first_epoch = 0;  ///< when epochs_compared > 0
  int64_t last_epoch = 0;   ///< when epochs_compared > 0
  /// Members are compared only when both files record maps (version 3).
  bool members_compared = false;
  /// Payloads too: on request, and when members are compared.
  bool payloads_compared = false;
  /// Epochs each run started only after the common rounds (the longer run's
  /// tail), not compared: how many, and the range of their numbers.
  size_t a_epochs_after = 0;
  size_t b_epochs_after = 0;
  int64_t a_first_after = 0, a_last_after = 0;  ///< when a_epochs_after > 0
  int64_t b_first_after = 0, b_last_after = 0;  ///< when b_epochs_after > 0
  /// The first epoch (by number) where the started set, a robot's mode or a
  /// robot's members differ; none when the runs agree.
  std::optional<EpochDisagreement> first_difference;
};

/// Compares two tables epoch by epoch, up to the shorter run's last round;
/// with `compare_payloads`, also the payloads of the maps' members (when both
/// tables hold maps). Precondition (checked): the tables have the same robot ids.
EpochComparison CompareEpochs(const EpochTable& a, const EpochTable& b, bool compare_payloads = false);

/// The members (ids, increasing) whose payloads differ between `a` and `b`,
/// two starts with the same members; empty when either holds no payloads.
std::vector<uint16_t> MembersWithOtherPayloads(const EpochStart& a, const EpochStart& b);

/// One robot whose true positions in the same round of two runs are too far
/// apart.
struct PositionDifference {
  uint16_t robot = 0;
  float a_x_m = 0, a_y_m = 0;  ///< run A's true position, metres, arena frame
  float b_x_m = 0, b_y_m = 0;  ///< run B's
  double distance_m = 0;       ///< between the two; NaN when a coordinate is not a number
};

/// The robots (by increasing id) whose true positions in `a` and `b`, the
/// same round of two runs, are more than `tolerance_m` apart; a robot
/// missing from either round's frames is skipped. A NaN coordinate on one
/// side only counts as too far.
std::vector<PositionDifference> ComparePositions(const Round& a, const Round& b, double tolerance_m);

/// The first round where positions differ.
struct PositionDisagreement {
  uint32_t round = 0;     ///< the round's index
  int64_t a_time_ns = 0;  ///< the round's time in each run
  int64_t b_time_ns = 0;
  std::vector<PositionDifference> robots;  ///< never empty
};

/// One run as CompareReplays read it.
struct ReplaySide {
  Header header;             ///< valid when the header was read
  uint16_t version = 0;      ///< the file's format version (0 when the header was not read)
  EpochTable table;          ///< the rounds read
  /// Why the file could not be read whole: unreadable, not a replay,
  /// damaged, or cut short (then `truncated`). Errors are the Reader's.
  std::optional<Error> error;
  bool truncated = false;
};

/// The robots of the two headers.
struct RobotSets {
  std::vector<uint16_t> only_a;  ///< ids in A's header and not B's
  std::vector<uint16_t> only_b;  ///< ids in B's header and not A's
  bool same() const { return only_a.empty() && only_b.empty(); }
};

struct ComparisonOptions {
  /// Compare true positions round by round, allowing this many metres (>= 0);
  /// none: positions are not compared.
  std::optional<double> pose_tolerance_m;
  /// Also compare, epoch by epoch, the payloads of the members of the maps
  /// robots start epochs with: the state the apps share (kPayloadsField).
  /// Off by default: a payload the app computes from estimates (gather's
  /// centre, in millimetres) can differ by a unit between runtimes whose
  /// epochs agree.
  bool compare_payloads = false;
  /// Most entries of each run's epoch table; a run that needs more is an
  /// error of its side (EpochTableBuilder).
  size_t max_epoch_table_cells = kMaxEpochTableCells;
};

struct ReplayComparison {
  ReplaySide a;
  ReplaySide b;
  RobotSets robots;  ///< when both headers were read
  /// When both files were read whole and have the same robots.
  EpochComparison epochs;
  /// With a pose tolerance: rounds (same index in both runs) whose positions
  /// were compared, and the first one that differs. Comparison stops there.
  uint32_t rounds_position_compared = 0;
  std::optional<PositionDisagreement> first_position_difference;

  /// Both files read whole, and their robots are the same.
  bool comparable() const { return !a.error && !b.error && robots.same(); }
};

/// Reads two replays side by side (rounds matched by index) and compares
/// them. A file that cannot be read whole leaves its side's `error` set and
/// nothing is compared (the other file is still read to its end, so both
/// problems are known). Files with different robot sets are read but not
/// compared.
ReplayComparison CompareReplays(std::istream& a, std::istream& b, const ComparisonOptions& options);

}  // namespace syrof::lab::replay
