#include "syrof/firmware/swarm/activation_check.h"

namespace syrof::firmware::swarm {

ActivationCheck::ActivationCheck(const sync::ActivationConfig& config, uint16_t robots)
    : config_(config), trackers_(robots) {
  figures_.model = sync::ToString(config.model);
}

void ActivationCheck::OnEpochLine(const EpochLine& line) {
  if (line.robot >= trackers_.size()) return;
  bool expected = true;
  if (config_.model == sync::ActivationModel::kAsync) {
    expected = trackers_[line.robot].OnEpochStart(config_, line.map.epoch, line.robot).looks;
  } else {
    expected = sync::IsActive(config_, line.map.epoch, line.map.members, line.robot);
  }
  ++figures_.starts;
  if (line.active) ++figures_.looked;
  if (line.active == expected) return;
  ++figures_.against_schedule;
  if (figures_.first_difference.empty()) {
    figures_.first_difference = "robot " + std::to_string(line.robot) + " at its start of epoch " +
                                std::to_string(line.map.epoch) + (line.active ? " looked" : " did not look") +
                                "; its " + figures_.model + " schedule says it " + (expected ? "looks" : "does not");
  }
}

}  // namespace syrof::firmware::swarm
