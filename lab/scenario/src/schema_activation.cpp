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

constexpr std::string_view kActivationModels[] = {"fsync", "ssync"};  // sync::ActivationModel's order
constexpr std::string_view kActivationSchedules[] = {"random", "round_robin", "scripted"};  // sync::ActivationSchedule's order

// A key that belongs to another model or schedule is an error naming whose
// it is, rather than a setting silently ignored.
bool CheckActivationKeys(const YamlNode& node, const ActivationSpec& activation, Diagnostics& diagnostics) {
  const bool ssync = activation.model == sync::ActivationModel::kSsync;
  const std::string schedule(kActivationSchedules[static_cast<size_t>(activation.schedule)]);
  for (const YamlNode& key : node.keys) {
    if (key.scalar == "model") continue;
    if (!ssync) {
      return FailAt(key, "activation",
                    "'" + key.scalar + "' applies to model ssync only (model is " +
                        std::string(kActivationModels[static_cast<size_t>(activation.model)]) + ")",
                    diagnostics);
    }
    if (key.scalar == "fair_within" && activation.schedule != sync::ActivationSchedule::kRandom) {
      return FailAt(key, "activation",
                    "'fair_within' applies to schedule random only (schedule is " + schedule +
                        "); the run's fairness is reported in metrics.json either way",
                    diagnostics);
    }
    if (key.scalar == "active" && activation.schedule != sync::ActivationSchedule::kScripted) {
      return FailAt(key, "activation", "'active' applies to schedule scripted only (schedule is " + schedule + ")",
                    diagnostics);
    }
  }
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
  static constexpr std::string_view kKeys[] = {"model", "schedule", "fair_within", "active"};
  if (node == nullptr) return true;
  const std::string path = "activation";
  if (!ExpectMap(*node, path, diagnostics) || !CheckKeys(*node, path, kKeys, diagnostics) ||
      !RequireKey(*node, path, "model", diagnostics)) {
    return false;
  }
  ActivationSpec& activation = scenario.activation;
  const YamlNode& model = *node->Find("model");
  if (model.is_scalar() && model.scalar == "async") {
    return FailAt(model, "activation.model", "activation model async is not built yet (fsync and ssync are)",
                  diagnostics);
  }
  size_t index = 0;
  if (!ReadChoice(model, "activation.model", kActivationModels, index, diagnostics)) return false;
  activation.model = static_cast<sync::ActivationModel>(index);
  if (activation.model == sync::ActivationModel::kSsync) {
    if (!RequireKey(*node, path, "schedule", diagnostics) ||
        !ReadChoice(*node->Find("schedule"), "activation.schedule", kActivationSchedules, index, diagnostics)) {
      return false;
    }
    activation.schedule = static_cast<sync::ActivationSchedule>(index);
  }
  if (!CheckActivationKeys(*node, activation, diagnostics)) return false;
  const int64_t run_epochs = RunEpochs(scenario.timing);
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
