// Timing, sensor noise, the radio channel and the faults.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>
#include <span>
#include <string_view>

#include "schema.h"
#include "text_checks.h"
#include "syrof/base/split_mix64.h"
#include "value_reader.h"
#include "yaml_tree.h"

namespace syrof::lab::scenario {
namespace {

constexpr NumberRange kProbability{0, 1};
constexpr NumberRange kTimeOfRun{0, kMaxDurationS};  // a day of simulated time is plenty
constexpr double kWholeTolerance = 1e-6;     // relative, for "a whole number of rounds"

bool IsWholeMultiple(double value, double unit) {
  const double ratio = value / unit;
  return std::abs(ratio - std::round(ratio)) <= kWholeTolerance * std::max(1.0, ratio);
}

// The first of `keys` present in `map`, for rules that tie several keys:
// the error goes to a value the user wrote.
const YamlNode& Blame(const YamlNode& map, std::initializer_list<std::string_view> keys, std::string& path) {
  for (std::string_view key : keys) {
    if (const YamlNode* node = map.Find(key)) {
      path = JoinPath("timing", key);
      return *node;
    }
  }
  path = "timing";
  return map;
}

// The synchronizer's limits (sync::kMaxSilenceRounds, runtime::kMaxManeuverRounds),
// restated here: the scenario layer sits below core/sync. They keep a
// legitimate epoch far shorter than the stay after which a robot rejoins
// (docs/protocol.md, "Epoch numbers").
constexpr int64_t kMaxSilenceRounds = 4096;
constexpr int64_t kMaxAppRoundRounds = 4096;

bool CheckTimingRules(const YamlNode& node, const TimingSpec& timing, Diagnostics& diagnostics) {
  std::string path;
  if (timing.silence_rounds <= timing.vote_rounds) {
    const YamlNode& at = Blame(node, {"silence_rounds", "vote_rounds"}, path);
    return FailAt(at, path,
                  "F (silence_rounds = " + std::to_string(timing.silence_rounds) +
                      ") must be greater than K (vote_rounds = " + std::to_string(timing.vote_rounds) + ")",
                  diagnostics);
  }
  if (timing.physics_step_s > timing.radio_round_s || !IsWholeMultiple(timing.radio_round_s, timing.physics_step_s)) {
    const YamlNode& at = Blame(node, {"physics_step_s", "radio_round_s"}, path);
    return FailAt(at, path,
                  "physics_step_s (" + FormatNumber(timing.physics_step_s) + ") must divide radio_round_s (" +
                      FormatNumber(timing.radio_round_s) + ") into whole steps",
                  diagnostics);
  }
  if (!IsWholeMultiple(timing.app_round_s, timing.radio_round_s)) {
    const YamlNode& at = Blame(node, {"app_round_s", "radio_round_s"}, path);
    return FailAt(at, path,
                  "app_round_s (" + FormatNumber(timing.app_round_s) + ") must be a whole number of radio rounds (" +
                      FormatNumber(timing.radio_round_s) + " s each)",
                  diagnostics);
  }
  if (std::round(timing.app_round_s / timing.radio_round_s) < timing.vote_rounds) {
    const YamlNode& at = Blame(node, {"app_round_s", "vote_rounds", "radio_round_s"}, path);
    return FailAt(at, path,
                  "app_round_s (" + FormatNumber(timing.app_round_s) + ") must last at least K = " +
                      std::to_string(timing.vote_rounds) + " radio rounds (" +
                      FormatNumber(timing.vote_rounds * timing.radio_round_s) + " s)",
                  diagnostics);
  }
  if (std::round(timing.app_round_s / timing.radio_round_s) > kMaxAppRoundRounds) {
    const YamlNode& at = Blame(node, {"app_round_s", "radio_round_s"}, path);
    return FailAt(at, path,
                  "app_round_s (" + FormatNumber(timing.app_round_s) + ") must last at most " +
                      std::to_string(kMaxAppRoundRounds) + " radio rounds (" +
                      FormatNumber(kMaxAppRoundRounds * timing.radio_round_s) + " s)",
                  diagnostics);
  }
  return true;
}

bool ReadModel(const YamlNode* node, const std::string& path, std::span<const std::string_view> keys,
               std::span<const NumberRange> ranges, std::span<double* const> fields, Diagnostics& diagnostics) {
  if (node == nullptr) return true;
  if (!ExpectMap(*node, path, diagnostics) || !CheckKeys(*node, path, keys, diagnostics)) return false;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (!ReadNumberAt(*node, path, keys[i], ranges[i], *fields[i], diagnostics)) return false;
  }
  return true;
}

constexpr std::string_view kChannelModels[] = {"iid", "gilbert_elliott", "scripted"};  // world::ChannelModel's order

// A key of another model than `model` (the loss of iid, the chain of
// gilbert_elliott, the list of scripted) is an error naming its model.
bool CheckChannelKeys(const YamlNode& node, world::ChannelModel model, Diagnostics& diagnostics) {
  struct Owned {
    std::string_view key;
    world::ChannelModel model;
  };
  static constexpr Owned kOwned[] = {{"loss", world::ChannelModel::kIid},
                                     {"good_to_bad", world::ChannelModel::kGilbertElliott},
                                     {"bad_to_good", world::ChannelModel::kGilbertElliott},
                                     {"loss_good", world::ChannelModel::kGilbertElliott},
                                     {"loss_bad", world::ChannelModel::kGilbertElliott},
                                     {"lost", world::ChannelModel::kScripted},
                                     {"lost_file", world::ChannelModel::kScripted}};
  for (const YamlNode& key : node.keys) {
    for (const Owned& owned : kOwned) {
      if (key.scalar != owned.key || owned.model == model) continue;
      return FailAt(key, "channel",
                    "'" + key.scalar + "' applies to model " +
                        std::string(kChannelModels[static_cast<size_t>(owned.model)]) + " only (model is " +
                        std::string(kChannelModels[static_cast<size_t>(model)]) + ")",
                    diagnostics);
    }
  }
  return true;
}

// A scripted channel's list: [round, sender, receiver] triples, each a
// beacon the channel loses (world::LostBeacon).
bool ReadLostList(const YamlNode& node, const std::string& path, const Scenario& scenario,
                  std::vector<world::LostBeacon>& lost, Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  if (node.values.size() > world::kMaxLostBeacons) {
    return FailAt(node, path,
                  "lists " + std::to_string(node.values.size()) + " beacons; at most " +
                      std::to_string(world::kMaxLostBeacons),
                  diagnostics);
  }
  const int64_t most_rounds = static_cast<int64_t>(scenario.timing.duration_s / scenario.timing.radio_round_s) + 1;
  for (size_t i = 0; i < node.values.size(); ++i) {
    const YamlNode& entry = node.values[i];
    const std::string entry_path = IndexPath(path, i);
    if (!ExpectList(entry, entry_path, diagnostics)) return false;
    if (entry.values.size() != 3) {
      return FailAt(entry, entry_path, "must be [round, sender, receiver], got " + std::to_string(entry.values.size()) +
                                           " numbers",
                    diagnostics);
    }
    world::LostBeacon beacon;
    if (!ReadInteger(entry.values[0], IndexPath(entry_path, 0), 0, most_rounds, beacon.round, diagnostics) ||
        !ReadRobotId(entry.values[1], IndexPath(entry_path, 1), scenario, beacon.from, diagnostics) ||
        !ReadRobotId(entry.values[2], IndexPath(entry_path, 2), scenario, beacon.to, diagnostics)) {
      return false;
    }
    if (beacon.from == beacon.to) {
      return FailAt(entry.values[2], IndexPath(entry_path, 2), "a robot never hears its own beacon", diagnostics);
    }
    lost.push_back(beacon);
  }
  return true;
}

// `lost_file`: the list in a YAML file of its own, relative to the
// scenario's folder; its errors name that file, at the key. The file is held
// to a scenario's text rules, with room for the longest list. Parsing costs
// far more memory than the text: yaml-cpp holds a whole flow collection's
// tokens until it closes (some 140 bytes per byte of text), and the tree a
// kilobyte per entry. So the bytes are capped near what a list of
// kMaxLostBeacons short entries takes one per line (`- [12, 0, 3]`, 13
// bytes), and the tree's nodes at that many entries of four nodes each: at
// most some 2.3 GB, where 64 MiB on one line would take some 9.
bool ReadLostFile(const YamlNode& key, const YamlNode& value, const Scenario& scenario,
                  std::vector<world::LostBeacon>& lost, Diagnostics& diagnostics) {
  std::string name;
  if (!ReadString(value, "channel.lost_file", name, diagnostics)) return false;
  if (name.empty()) return FailAt(value, "channel.lost_file", "must name a file, got an empty string", diagnostics);
  std::filesystem::path path(name);
  if (path.is_relative() && !scenario.source.empty()) path = std::filesystem::path(scenario.source).parent_path() / path;
  const auto fail = [&](const std::string& problem) {
    return FailAt(value, "channel.lost_file", "'" + name + "' " + problem + " (looked for " + path.string() + ")",
                  diagnostics);
  };
  // Only a regular file is opened: a pipe would block the open, a device
  // could be endless.
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (status.type() == std::filesystem::file_type::not_found) {
    return FailAt(value, "channel.lost_file", "no such file '" + name + "' (looked for " + path.string() + ")",
                  diagnostics);
  }
  if (error) return fail("cannot be read: " + error.message());
  if (std::filesystem::is_directory(status)) return fail("is a directory, not a file");
  if (!std::filesystem::is_regular_file(status)) return fail("is not a regular file");
  constexpr size_t kMaxLostFileBytes = 16u << 20;
  std::ifstream file(path, std::ios::binary);
  if (!file) return fail("cannot be opened");
  // One byte past the cap is read, so a file that grew since is refused too.
  std::string text(kMaxLostFileBytes + 1, '\0');
  file.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (file.bad()) return fail("cannot be read");
  text.resize(static_cast<size_t>(file.gcount()));
  if (text.size() > kMaxLostFileBytes) {
    return fail("is more than " + std::to_string(kMaxLostFileBytes) + " bytes, the limit");
  }
  constexpr size_t kMaxLostFileNodes = 1 + 4 * world::kMaxLostBeacons;
  Diagnostics inner(path.string());
  YamlNode root;
  if (!CheckScenarioText(text, inner, kMaxLostFileBytes) || !ReadYamlDocument(text, root, inner, kMaxLostFileNodes) ||
      !ReadLostList(root, "lost", scenario, lost, inner)) {
    return FailAt(key, "channel.lost_file", inner.error() ? inner.error()->ToString() : "cannot be read", diagnostics);
  }
  return true;
}

// One entry of a channel list: a map with only `keys`, of which the first
// `required` must be present.
bool ExpectEntry(const YamlNode& entry, const std::string& entry_path, std::span<const std::string_view> keys,
                 size_t required, Diagnostics& diagnostics) {
  if (!ExpectMap(entry, entry_path, diagnostics) || !CheckKeys(entry, entry_path, keys, diagnostics)) return false;
  for (std::string_view key : keys.first(required)) {
    if (!RequireKey(entry, entry_path, key, diagnostics)) return false;
  }
  return true;
}

bool ReadLinks(const YamlNode& node, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"from", "to", "loss"};
  const std::string path = "channel.links";
  if (!ExpectList(node, path, diagnostics)) return false;
  std::vector<world::LinkLossSpec>& links = scenario.channel.links;
  for (size_t i = 0; i < node.values.size(); ++i) {
    const YamlNode& entry = node.values[i];
    const std::string entry_path = IndexPath(path, i);
    if (!ExpectEntry(entry, entry_path, kKeys, std::size(kKeys), diagnostics)) return false;
    world::LinkLossSpec link;
    if (!ReadRobotId(*entry.Find("from"), JoinPath(entry_path, "from"), scenario, link.from, diagnostics) ||
        !ReadRobotId(*entry.Find("to"), JoinPath(entry_path, "to"), scenario, link.to, diagnostics) ||
        !ReadNumber(*entry.Find("loss"), JoinPath(entry_path, "loss"), kProbability, link.loss, diagnostics)) {
      return false;
    }
    if (link.from == link.to) {
      return FailAt(entry, entry_path, "a link joins two different robots (from = to = " +
                                           std::to_string(link.from) + ")", diagnostics);
    }
    for (size_t j = 0; j < links.size(); ++j) {
      if (links[j].from == link.from && links[j].to == link.to) {
        return FailAt(entry, entry_path,
                      "the link " + std::to_string(link.from) + " -> " + std::to_string(link.to) +
                          " is already given in links[" + std::to_string(j) + "]",
                      diagnostics);
      }
    }
    links.push_back(link);
  }
  return true;
}

bool ReadGroups(const YamlNode& node, const std::string& path, const Scenario& scenario, world::PartitionSpec& partition,
                Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  if (node.values.empty()) return FailAt(node, path, "needs at least one group", diagnostics);
  // Which group each robot is in, to catch a robot listed twice.
  std::vector<int> group_of(scenario.robots.size(), -1);
  for (size_t g = 0; g < node.values.size(); ++g) {
    const YamlNode& group = node.values[g];
    const std::string group_path = IndexPath(path, g);
    if (!ExpectList(group, group_path, diagnostics)) return false;
    if (group.values.empty()) return FailAt(group, group_path, "a group needs at least one robot", diagnostics);
    std::vector<uint16_t>& ids = partition.groups.emplace_back();
    for (size_t k = 0; k < group.values.size(); ++k) {
      uint16_t id = 0;
      if (!ReadRobotId(group.values[k], IndexPath(group_path, k), scenario, id, diagnostics)) return false;
      if (group_of[id] >= 0) {
        const std::string where = group_of[id] == static_cast<int>(g) ? "this group" : "groups[" + std::to_string(group_of[id]) + "]";
        return FailAt(group.values[k], IndexPath(group_path, k),
                      "robot " + std::to_string(id) + " is listed twice (already in " + where + ")", diagnostics);
      }
      group_of[id] = static_cast<int>(g);
      ids.push_back(id);
    }
  }
  return true;
}

// An entry's `start_s` and `end_s` (both present, checked by the caller): a
// window [start_s, end_s) that starts before the run ends and is not empty.
bool ReadWindow(const YamlNode& entry, const std::string& entry_path, double duration_s, double& start_s,
                double& end_s, Diagnostics& diagnostics) {
  const YamlNode& start = *entry.Find("start_s");
  const YamlNode& end = *entry.Find("end_s");
  if (!ReadNumber(start, JoinPath(entry_path, "start_s"), kTimeOfRun, start_s, diagnostics) ||
      !ReadNumber(end, JoinPath(entry_path, "end_s"), kTimeOfRun, end_s, diagnostics)) {
    return false;
  }
  if (start_s >= duration_s) {
    return FailAt(start, JoinPath(entry_path, "start_s"),
                  "starts at " + FormatNumber(start_s) + " s, at or after the end of the run (duration_s = " +
                      FormatNumber(duration_s) + ")",
                  diagnostics);
  }
  if (end_s <= start_s) {
    return FailAt(end, JoinPath(entry_path, "end_s"),
                  "must be greater than start_s (" + FormatNumber(start_s) + "), got " + end.scalar, diagnostics);
  }
  return true;
}

bool ReadPartitions(const YamlNode& node, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"start_s", "end_s", "groups"};
  const std::string path = "channel.partitions";
  if (!ExpectList(node, path, diagnostics)) return false;
  const double duration_s = scenario.timing.duration_s;
  for (size_t i = 0; i < node.values.size(); ++i) {
    const YamlNode& entry = node.values[i];
    const std::string entry_path = IndexPath(path, i);
    if (!ExpectEntry(entry, entry_path, kKeys, std::size(kKeys), diagnostics)) return false;
    world::PartitionSpec partition;
    if (!ReadWindow(entry, entry_path, duration_s, partition.start_s, partition.end_s, diagnostics)) return false;
    for (size_t j = 0; j < scenario.channel.partitions.size(); ++j) {
      const world::PartitionSpec& other = scenario.channel.partitions[j];
      if (partition.start_s < other.end_s && other.start_s < partition.end_s) {
        return FailAt(entry, entry_path,
                      "its window overlaps partitions[" + std::to_string(j) + "] ([" + FormatNumber(other.start_s) +
                          ", " + FormatNumber(other.end_s) + ") s); give one partition at a time",
                      diagnostics);
      }
    }
    if (!ReadGroups(*entry.Find("groups"), JoinPath(entry_path, "groups"), scenario, partition, diagnostics)) {
      return false;
    }
    scenario.channel.partitions.push_back(std::move(partition));
  }
  return true;
}

bool ReadCuts(const YamlNode& node, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"from", "to", "start_s", "end_s", "both_ways"};
  const std::string path = "channel.cuts";
  if (!ExpectList(node, path, diagnostics)) return false;
  const double duration_s = scenario.timing.duration_s;
  for (size_t i = 0; i < node.values.size(); ++i) {
    const YamlNode& entry = node.values[i];
    const std::string entry_path = IndexPath(path, i);
    if (!ExpectEntry(entry, entry_path, kKeys, 4, diagnostics)) return false;  // both_ways is optional
    world::CutSpec cut;
    if (!ReadRobotId(*entry.Find("from"), JoinPath(entry_path, "from"), scenario, cut.from, diagnostics) ||
        !ReadRobotId(*entry.Find("to"), JoinPath(entry_path, "to"), scenario, cut.to, diagnostics)) {
      return false;
    }
    if (cut.from == cut.to) {
      return FailAt(entry, entry_path,
                    "a cut joins two different robots (from = to = " + std::to_string(cut.from) + ")", diagnostics);
    }
    if (!ReadWindow(entry, entry_path, duration_s, cut.start_s, cut.end_s, diagnostics)) return false;
    if (const YamlNode* both = entry.Find("both_ways")) {
      if (both->scalar == "true") {
        cut.both_ways = true;
      } else if (both->scalar != "false") {
        return FailAt(*both, JoinPath(entry_path, "both_ways"), "must be true or false, got '" + both->scalar + "'",
                      diagnostics);
      }
    }
    scenario.channel.cuts.push_back(cut);
  }
  return true;
}

constexpr std::string_view kFaultKinds[] = {"crash", "pause", "join", "deaf", "mute"};  // FaultKind's order

struct PlacedFault {
  FaultSpec fault;
  const YamlNode* node;
  std::string path;
};

bool ReadFault(const YamlNode& node, const std::string& path, const Scenario& scenario, PlacedFault& placed,
               Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"crash", "pause", "join", "deaf", "mute", "at_s", "until_s"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics)) return false;
  const YamlNode* robot = nullptr;
  for (size_t kind = 0; kind < std::size(kFaultKinds); ++kind) {
    const YamlNode* named = node.Find(kFaultKinds[kind]);
    if (named == nullptr) continue;
    if (robot != nullptr) {
      return FailAt(node, path, "names two fault kinds; give one of crash, pause, join, deaf, mute per entry", diagnostics);
    }
    robot = named;
    placed.fault.kind = static_cast<FaultKind>(kind);
    if (!ReadRobotId(*named, JoinPath(path, kFaultKinds[kind]), scenario, placed.fault.robot, diagnostics)) {
      return false;
    }
  }
  if (robot == nullptr) {
    return FailAt(node, path, "a fault needs one of crash, pause, join, deaf, mute (the robot id)", diagnostics);
  }
  if (!RequireKey(node, path, "at_s", diagnostics)) return false;
  const YamlNode& at = *node.Find("at_s");
  if (!ReadNumber(at, JoinPath(path, "at_s"), kTimeOfRun, placed.fault.at_s, diagnostics)) return false;
  if (placed.fault.at_s >= scenario.timing.duration_s) {
    return FailAt(at, JoinPath(path, "at_s"),
                  FormatNumber(placed.fault.at_s) + " s is at or after the end of the run (duration_s = " +
                      FormatNumber(scenario.timing.duration_s) + ")",
                  diagnostics);
  }
  const YamlNode* until = node.Find("until_s");
  if (placed.fault.kind != FaultKind::kPause && !IsRadioFault(placed.fault.kind)) {
    for (const YamlNode& key : node.keys) {
      if (key.scalar == "until_s") {
        return FailAt(key, path, "'until_s' applies to pause, deaf and mute faults only", diagnostics);
      }
    }
    return true;
  }
  if (until == nullptr) return RequireKey(node, path, "until_s", diagnostics);
  if (!ReadNumber(*until, JoinPath(path, "until_s"), kTimeOfRun, placed.fault.until_s, diagnostics)) return false;
  if (placed.fault.until_s <= placed.fault.at_s) {
    return FailAt(*until, JoinPath(path, "until_s"),
                  "must be greater than at_s (" + FormatNumber(placed.fault.at_s) + "), got " + until->scalar,
                  diagnostics);
  }
  return true;
}

// One robot's faults, in time order, must tell a possible story: a join
// first and at most once, nothing after a crash, pauses not overlapping.
bool CheckFaultStory(const std::vector<PlacedFault>& faults, Diagnostics& diagnostics) {
  for (size_t i = 0; i < faults.size(); ++i) {
    const FaultSpec& later = faults[i].fault;
    for (size_t j = 0; j < i; ++j) {
      const FaultSpec& earlier = faults[j].fault;
      // Deaf and mute act on the radio alone: any time, any overlap.
      if (earlier.robot != later.robot || IsRadioFault(earlier.kind) || IsRadioFault(later.kind)) continue;
      const std::string robot = "robot " + std::to_string(later.robot);
      const std::string when = " at " + FormatNumber(earlier.at_s) + " s (" + faults[j].path + ")";
      std::string problem;
      if (later.kind == FaultKind::kJoin) {
        problem = robot + " joins only once, before its other faults; it already has a " +
                  std::string(kFaultKinds[static_cast<size_t>(earlier.kind)]) + when;
      } else if (earlier.kind == FaultKind::kCrash) {
        problem = robot + " already crashed" + when;
      } else if (earlier.kind == FaultKind::kPause && later.at_s < earlier.until_s) {
        problem = robot + " is still paused until " + FormatNumber(earlier.until_s) + " s (" + faults[j].path + ")";
      } else if (earlier.kind == FaultKind::kJoin && later.at_s == earlier.at_s) {
        problem = robot + " joins at the same time" + when;
      }
      if (!problem.empty()) return FailAt(*faults[i].node, faults[i].path, problem, diagnostics);
    }
  }
  return true;
}

}  // namespace

bool ReadTiming(const YamlNode* node, const Overrides& overrides, TimingSpec& timing, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"radio_round_s", "app_round_s",  "vote_rounds",
                                               "silence_rounds", "duration_s", "physics_step_s"};
  const std::string path = "timing";
  YamlNode absent;  // an empty map stands for a missing section
  absent.kind = YamlNode::Kind::kMap;
  const YamlNode& map = node != nullptr ? *node : absent;
  if (!ExpectMap(map, path, diagnostics) || !CheckKeys(map, path, kKeys, diagnostics)) return false;
  int64_t vote_rounds = timing.vote_rounds;
  int64_t silence_rounds = timing.silence_rounds;
  if (!ReadNumberAt(map, path, "radio_round_s", NumberRange{0.001, 10}, timing.radio_round_s, diagnostics) ||
      !ReadNumberAt(map, path, "app_round_s", NumberRange{0, 3600, true}, timing.app_round_s, diagnostics) ||
      !ReadIntegerAt(map, path, "vote_rounds", 1, 200, vote_rounds, diagnostics) ||
      !ReadIntegerAt(map, path, "silence_rounds", 2, kMaxSilenceRounds, silence_rounds, diagnostics) ||
      !ReadNumberAt(map, path, "duration_s", NumberRange{0, kTimeOfRun.max, true}, timing.duration_s, diagnostics) ||
      !ReadNumberAt(map, path, "physics_step_s", NumberRange{0.0001, 1}, timing.physics_step_s, diagnostics)) {
    return false;
  }
  timing.vote_rounds = static_cast<int>(vote_rounds);
  timing.silence_rounds = static_cast<int>(silence_rounds);
  if (overrides.duration_s) timing.duration_s = *overrides.duration_s;  // checked by ReadScenario
  return CheckTimingRules(map, timing, diagnostics);
}

bool ReadSensors(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"imu", "flow", "uwb"};
  if (node == nullptr) return true;
  if (!ExpectMap(*node, "sensors", diagnostics) || !CheckKeys(*node, "sensors", kKeys, diagnostics)) return false;

  static constexpr std::string_view kImuKeys[] = {
      "accel_sigma_mps2", "accel_bias_sigma_mps2", "accel_bias_walk_mps2_per_sqrt_s",
      "gyro_sigma_radps", "gyro_bias_sigma_radps", "gyro_bias_walk_radps_per_sqrt_s"};
  static constexpr NumberRange kImuRanges[] = {{0, 100}, {0, 100}, {0, 100}, {0, 100}, {0, 100}, {0, 100}};
  sensors::ImuModel& imu = scenario.sensors.imu;
  double* const imu_fields[] = {&imu.accel_sigma_mps2, &imu.accel_bias_sigma_mps2,
                                &imu.accel_bias_walk_mps2_per_sqrt_s, &imu.gyro_sigma_radps,
                                &imu.gyro_bias_sigma_radps, &imu.gyro_bias_walk_radps_per_sqrt_s};
  static constexpr std::string_view kFlowKeys[] = {"sigma_px"};
  static constexpr NumberRange kFlowRanges[] = {{0, 100}};
  double* const flow_fields[] = {&scenario.sensors.flow.sigma_px};
  static constexpr std::string_view kUwbKeys[] = {"sigma_m", "outlier_probability", "outlier_min_m",
                                                  "outlier_max_m", "dropout_probability"};
  static constexpr NumberRange kUwbRanges[] = {{0, 10}, kProbability, {0, 100}, {0, 100}, kProbability};
  sensors::UwbModel& uwb = scenario.sensors.uwb;
  double* const uwb_fields[] = {&uwb.sigma_m, &uwb.outlier_probability, &uwb.outlier_min_m, &uwb.outlier_max_m,
                                &uwb.dropout_probability};
  const YamlNode* uwb_node = node->Find("uwb");
  if (!ReadModel(node->Find("imu"), "sensors.imu", kImuKeys, kImuRanges, imu_fields, diagnostics) ||
      !ReadModel(node->Find("flow"), "sensors.flow", kFlowKeys, kFlowRanges, flow_fields, diagnostics) ||
      !ReadModel(uwb_node, "sensors.uwb", kUwbKeys, kUwbRanges, uwb_fields, diagnostics)) {
    return false;
  }
  if (uwb.outlier_min_m > uwb.outlier_max_m) {
    const YamlNode* at = uwb_node->Find("outlier_max_m");
    return FailAt(at != nullptr ? *at : *uwb_node, "sensors.uwb.outlier_max_m",
                  "must be at least outlier_min_m (" + FormatNumber(uwb.outlier_min_m) + "), got " +
                      FormatNumber(uwb.outlier_max_m),
                  diagnostics);
  }
  return true;
}

bool ReadChannel(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"model",    "loss",  "good_to_bad", "bad_to_good", "loss_good",
                                               "loss_bad", "links", "partitions",  "cuts",        "lost",
                                               "lost_file"};
  if (node == nullptr) return true;
  const std::string path = "channel";
  if (!ExpectMap(*node, path, diagnostics) || !CheckKeys(*node, path, kKeys, diagnostics)) return false;
  world::ChannelSpec& channel = scenario.channel;
  if (const YamlNode* model = node->Find("model")) {
    size_t index = 0;
    if (!ReadChoice(*model, "channel.model", kChannelModels, index, diagnostics)) return false;
    channel.model = static_cast<world::ChannelModel>(index);
  }
  if (!CheckChannelKeys(*node, channel.model, diagnostics)) return false;
  if (!ReadNumberAt(*node, path, "loss", kProbability, channel.loss, diagnostics) ||
      !ReadNumberAt(*node, path, "good_to_bad", kProbability, channel.good_to_bad, diagnostics) ||
      !ReadNumberAt(*node, path, "bad_to_good", kProbability, channel.bad_to_good, diagnostics) ||
      !ReadNumberAt(*node, path, "loss_good", kProbability, channel.loss_good, diagnostics) ||
      !ReadNumberAt(*node, path, "loss_bad", kProbability, channel.loss_bad, diagnostics)) {
    return false;
  }
  if (const YamlNode* lost = node->Find("lost")) {
    if (!ReadLostList(*lost, "channel.lost", scenario, channel.lost, diagnostics)) return false;
  }
  for (size_t i = 0; i < node->keys.size(); ++i) {
    if (node->keys[i].scalar != "lost_file") continue;
    if (!ReadLostFile(node->keys[i], node->values[i], scenario, channel.lost, diagnostics)) return false;
  }
  const YamlNode* links = node->Find("links");
  const YamlNode* partitions = node->Find("partitions");
  const YamlNode* cuts = node->Find("cuts");
  return (links == nullptr || ReadLinks(*links, scenario, diagnostics)) &&
         (partitions == nullptr || ReadPartitions(*partitions, scenario, diagnostics)) &&
         (cuts == nullptr || ReadCuts(*cuts, scenario, diagnostics));
}

bool ReadFaults(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  if (node == nullptr) return true;
  const std::string path = "faults";
  if (!ExpectList(*node, path, diagnostics)) return false;
  std::vector<PlacedFault> faults(node->values.size());
  for (size_t i = 0; i < faults.size(); ++i) {
    faults[i].node = &node->values[i];
    faults[i].path = IndexPath(path, i);
    if (!ReadFault(node->values[i], faults[i].path, scenario, faults[i], diagnostics)) return false;
  }
  std::stable_sort(faults.begin(), faults.end(), [](const PlacedFault& a, const PlacedFault& b) {
    return a.fault.at_s != b.fault.at_s ? a.fault.at_s < b.fault.at_s : a.fault.robot < b.fault.robot;
  });
  if (!CheckFaultStory(faults, diagnostics)) return false;
  for (const PlacedFault& placed : faults) {
    scenario.faults.push_back(placed.fault);
    if (placed.fault.kind == FaultKind::kJoin) scenario.robots[placed.fault.robot].present_at_start = false;
  }
  return true;
}

}  // namespace syrof::lab::scenario

namespace syrof::lab::scenario {
namespace {

// A number for every robot, or a list with one per robot, in `range`.
bool ReadPerRobot(const YamlNode& node, const std::string& path, const NumberRange& range, size_t robots,
                  std::vector<double>& values, Diagnostics& diagnostics) {
  values.assign(robots, 0.0);
  if (node.is_scalar()) {
    double value = 0;
    if (!ReadNumber(node, path, range, value, diagnostics)) return false;
    values.assign(robots, value);
    return true;
  }
  if (!node.is_sequence()) return FailAt(node, path, "must be a number or a list with one per robot", diagnostics);
  if (node.values.size() != robots) {
    return FailAt(node, path,
                  "has " + std::to_string(node.values.size()) + " values; the scenario has " + std::to_string(robots) +
                      " robots (give one each, or one number for all)",
                  diagnostics);
  }
  for (size_t i = 0; i < robots; ++i) {
    if (!ReadNumber(node.values[i], IndexPath(path, i), range, values[i], diagnostics)) return false;
  }
  return true;
}

// Uniform in [0, 1) from the seed, a purpose and a robot: one stream per
// use, so adding a robot changes no other robot's clock.
double ClockDraw(uint64_t seed, uint64_t purpose, uint16_t robot) {
  const uint64_t hash = base::SplitMix64Hash(seed ^ base::SplitMix64Hash(purpose + robot));
  return static_cast<double>(hash >> 11) * 0x1.0p-53;
}

}  // namespace

bool ReadClocks(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  if (node == nullptr) return true;
  static constexpr std::string_view kKeys[] = {"offset_ms", "offset_max_ms", "drift_ppm", "drift_max_ppm", "jitter_ms",
                                               "alignment"};
  const std::string path = "clocks";
  if (!ExpectMap(*node, path, diagnostics) || !CheckKeys(*node, path, kKeys, diagnostics)) return false;
  ClockSpec& clocks = scenario.clocks;
  clocks.enabled = true;
  const size_t robots = scenario.robots.size();
  const double round_ms = scenario.timing.radio_round_s * 1e3;
  const NumberRange offset_range{0, round_ms};
  const NumberRange drift_range{-kMaxDriftPpm, kMaxDriftPpm};
  for (const auto& [fixed, random] : {std::pair<std::string_view, std::string_view>{"offset_ms", "offset_max_ms"},
                                      std::pair<std::string_view, std::string_view>{"drift_ppm", "drift_max_ppm"}}) {
    if (node->Find(fixed) != nullptr && node->Find(random) != nullptr) {
      return FailAt(*node->Find(random), JoinPath(path, random),
                    "give either '" + std::string(fixed) + "' (fixed) or '" + std::string(random) +
                        "' (drawn from the seed), not both",
                    diagnostics);
    }
  }
  clocks.offset_ms.assign(robots, 0.0);
  clocks.drift_ppm.assign(robots, 0.0);
  if (const YamlNode* offset = node->Find("offset_ms")) {
    if (!ReadPerRobot(*offset, JoinPath(path, "offset_ms"), offset_range, robots, clocks.offset_ms, diagnostics)) {
      return false;
    }
  }
  if (const YamlNode* drift = node->Find("drift_ppm")) {
    if (!ReadPerRobot(*drift, JoinPath(path, "drift_ppm"), drift_range, robots, clocks.drift_ppm, diagnostics)) {
      return false;
    }
  }
  double offset_max_ms = 0;
  double drift_max_ppm = 0;
  if (!ReadNumberAt(*node, path, "offset_max_ms", offset_range, offset_max_ms, diagnostics) ||
      !ReadNumberAt(*node, path, "drift_max_ppm", NumberRange{0, kMaxDriftPpm}, drift_max_ppm, diagnostics) ||
      !ReadNumberAt(*node, path, "jitter_ms", NumberRange{0, round_ms / 4}, clocks.jitter_ms, diagnostics)) {
    return false;
  }
  for (size_t i = 0; i < robots; ++i) {
    const auto id = static_cast<uint16_t>(i);
    if (node->Find("offset_max_ms") != nullptr) {
      clocks.offset_ms[i] = offset_max_ms * ClockDraw(scenario.seed, 0x4f4646534554ULL << 8, id);
    }
    if (node->Find("drift_max_ppm") != nullptr) {
      clocks.drift_ppm[i] = drift_max_ppm * (2 * ClockDraw(scenario.seed, 0x4452494654ULL << 8, id) - 1);
    }
  }
  if (const YamlNode* alignment = node->Find("alignment")) {
    static constexpr std::string_view kSwitch[] = {"on", "off"};
    size_t choice = 0;
    if (!ReadChoice(*alignment, JoinPath(path, "alignment"), kSwitch, choice, diagnostics)) return false;
    clocks.alignment = choice == 0;
  }
  return true;
}

}  // namespace syrof::lab::scenario
