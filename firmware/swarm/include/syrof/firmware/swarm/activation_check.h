// Whether each robot decided who looks as its activation schedule says
// (sync/activation.h, docs/activation.md): every "E" line says whether the
// robot looked at that epoch start (console_lines.h, EpochLine::active), and
// this check decides the same from the scenario's config and the map the
// robot started with: SSYNC with sync::IsActive, ASYNC by following each
// robot's cycles with its own sync::AsyncTracker, FSYNC every start. A robot
// that ignored its boot words (an image that runs every robot every epoch)
// shows here, whatever the epochs `syrof compare` sees. Pure: no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/firmware/swarm/console_lines.h"
#include "syrof/sync/activation.h"

namespace syrof::firmware::swarm {

/// firmware-swarm.json's "activation".
struct ActivationFigures {
  std::string model = "fsync";  ///< sync::ToString of the scenario's model
  int64_t starts = 0;           ///< epoch lines checked
  int64_t looked = 0;           ///< of those, the starts the robots said they looked at
  int64_t against_schedule = 0; ///< starts where the robot's word and the schedule differ
  std::string first_difference; ///< the first of those, in words; empty when none
};

class ActivationCheck {
 public:
  /// `config`'s scripts must outlive the check; `robots` ids 0 .. robots - 1.
  ActivationCheck(const sync::ActivationConfig& config, uint16_t robots);

  /// One epoch line, in the order the robot printed them. A robot whose
  /// lines were lost (EpochLine's `lost` count) is followed as printed.
  void OnEpochLine(const EpochLine& line);

  const ActivationFigures& figures() const { return figures_; }

 private:
  sync::ActivationConfig config_;
  std::vector<sync::AsyncTracker> trackers_;
  ActivationFigures figures_;
};

}  // namespace syrof::firmware::swarm
