// `activation:` (docs/scenarios.md, docs/activation.md): which robots look,
// compute and move in each epoch. Needs the robots and the timing (the
// run's epochs bound fair_within and the script's epochs).
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include "schema.h"
#include "value_reader.h"

namespace syrof::lab::scenario {
namespace {

constexpr std::string_view kActivationModels[] = {"fsync", "ssync", "async"};  // sync::ActivationModel's order
constexpr std::string_view kActivationSchedules[] = {"random", "round_robin", "scripted"};  // sync::ActivationSchedule's order

// A key that belongs to another model or schedule is an error naming whose
// it is, rather than a setting silently ignored.
bool CheckActivationKeys(const YamlNode& node, const ActivationSpec& activation, Diagnostics& diagnostics) {
  const std::string model(kActivationModels[static_cast<size_t>(activation.model)]);
  const std::string schedule(kActivationSchedules[static_cast<size_t>(activation.schedule)]);
  const bool ssync = activation.model == sync::ActivationModel::kSsync;
  const bool async = activation.model == sync::ActivationModel::kAsync;
  for (const YamlNode& key : node.keys) {
    if (key.scalar == "model") continue;
    if (!ssync && !async) {
      return FailAt(key, "activation", "'" + key.scalar + "' applies to models ssync and async only (model is " + model + ")",
                    diagnostics);
    }
    if ((key.scalar == "fair_within" || key.scalar == "active") && !ssync) {
      return FailAt(key, "activation", "'" + key.scalar + "' applies to model ssync only (model is " + model + ")",
                    diagnostics);
    }
    if ((key.scalar == "max_delay_epochs" || key.scalar == "min_move_m" || key.scalar == "cycles") && !async) {
      return FailAt(key, "activation", "'" + key.scalar + "' applies to model async only (model is " + model + ")",
                    diagnostics);
    }
    if (key.scalar == "fair_within" && activation.schedule != sync::ActivationSchedule::kRandom) {
      return FailAt(key, "activation",
                    "'fair_within' applies to schedule random only (schedule is " + schedule +
                        "); the run's fairness is reported in metrics.json either way",
                    diagnostics);
    }
    if ((key.scalar == "active" || key.scalar == "cycles") && activation.schedule != sync::ActivationSchedule::kScripted) {
      return FailAt(key, "activation",
                    "'" + key.scalar + "' applies to schedule scripted only (schedule is " + schedule + ")", diagnostics);
    }
  }
  return true;
}

// `cycles: [[epoch, robot, start_delay, move_epochs], ...]` (a fifth value,
// `cut`, with min_move_m): each (epoch, robot) once, epochs in 1 .. the
// run's epochs, start_delay 0 .. max_delay_epochs, move_epochs 1 ..
// max_delay_epochs + 1.
bool ReadCycleList(const YamlNode& node, const std::string& path, const Scenario& scenario, int64_t run_epochs,
                   ActivationSpec& activation, Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  const int64_t most = activation.max_delay_epochs;
  for (size_t i = 0; i < node.values.size(); ++i) {
    const YamlNode& entry = node.values[i];
    const std::string entry_path = IndexPath(path, i);
    if (!ExpectList(entry, entry_path, diagnostics)) return false;
    if (entry.values.size() != 4 && entry.values.size() != 5) {
      return FailAt(entry, entry_path,
                    "must be [epoch, robot, start_delay, move_epochs] or [epoch, robot, start_delay, move_epochs, "
                    "cut], got " + std::to_string(entry.values.size()) + " values",
                    diagnostics);
    }
    int64_t epoch = 0;
    int64_t start_delay = 0;
    int64_t move_epochs = 0;
    uint16_t robot = 0;
    if (!ReadInteger(entry.values[0], IndexPath(entry_path, 0), 1, run_epochs, epoch, diagnostics) ||
        !ReadRobotId(entry.values[1], IndexPath(entry_path, 1), scenario, robot, diagnostics) ||
        !ReadInteger(entry.values[2], IndexPath(entry_path, 2), 0, most, start_delay, diagnostics) ||
        !ReadInteger(entry.values[3], IndexPath(entry_path, 3), 1, most + 1, move_epochs, diagnostics)) {
      return false;
    }
    bool cut = false;
    if (entry.values.size() == 5) {
      int64_t value = 0;
      if (!ReadInteger(entry.values[4], IndexPath(entry_path, 4), 0, 1, value, diagnostics)) return false;
      if (value == 1 && activation.min_move_m <= 0) {
        return FailAt(entry.values[4], IndexPath(entry_path, 4),
                      "a cut needs min_move_m (non-rigid moves); without it every move is rigid", diagnostics);
      }
      cut = value == 1;
    }
    for (const sync::ScriptedCycle& earlier : activation.cycles) {
      if (earlier.epoch == epoch && earlier.robot == robot) {
        return FailAt(entry, entry_path,
                      "robot " + std::to_string(robot) + "'s look in epoch " + std::to_string(epoch) +
                          " is listed twice",
                      diagnostics);
      }
    }
    activation.cycles.push_back(sync::ScriptedCycle{static_cast<uint16_t>(epoch), robot,
                                                    static_cast<uint8_t>(start_delay),
                                                    static_cast<uint8_t>(move_epochs), cut});
  }
  std::sort(activation.cycles.begin(), activation.cycles.end(),
            [](const sync::ScriptedCycle& a, const sync::ScriptedCycle& b) {
              return a.epoch != b.epoch ? a.epoch < b.epoch : a.robot < b.robot;
            });
  return true;
}

// `active: [[epoch, [ids]], ...]`: epochs in 1 .. the run's epochs, each
// listed once, each naming at least one robot of the scenario, once.
bool ReadActiveList(const YamlNode& node, const std::string& path, const Scenario& scenario, int64_t run_epochs,
                    std::vector<sync::ScriptedActivation>& script, Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  std::vector<int64_t> listed_epochs;
  for (size_t i = 0; i < node.values.size(); ++i) {
    const YamlNode& entry = node.values[i];
    const std::string entry_path = IndexPath(path, i);
    if (!ExpectList(entry, entry_path, diagnostics)) return false;
    if (entry.values.size() != 2) {
      return FailAt(entry, entry_path,
                    "must be [epoch, [robot ids]], got " + std::to_string(entry.values.size()) + " values",
                    diagnostics);
    }
    int64_t epoch = 0;
    if (!ReadInteger(entry.values[0], IndexPath(entry_path, 0), 1, run_epochs, epoch, diagnostics)) return false;
    if (std::find(listed_epochs.begin(), listed_epochs.end(), epoch) != listed_epochs.end()) {
      return FailAt(entry.values[0], IndexPath(entry_path, 0),
                    "epoch " + std::to_string(epoch) + " is listed twice; give its robots in one entry", diagnostics);
    }
    listed_epochs.push_back(epoch);
    const YamlNode& ids = entry.values[1];
    const std::string ids_path = IndexPath(entry_path, 1);
    if (!ExpectList(ids, ids_path, diagnostics)) return false;
    if (ids.values.empty()) {
      return FailAt(ids, ids_path, "names no robot; an epoch has at least one active robot", diagnostics);
    }
    const size_t first = script.size();
    for (size_t j = 0; j < ids.values.size(); ++j) {
      uint16_t robot = 0;
      if (!ReadRobotId(ids.values[j], IndexPath(ids_path, j), scenario, robot, diagnostics)) return false;
      for (size_t k = first; k < script.size(); ++k) {
        if (script[k].robot == robot) {
          return FailAt(ids.values[j], IndexPath(ids_path, j), "robot " + std::to_string(robot) + " is named twice",
                        diagnostics);
        }
      }
      script.push_back(sync::ScriptedActivation{static_cast<uint16_t>(epoch), robot});
    }
  }
  std::sort(script.begin(), script.end(), [](const sync::ScriptedActivation& a, const sync::ScriptedActivation& b) {
    return a.epoch != b.epoch ? a.epoch < b.epoch : a.robot < b.robot;
  });
  return true;
}

}  // namespace

int64_t RunEpochs(const TimingSpec& timing) {
  return std::max<int64_t>(1, static_cast<int64_t>(std::floor(timing.duration_s / timing.app_round_s + 1e-9)));
}

bool ReadActivation(const YamlNode* node, Scenario& scenario, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"model",         "schedule",         "fair_within", "active",
                                               "max_delay_epochs", "min_move_m", "cycles"};
  if (node == nullptr) return true;
  const std::string path = "activation";
  if (!ExpectMap(*node, path, diagnostics) || !CheckKeys(*node, path, kKeys, diagnostics) ||
      !RequireKey(*node, path, "model", diagnostics)) {
    return false;
  }
  ActivationSpec& activation = scenario.activation;
  const YamlNode& model = *node->Find("model");
  size_t index = 0;
  if (!ReadChoice(model, "activation.model", kActivationModels, index, diagnostics)) return false;
  activation.model = static_cast<sync::ActivationModel>(index);
  if (activation.model != sync::ActivationModel::kFsync) {
    if (!RequireKey(*node, path, "schedule", diagnostics) ||
        !ReadChoice(*node->Find("schedule"), "activation.schedule", kActivationSchedules, index, diagnostics)) {
      return false;
    }
    activation.schedule = static_cast<sync::ActivationSchedule>(index);
    if (activation.model == sync::ActivationModel::kAsync &&
        activation.schedule == sync::ActivationSchedule::kRoundRobin) {
      return FailAt(*node->Find("schedule"), "activation.schedule",
                    "schedule round_robin applies to model ssync only; async takes random or scripted", diagnostics);
    }
  }
  if (!CheckActivationKeys(*node, activation, diagnostics)) return false;
  const int64_t run_epochs = RunEpochs(scenario.timing);
  if (activation.model == sync::ActivationModel::kAsync) {
    if (!RequireKey(*node, path, "max_delay_epochs", diagnostics)) return false;
    int64_t most = 0;
    if (!ReadInteger(*node->Find("max_delay_epochs"), "activation.max_delay_epochs", 1, sync::kMaxAsyncDelayEpochs,
                     most, diagnostics)) {
      return false;
    }
    activation.max_delay_epochs = static_cast<uint8_t>(most);
    // At most the arena's diagonal (a wire position is whole millimetres).
    if (!ReadNumberAt(*node, path, "min_move_m", NumberRange{0, 30, true}, activation.min_move_m, diagnostics)) {
      return false;
    }
    if (activation.schedule == sync::ActivationSchedule::kScripted) {
      return RequireKey(*node, path, "cycles", diagnostics) &&
             ReadCycleList(*node->Find("cycles"), "activation.cycles", scenario, run_epochs, activation, diagnostics);
    }
    return true;
  }
  const int64_t most_fair_within = std::min<int64_t>(run_epochs, sync::kMaxFairWithinEpochs);
  if (const YamlNode* fair_within = node->Find("fair_within")) {
    int64_t value = 0;
    if (!ReadInteger(*fair_within, "activation.fair_within", 1, most_fair_within, value, diagnostics)) {
      return false;
    }
    activation.fair_within = static_cast<uint16_t>(value);
  } else {
    activation.fair_within = static_cast<uint16_t>(std::min<int64_t>(kDefaultFairWithinEpochs, most_fair_within));
  }
  if (activation.schedule == sync::ActivationSchedule::kScripted) {
    if (!RequireKey(*node, path, "active", diagnostics) ||
        !ReadActiveList(*node->Find("active"), "activation.active", scenario, run_epochs, activation.script,
                        diagnostics)) {
      return false;
    }
  }
  return true;
}

}  // namespace syrof::lab::scenario
