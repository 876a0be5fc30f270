#include "compare_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "exit_status.h"
#include "syrof/lab/replay/comparison.h"
#include "syrof/wire/beacon.h"

namespace syrof::cli {
namespace {
// The subcommands compile as one unit (cli/CMakeLists.txt): this file's
// helpers live in a namespace of their own.
namespace compare_text {

namespace replay = lab::replay;
namespace fs = std::filesystem;

// Above this many robots the epoch table shows only the robots that differ.
constexpr size_t kMaxRobotsShownWhole = 40;

// "5"; past a wrap of the 16-bit epoch, the wire number and the wraps.
std::string EpochLabel(int64_t number) {
  if (number >= 0 && number <= 0xFFFF) return fmt::format("{}", number);
  const auto wire_epoch = static_cast<uint16_t>(number);
  if (number > 0) {
    const int64_t wraps = number >> 16;
    return fmt::format("{} (after {} wrap{} of the 16-bit number)", wire_epoch, wraps, wraps == 1 ? "" : "s");
  }
  return fmt::format("{} (before the file's first epoch, across a wrap)", wire_epoch);
}

// "3 to 7", or "3" alone.
std::string NumberRange(int64_t first, int64_t last) {
  if (first == last) return EpochLabel(first);
  return fmt::format("{} to {}", EpochLabel(first), EpochLabel(last));
}

// "epochs 3 to 7", or "epoch 3".
std::string EpochRange(int64_t first, int64_t last) {
  return fmt::format("{} {}", first == last ? "epoch" : "epochs", NumberRange(first, last));
}

// "0-3 5 7-9": ids in increasing order, runs of three or more as ranges.
std::string IdList(const std::vector<uint16_t>& ids) {
  if (ids.empty()) return "none";
  std::string text;
  for (size_t first = 0; first < ids.size();) {
    size_t last = first;
    while (last + 1 < ids.size() && ids[last + 1] == ids[last] + 1) ++last;
    if (!text.empty()) text += ' ';
    if (last - first >= 2) {
      text += fmt::format("{}-{}", ids[first], ids[last]);
    } else {
      for (size_t index = first; index <= last; ++index) text += fmt::format("{}{}", index == first ? "" : " ", ids[index]);
    }
    first = last + 1;
  }
  return text;
}

// "a, b, c".
std::string Join(const std::vector<std::string>& parts) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : ", ") + part;
  return text;
}

std::string RobotWord(size_t count) { return count == 1 ? "robot" : "robots"; }

const char* ModeName(uint8_t mode) { return wire::ToString(static_cast<wire::Mode>(mode)); }

std::string StartedText(const replay::EpochStart& start) {
  if (!start.started()) return "no";
  if (start.start_count == 1) return fmt::format("round {}", start.round);
  return fmt::format("round {} ({} times)", start.round, start.start_count);
}

std::string MembersText(const replay::EpochStart& start) {
  if (!start.started()) return "";
  if (start.members == nullptr) return "(no map)";
  return IdList(*start.members);
}

std::string FieldsText(uint8_t fields) {
  std::vector<std::string> names;
  if ((fields & replay::kStartedField) != 0) names.emplace_back("started");
  if ((fields & replay::kModeField) != 0) names.emplace_back("mode");
  if ((fields & replay::kMembersField) != 0) names.emplace_back("members");
  if ((fields & replay::kPayloadsField) != 0) names.emplace_back("payloads");
  return Join(names);
}

// "mode (robots 1 2), members (robot 4)": each field with the robots it differs for.
std::string WhatDiffers(const replay::EpochDisagreement& disagreement) {
  std::vector<std::string> parts;
  for (const uint8_t field :
       {replay::kStartedField, replay::kModeField, replay::kMembersField, replay::kPayloadsField}) {
    std::vector<uint16_t> robots;
    for (const replay::RobotDifference& robot : disagreement.robots) {
      if ((robot.fields & field) != 0) robots.push_back(robot.robot);
    }
    if (!robots.empty()) parts.push_back(fmt::format("{} ({} {})", FieldsText(field), RobotWord(robots.size()), IdList(robots)));
  }
  return Join(parts);
}

// Seconds with all nine digits of the nanoseconds, as `syrof replay` prints them.
std::string Seconds(int64_t time_ns) {
  const bool negative = time_ns < 0;
  const uint64_t magnitude = negative ? 0 - static_cast<uint64_t>(time_ns) : static_cast<uint64_t>(time_ns);
  return fmt::format("{}{}.{:09}s", negative ? "-" : "", magnitude / 1000000000u, magnitude % 1000000000u);
}

// Rows of text printed as aligned columns, two spaces apart.
void PrintColumns(const std::vector<std::vector<std::string>>& rows, std::ostream& out) {
  std::vector<size_t> widths;
  for (const auto& row : rows) {
    widths.resize(std::max(widths.size(), row.size()));
    for (size_t column = 0; column < row.size(); ++column) widths[column] = std::max(widths[column], row[column].size());
  }
  for (const auto& row : rows) {
    std::string line;
    for (size_t column = 0; column < row.size(); ++column) {
      line += row[column];
      if (column + 1 < row.size()) line += std::string(widths[column] - row[column].size() + 2, ' ');
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out << line << '\n';
  }
}

// "47 1a 00" (hex bytes), or "none".
std::string PayloadText(const std::vector<uint8_t>& payload) {
  if (payload.empty()) return "none";
  std::string text;
  for (const uint8_t byte : payload) text += fmt::format("{}{:02x}", text.empty() ? "" : " ", byte);
  return text;
}

// For each robot whose map's payloads differ, the members whose payloads
// differ and both runs' bytes: a line a member, the first robot's map whole
// and, for the others, the members only (a COOPERATIVE epoch's maps are one).
void PrintPayloads(const replay::EpochDisagreement& disagreement, const std::vector<uint16_t>& robot_ids,
                   std::ostream& out) {
  bool first = true;
  for (const replay::RobotDifference& robot : disagreement.robots) {
    if ((robot.fields & replay::kPayloadsField) == 0) continue;
    const auto id = std::lower_bound(robot_ids.begin(), robot_ids.end(), robot.robot);
    const auto slot = static_cast<size_t>(id - robot_ids.begin());
    const replay::EpochStart& a = disagreement.a.robots[slot];
    const replay::EpochStart& b = disagreement.b.robots[slot];
    const std::vector<uint16_t> members = replay::MembersWithOtherPayloads(a, b);
    if (!first) {
      out << fmt::format("robot {}'s map: the payloads of member{} {} differ\n", robot.robot,
                         members.size() == 1 ? "" : "s", IdList(members));
      continue;
    }
    first = false;
    out << fmt::format("\npayloads that differ in robot {}'s map of epoch {} (bytes the members' apps sent):\n",
                       robot.robot, EpochLabel(disagreement.number));
    std::vector<std::vector<std::string>> rows;
    rows.push_back({"member", "A: payload", "B: payload"});
    for (const uint16_t member : members) {
      const auto at = std::lower_bound(a.members->begin(), a.members->end(), member);
      const auto index = static_cast<size_t>(at - a.members->begin());
      rows.push_back({fmt::format("{}", member), PayloadText((*a.payloads)[index]), PayloadText((*b.payloads)[index])});
    }
    PrintColumns(rows, out);
  }
}

// Both sides of the first epoch that differs, one robot per line.
void PrintEpochTable(const replay::EpochComparison& comparison, const std::vector<uint16_t>& robot_ids,
                     std::ostream& out) {
  const replay::EpochDisagreement& disagreement = *comparison.first_difference;
  std::vector<std::vector<std::string>> rows;
  rows.push_back({"", "", "A:", "", "", "B:", "", "", ""});
  rows.push_back({"", "robot", "started", "mode", "members", "started", "mode", "members", "differs"});
  const bool whole = robot_ids.size() <= kMaxRobotsShownWhole;
  size_t next_difference = 0;
  for (size_t slot = 0; slot < robot_ids.size(); ++slot) {
    uint8_t fields = 0;
    if (next_difference < disagreement.robots.size() && disagreement.robots[next_difference].robot == robot_ids[slot]) {
      fields = disagreement.robots[next_difference++].fields;
    }
    if (fields == 0 && !whole) continue;
    const replay::EpochStart& a = disagreement.a.robots[slot];
    const replay::EpochStart& b = disagreement.b.robots[slot];
    rows.push_back({fields != 0 ? "*" : "", fmt::format("{}", robot_ids[slot]), StartedText(a),
                    a.started() ? ModeName(a.mode) : "", MembersText(a), StartedText(b),
                    b.started() ? ModeName(b.mode) : "", MembersText(b), FieldsText(fields)});
  }
  out << fmt::format("\nepoch {} in both runs (started: the round the robot started it in; members: of its map):\n",
                     EpochLabel(disagreement.number));
  PrintColumns(rows, out);
  if (!whole) {
    const size_t hidden = robot_ids.size() - disagreement.robots.size();
    out << fmt::format("({} {} that agree not shown)\n", hidden, RobotWord(hidden));
  }
  PrintPayloads(disagreement, robot_ids, out);
}

void PrintPositionTable(const replay::PositionDisagreement& disagreement, std::ostream& out) {
  std::vector<std::vector<std::string>> rows;
  rows.push_back({"robot", "A: x m", "y m", "B: x m", "y m", "apart m"});
  for (const replay::PositionDifference& robot : disagreement.robots) {
    rows.push_back({fmt::format("{}", robot.robot), fmt::format("{:.4f}", robot.a_x_m), fmt::format("{:.4f}", robot.a_y_m),
                    fmt::format("{:.4f}", robot.b_x_m), fmt::format("{:.4f}", robot.b_y_m),
                    fmt::format("{:.4g}", robot.distance_m)});
  }
  out << '\n';
  PrintColumns(rows, out);
}

// What the two runs are, when it is not the same: a different scenario,
// seed, app, radio round, message format or private inputs, a run longer
// than the other, a format without maps. None of these alone is a
// disagreement.
std::vector<std::string> Notes(const replay::ReplayComparison& result) {
  const replay::Header& a = result.a.header;
  const replay::Header& b = result.b.header;
  std::vector<std::string> notes;
  if (a.scenario_name != b.scenario_name) {
    notes.push_back(fmt::format("different scenarios: A '{}', B '{}'", a.scenario_name, b.scenario_name));
  }
  if (a.seed != b.seed) notes.push_back(fmt::format("different seeds: A {}, B {}", a.seed, b.seed));
  if (a.app_name != b.app_name) notes.push_back(fmt::format("different apps: A '{}', B '{}'", a.app_name, b.app_name));
  if (a.radio_round_ns != b.radio_round_ns) {
    notes.push_back(fmt::format("different radio rounds: A {} ns, B {} ns (rounds of one index are not the same time)",
                                a.radio_round_ns, b.radio_round_ns));
  }
  // Private inputs and message formats (version 4 on): runs with other
  // inputs are other runs, whatever their epochs say.
  if (a.message != b.message) {
    const auto text = [](const replay::Header& header) {
      return header.message ? header.message->ToString() : std::string("not recorded");
    };
    notes.push_back(fmt::format("different message formats: A {}, B {}", text(a), text(b)));
  }
  std::string inputs_differ;
  for (size_t i = 0; i < std::min(a.robots.size(), b.robots.size()); ++i) {
    if (a.robots[i].id == b.robots[i].id && a.robots[i].inputs != b.robots[i].inputs) {
      inputs_differ += (inputs_differ.empty() ? "" : " ") + std::to_string(a.robots[i].id);
    }
  }
  if (!inputs_differ.empty()) {
    notes.push_back(fmt::format("different private inputs for robot{} {} (syrof replay FILE --summary shows them)",
                                inputs_differ.find(' ') == std::string::npos ? "" : "s", inputs_differ));
  }
  if (!result.robots.same()) return notes;
  const replay::EpochTable& table_a = result.a.table;
  const replay::EpochTable& table_b = result.b.table;
  const replay::EpochComparison& epochs = result.epochs;
  if (table_a.round_count == 0 || table_b.round_count == 0) {
    for (const auto* side : {&result.a, &result.b}) {
      if (side->table.round_count == 0) notes.push_back(fmt::format("{} holds no round", side == &result.a ? "A" : "B"));
    }
  } else if (table_a.last_round != table_b.last_round) {
    const bool a_longer = table_a.last_round > table_b.last_round;
    std::string tail;
    if ((a_longer ? epochs.a_epochs_after : epochs.b_epochs_after) > 0) {
      tail = fmt::format("; {}'s later {} not compared", a_longer ? "A" : "B",
                         a_longer ? EpochRange(epochs.a_first_after, epochs.a_last_after)
                                  : EpochRange(epochs.b_first_after, epochs.b_last_after));
    }
    notes.push_back(fmt::format("{} is longer: it ends at round {}, {} at round {}; compared the epochs started up to round {}{}",
                                a_longer ? "A" : "B", std::max(table_a.last_round, table_b.last_round),
                                a_longer ? "B" : "A", std::min(table_a.last_round, table_b.last_round),
                                epochs.last_common_round, tail));
  }
  if (!epochs.members_compared) {
    for (const auto* side : {&result.a, &result.b}) {
      if (!side->table.has_maps) {
        notes.push_back(fmt::format("members not compared: {} is format version {}, which records no maps",
                                    side == &result.a ? "A" : "B", side->version));
      }
    }
  }
  return notes;
}

// Why `path` (from the command-line argument `argument`) cannot be read,
// or nothing when it is open in `in`.
std::optional<lab::Error> OpenProblem(const std::string& argument, const std::string& path, std::ifstream& in) {
  auto problem = [](std::string message) {
    return lab::Error{.where = "", .line = 0, .column = 0, .message = std::move(message)};
  };
  std::error_code error;
  if (!fs::exists(argument, error)) return problem(fmt::format("'{}': no such file or folder", argument));
  if (path != argument && !fs::exists(path, error)) {
    return problem(fmt::format("'{}' is a folder without a replay file ({} does not exist; `syrof run --out DIR` "
                               "writes DIR/replay unless run with --no-replay)",
                               argument, path));
  }
  if (fs::is_directory(path, error)) return problem(fmt::format("'{}' is a folder, not a replay file", path));
  in.open(path, std::ios::binary);
  if (!in) return problem(fmt::format("cannot open '{}': {}", path, std::strerror(errno)));
  return std::nullopt;
}

CLI::Validator ToleranceValidator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        const char* end = text.data() + text.size();
        const auto [rest, error] = std::from_chars(text.data(), end, value);
        if (error != std::errc() || rest != end || !std::isfinite(value) || value < 0) {
          return fmt::format("must be a distance in metres, 0 or more, not '{}'", text);
        }
        return {};
      },
      "", "METRES");
}

int Compare(const CompareOptions& options, std::ostream& out, std::ostream& err) {
  const std::string path_a = ReplayPathOf(options.run_a);
  const std::string path_b = ReplayPathOf(options.run_b);
  std::ifstream in_a;
  std::ifstream in_b;
  const std::optional<lab::Error> problem_a = OpenProblem(options.run_a, path_a, in_a);
  const std::optional<lab::Error> problem_b = OpenProblem(options.run_b, path_b, in_b);
  if (problem_a) fmt::print(err, "syrof compare: A: {}\n", problem_a->ToString());
  if (problem_b) fmt::print(err, "syrof compare: B: {}\n", problem_b->ToString());
  if (problem_a || problem_b) return kBadInput;

  const replay::ReplayComparison result = replay::CompareReplays(
      in_a, in_b, {.pose_tolerance_m = options.pose_tolerance_m, .compare_payloads = options.payloads});
  if (result.a.error) fmt::print(err, "syrof compare: A: {}: {}\n", path_a, result.a.error->ToString());
  if (result.b.error) fmt::print(err, "syrof compare: B: {}: {}\n", path_b, result.b.error->ToString());
  if (result.a.error || result.b.error) return kBadInput;

  const std::string names = fmt::format("A {} and B {}", path_a, path_b);
  const std::vector<std::string> notes = Notes(result);
  const auto print_notes = [&] {
    for (const std::string& note : notes) fmt::print(out, "note: {}\n", note);
  };
  if (!result.robots.same()) {
    fmt::print(out, "syrof compare: {} are runs of different robots, not compared: only in A: {}; only in B: {}\n",
               names, IdList(result.robots.only_a), IdList(result.robots.only_b));
    print_notes();
    return kRunsDiffer;
  }

  const replay::EpochComparison& epochs = result.epochs;
  const size_t robots = result.a.header.robots.size();
  const std::string compared = epochs.payloads_compared  ? "starts, modes, members and payloads"
                               : epochs.members_compared ? "starts, modes and members"
                                                         : "starts and modes";
  std::string positions;
  if (options.pose_tolerance_m && !result.first_position_difference) {
    positions = result.rounds_position_compared == 0
                    ? "; positions not compared (no round index in both runs)"
                    : fmt::format("; true positions within {} m in {} rounds", *options.pose_tolerance_m,
                                  result.rounds_position_compared);
  }
  if (!epochs.first_difference && !result.first_position_difference) {
    if (epochs.epochs_compared == 0) {
      fmt::print(out, "syrof compare: {} agree: no epoch started in the rounds both hold ({} {}){}\n", names, robots,
                 RobotWord(robots), positions);
    } else {
      fmt::print(out, "syrof compare: {} agree: {} {} ({}) of {} {}, the same {}{}\n", names, epochs.epochs_compared,
                 epochs.epochs_compared == 1 ? "epoch" : "epochs", NumberRange(epochs.first_epoch, epochs.last_epoch),
                 robots, RobotWord(robots), compared, positions);
    }
    print_notes();
    return kOk;
  }

  if (epochs.first_difference) {
    const replay::EpochDisagreement& first = *epochs.first_difference;
    std::string agreed = "the first epoch compared";
    if (first.number - 1 > epochs.first_epoch) {
      agreed = fmt::format("epochs {} agree", NumberRange(epochs.first_epoch, first.number - 1));
    } else if (first.number - 1 == epochs.first_epoch) {
      agreed = fmt::format("epoch {} agrees", EpochLabel(epochs.first_epoch));
    }
    fmt::print(out, "syrof compare: {} differ at epoch {} ({}): {}\n", names, EpochLabel(first.number), agreed,
               WhatDiffers(first));
  } else {
    fmt::print(out, "syrof compare: {} agree on {} {} ({}) of {} {}, the same {}, but not on positions\n", names,
               epochs.epochs_compared, epochs.epochs_compared == 1 ? "epoch" : "epochs",
               NumberRange(epochs.first_epoch, epochs.last_epoch), robots, RobotWord(robots), compared);
  }
  if (result.first_position_difference) {
    const replay::PositionDisagreement& first = *result.first_position_difference;
    fmt::print(out, "syrof compare: true positions differ at round {} (A t={}, B t={}): {} of {} {} more than {} m apart\n",
               first.round, Seconds(first.a_time_ns), Seconds(first.b_time_ns), first.robots.size(), robots,
               RobotWord(robots), *options.pose_tolerance_m);
  }
  print_notes();
  if (epochs.first_difference) PrintEpochTable(epochs, result.a.table.robot_ids, out);
  if (result.first_position_difference) PrintPositionTable(*result.first_position_difference, out);
  return kRunsDiffer;
}

}  // namespace compare_text
}  // namespace

std::string ReplayPathOf(const std::string& argument) {
  std::error_code error;
  if (std::filesystem::is_directory(argument, error)) return (std::filesystem::path(argument) / "replay").string();
  return argument;
}

CLI::App* SetupCompareCommand(CLI::App& app, CompareOptions& options) {
  CLI::App* command = app.add_subcommand(
      "compare",
      "Do two runs agree? The epochs each robot started, their modes and members (and, with --payloads, "
      "the apps' payloads in those maps; with --pose-tolerance-m, the robots' true positions); the first "
      "difference as a table");
  command->add_option("RUN_A", options.run_a, "An output folder (syrof run/swarm --out) or a replay file")->required();
  command->add_option("RUN_B", options.run_b, "The run to compare it with, the same way")->required();
  command->add_flag("--payloads", options.payloads,
                    "Also compare the payloads (sendMessageData's bytes) of the members of the map each robot "
                    "started each epoch with: the state the apps share");
  command
      ->add_option("--pose-tolerance-m", options.pose_tolerance_m,
                   "Also compare every robot's true position in each round both runs hold; report the first round "
                   "where one differs by more than this many metres")
      ->type_name("METRES")
      ->check(compare_text::ToleranceValidator());
  command->footer(
      "Exit status: 0 the runs agree, 1 they differ (or their robots differ), 2 a run cannot be read "
      "(missing, not a replay, damaged, cut short) or an internal error. docs/replay.md, \"Comparing two runs\".");
  return command;
}

int RunCompareCommand(const CompareOptions& options, std::ostream& out, std::ostream& err) {
  try {
    const int status = compare_text::Compare(options, out, err);
    out.flush();
    if (!out) {
      err << "syrof compare: writing the output failed\n";
      return kBadInput;  // compare's 2 is "trouble" (exit_status.h)
    }
    return status;
  } catch (const std::exception& error) {
    err << fmt::format("syrof compare: internal error: {}\n", error.what());
    return kBadInput;  // compare's 2 is "trouble": 1 means the runs differ
  }
}

}  // namespace syrof::cli
