#include "syrof/lab/replay/comparison.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <utility>

#include <fmt/format.h>

#include "syrof/base/check.h"
#include "syrof/lab/replay/reader.h"

namespace syrof::lab::replay {
namespace {

// `row` without the starts after round `last_round`; none when no start is left.
std::optional<EpochRow> StartsUpTo(const EpochRow& row, uint32_t last_round) {
  EpochRow kept = row;
  bool any = false;
  for (EpochStart& start : kept.robots) {
    if (start.started() && start.round > last_round) start = EpochStart{};
    any = any || start.started();
  }
  if (!any) return std::nullopt;
  return kept;
}

bool SameMembers(const std::shared_ptr<const MemberIds>& a, const std::shared_ptr<const MemberIds>& b) {
  if (a == b) return true;
  if (a == nullptr || b == nullptr) return false;
  return *a == *b;
}

bool SamePayloads(const EpochStart& a, const EpochStart& b) {
  if (a.payloads == b.payloads) return true;
  if (a.payloads == nullptr || b.payloads == nullptr) return false;
  return *a.payloads == *b.payloads;
}

uint8_t Differences(const EpochStart& a, const EpochStart& b, bool compare_members, bool compare_payloads) {
  if (a.start_count != b.start_count) return kStartedField;
  if (!a.started()) return 0;
  uint8_t fields = 0;
  if (a.mode != b.mode) fields |= kModeField;
  if (compare_members && !SameMembers(a.members, b.members)) {
    fields |= kMembersField;
  } else if (compare_payloads && !SamePayloads(a, b)) {
    fields |= kPayloadsField;
  }
  return fields;
}

// The rows of `table` within the common rounds, by number; counts the rest
// into `after`, `first_after`, `last_after`.
std::vector<EpochRow> RowsUpTo(const EpochTable& table, uint32_t last_round, size_t& after, int64_t& first_after,
                               int64_t& last_after) {
  std::vector<EpochRow> rows;
  for (const EpochRow& row : table.epochs) {
    if (std::optional<EpochRow> kept = StartsUpTo(row, last_round)) {
      rows.push_back(std::move(*kept));
      continue;
    }
    if (after++ == 0) first_after = row.number;
    last_after = row.number;
  }
  return rows;
}

// The true positions of a robot in two runs, bit for bit.
bool SamePosition(const RobotFrame& a, const RobotFrame& b) {
  return std::memcmp(&a.true_x_m, &b.true_x_m, sizeof a.true_x_m) == 0 &&
         std::memcmp(&a.true_y_m, &b.true_y_m, sizeof a.true_y_m) == 0;
}

}  // namespace

std::vector<uint16_t> MembersWithOtherPayloads(const EpochStart& a, const EpochStart& b) {
  std::vector<uint16_t> members;
  if (a.members == nullptr || a.payloads == nullptr || b.payloads == nullptr) return members;
  const size_t count = std::min({a.members->size(), a.payloads->size(), b.payloads->size()});
  for (size_t i = 0; i < count; ++i) {
    if ((*a.payloads)[i] != (*b.payloads)[i]) members.push_back((*a.members)[i]);
  }
  return members;
}

EpochComparison CompareEpochs(const EpochTable& a, const EpochTable& b, bool compare_payloads) {
  SYROF_CHECK(a.robot_ids == b.robot_ids);
  EpochComparison result;
  result.members_compared = a.has_maps && b.has_maps;
  result.payloads_compared = result.members_compared && compare_payloads;
  if (a.round_count == 0 || b.round_count == 0) {
    // Nothing in common: every epoch is the longer run's tail.
    result.a_epochs_after = a.epochs.size();
    result.b_epochs_after = b.epochs.size();
    if (!a.epochs.empty()) {
      result.a_first_after = a.epochs.front().number;
      result.a_last_after = a.epochs.back().number;
    }
    if (!b.epochs.empty()) {
      result.b_first_after = b.epochs.front().number;
      result.b_last_after = b.epochs.back().number;
    }
    return result;
  }
  result.any_common_round = true;
  result.last_common_round = std::min(a.last_round, b.last_round);
  const std::vector<EpochRow> rows_a =
      RowsUpTo(a, result.last_common_round, result.a_epochs_after, result.a_first_after, result.a_last_after);
  const std::vector<EpochRow> rows_b =
      RowsUpTo(b, result.last_common_round, result.b_epochs_after, result.b_first_after, result.b_last_after);

  // Merge the two lists by number; an epoch one run has no row for is a row
  // of no starts there.
  size_t next_a = 0;
  size_t next_b = 0;
  while (next_a < rows_a.size() || next_b < rows_b.size()) {
    int64_t number = 0;
    if (next_b == rows_b.size() || (next_a < rows_a.size() && rows_a[next_a].number <= rows_b[next_b].number)) {
      number = rows_a[next_a].number;
    } else {
      number = rows_b[next_b].number;
    }
    const EpochRow none{.number = number, .robots = std::vector<EpochStart>(a.robot_ids.size())};
    const bool in_a = next_a < rows_a.size() && rows_a[next_a].number == number;
    const bool in_b = next_b < rows_b.size() && rows_b[next_b].number == number;
    const EpochRow& row_a = in_a ? rows_a[next_a] : none;
    const EpochRow& row_b = in_b ? rows_b[next_b] : none;
    if (result.epochs_compared++ == 0) result.first_epoch = number;
    result.last_epoch = number;

    EpochDisagreement disagreement;
    for (size_t slot = 0; slot < a.robot_ids.size(); ++slot) {
      const uint8_t fields = Differences(row_a.robots[slot], row_b.robots[slot], result.members_compared, result.payloads_compared);
      if (fields == 0) continue;
      disagreement.robots.push_back({.robot = a.robot_ids[slot], .fields = fields});
      disagreement.fields |= fields;
    }
    if (!disagreement.robots.empty()) {
      disagreement.number = number;
      disagreement.a = row_a;
      disagreement.b = row_b;
      result.first_difference = std::move(disagreement);
      return result;
    }
    next_a += in_a ? 1 : 0;
    next_b += in_b ? 1 : 0;
  }
  return result;
}

std::vector<PositionDifference> ComparePositions(const Round& a, const Round& b, double tolerance_m) {
  std::vector<PositionDifference> differences;
  size_t next_b = 0;
  for (const RobotFrame& frame_a : a.robots) {
    while (next_b < b.robots.size() && b.robots[next_b].id < frame_a.id) ++next_b;
    if (next_b == b.robots.size()) break;
    const RobotFrame& frame_b = b.robots[next_b];
    if (frame_b.id != frame_a.id) continue;
    const double distance_m = std::hypot(static_cast<double>(frame_a.true_x_m) - frame_b.true_x_m,
                                         static_cast<double>(frame_a.true_y_m) - frame_b.true_y_m);
    if (distance_m <= tolerance_m || SamePosition(frame_a, frame_b)) continue;
    differences.push_back({.robot = frame_a.id,
                           .a_x_m = frame_a.true_x_m,
                           .a_y_m = frame_a.true_y_m,
                           .b_x_m = frame_b.true_x_m,
                           .b_y_m = frame_b.true_y_m,
                           .distance_m = distance_m});
  }
  return differences;
}

namespace {

// Set differences of the two headers' (increasing) ids.
RobotSets CompareRobotSets(const Header& a, const Header& b) {
  std::vector<uint16_t> ids_a;
  std::vector<uint16_t> ids_b;
  for (const RobotInfo& robot : a.robots) ids_a.push_back(robot.id);
  for (const RobotInfo& robot : b.robots) ids_b.push_back(robot.id);
  RobotSets sets;
  std::set_difference(ids_a.begin(), ids_a.end(), ids_b.begin(), ids_b.end(), std::back_inserter(sets.only_a));
  std::set_difference(ids_b.begin(), ids_b.end(), ids_a.begin(), ids_a.end(), std::back_inserter(sets.only_b));
  return sets;
}

// One file being read: its reader, its table being built, its next round.
struct Side {
  Side(std::istream& in, ReplaySide& out, size_t max_cells) : reader(in), result(out), max_table_cells(max_cells) {
    if (reader.ReadHeader(result.header)) {
      result.version = reader.version();
      builder.emplace(result.header, result.version, max_cells);
    } else {
      Finish();
    }
  }

  bool header_read() const { return builder.has_value(); }
  void Advance() { have_round = builder && reader.Next(round); }
  // A run whose epochs overflow the table is read no further.
  void AddAndAdvance() {
    if (builder->Add(round)) {
      Advance();
      return;
    }
    have_round = false;
    full_at = Error{.where = fmt::format("round {}", round.index),
                    .message = fmt::format("the run's epochs need more than {} entries (epochs x {} robots) to "
                                           "compare; a real run needs far fewer",
                                           max_table_cells, result.header.robots.size())};
  }
  void Finish() {
    if (builder) result.table = std::move(*builder).Finish();
    if (full_at) {
      result.error = std::move(full_at);
    } else if (!reader.complete()) {
      result.error = reader.error();
      result.truncated = reader.truncated();
    }
  }

  Reader reader;
  ReplaySide& result;
  std::optional<EpochTableBuilder> builder;
  Round round;
  bool have_round = false;
  const size_t max_table_cells;
  std::optional<Error> full_at;  // where the table found itself full
};

}  // namespace

ReplayComparison CompareReplays(std::istream& a, std::istream& b, const ComparisonOptions& options) {
  ReplayComparison result;
  Side side_a(a, result.a, options.max_epoch_table_cells);
  Side side_b(b, result.b, options.max_epoch_table_cells);
  if (side_a.header_read() && side_b.header_read()) result.robots = CompareRobotSets(result.a.header, result.b.header);
  const bool compare_positions = options.pose_tolerance_m.has_value() && side_a.header_read() &&
                                 side_b.header_read() && result.robots.same();
  side_a.Advance();
  side_b.Advance();
  while (side_a.have_round || side_b.have_round) {
    if (side_a.have_round && side_b.have_round && side_a.round.index == side_b.round.index) {
      if (compare_positions && !result.first_position_difference) {
        ++result.rounds_position_compared;
        std::vector<PositionDifference> differences =
            ComparePositions(side_a.round, side_b.round, *options.pose_tolerance_m);
        if (!differences.empty()) {
          result.first_position_difference = PositionDisagreement{.round = side_a.round.index,
                                                                  .a_time_ns = side_a.round.time_ns,
                                                                  .b_time_ns = side_b.round.time_ns,
                                                                  .robots = std::move(differences)};
        }
      }
      side_a.AddAndAdvance();
      side_b.AddAndAdvance();
    } else if (side_a.have_round && (!side_b.have_round || side_a.round.index < side_b.round.index)) {
      side_a.AddAndAdvance();
    } else {
      side_b.AddAndAdvance();
    }
  }
  if (side_a.header_read()) side_a.Finish();
  if (side_b.header_read()) side_b.Finish();
  if (result.comparable()) result.epochs = CompareEpochs(result.a.table, result.b.table, options.compare_payloads);
  return result;
}

}  // namespace syrof::lab::replay
