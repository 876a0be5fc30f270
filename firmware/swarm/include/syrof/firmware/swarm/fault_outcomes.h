// Whether an emulated swarm handled its scenario's faults, judged from the
// robots' own console reports (console_lines.h) stamped with world time:
//
//   crash of C at t   every robot still running at the end that started an
//                     epoch after t started its last one without C (its
//                     failure detector removed C), and at least one did;
//   pause of P        P reported again after the pause ended and was a
//                     MEMBER again afterwards ("came back");
//   join of J at t    J reported MEMBER after t, and another robot started
//                     an epoch with J in its map.
//
// For each pause it also keeps what the paused guest saw: the jump of its
// own clock (t_ms) between its last report before the stop and its first
// after, against the world time between them (docs/firmware.md, "Faults").
// Pure: fed by the host, no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/firmware/swarm/console_lines.h"
#include "syrof/firmware/swarm/fault_player.h"

namespace syrof::firmware::swarm {

struct FaultOutcome {
  HostAction::Kind kind = HostAction::Kind::kSwitchOn;  ///< kKill: a crash, kStop: a pause, kSwitchOn: a join
  uint16_t robot = 0;
  int64_t at_ns = 0;           ///< world time the host acted
  bool ok = false;
  std::optional<int64_t> done_ns;  ///< world time the outcome was first seen (removed, back as MEMBER, joined)
  std::string detail;          ///< one line for people
  // Pauses only: what the guest saw across the stall.
  std::optional<int64_t> guest_gap_ms;  ///< its clock between its last report before and first after
  std::optional<int64_t> world_gap_ms;  ///< world time between those two reports
  bool rejoined_as_joiner = false;      ///< reported non-MEMBER after the pause before MEMBER again
};

class FaultOutcomes {
 public:
  explicit FaultOutcomes(uint16_t robots);

  /// The host applied `action` at world time `world_ns` (a kContinue ends the
  /// robot's latest pause).
  void OnAction(const HostAction& action, int64_t world_ns);
  /// A robot's report arrived at world time `world_ns` (non-decreasing).
  void OnRoundLine(const RoundLine& line, int64_t world_ns);
  void OnEpochLine(const EpochLine& line, int64_t world_ns);

  /// One outcome per crash, pause and join, in the order they happened;
  /// `final_presence` says who was still running at the end.
  std::vector<FaultOutcome> Finish(const std::vector<lab::sim::Lifecycle>& final_presence) const;

 private:
  struct Pause {
    uint16_t robot = 0;
    int64_t stop_ns = 0;
    std::optional<int64_t> continue_ns;
    std::optional<RoundLine> last_before;
    int64_t last_before_ns = 0;
    std::optional<RoundLine> first_after;
    int64_t first_after_ns = 0;
    std::optional<int64_t> member_again_ns;
    bool saw_non_member = false;
  };
  struct Join {
    uint16_t robot = 0;
    int64_t at_ns;
    std::optional<int64_t> member_ns;   // the joiner said MEMBER
    std::optional<int64_t> in_map_ns;   // another robot's epoch map held it
  };
  struct Crash {
    uint16_t robot = 0;
    int64_t at_ns;
    // Per robot: whether its latest epoch start after the crash held the
    // crashed robot (unset: none since), and when it first did not.
    std::vector<std::optional<bool>> last_holds;
    std::optional<int64_t> first_without_ns;
  };
  struct Event {
    HostAction::Kind kind;
    size_t index;  // into the vector of its kind
  };

  uint16_t robots_;
  std::vector<Pause> pauses_;
  std::vector<Join> joins_;
  std::vector<Crash> crashes_;
  std::vector<Event> order_;
  std::vector<std::optional<RoundLine>> latest_;  // each robot's latest report
  std::vector<int64_t> latest_ns_;
};

}  // namespace syrof::firmware::swarm
