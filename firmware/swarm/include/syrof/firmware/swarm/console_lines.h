// The lines an emulated robot prints on its console for the swarm host
// (firmware/robot/robot_image.h, ImageConfig::report_rounds), parsed back:
//
//   R t_ms=T robot=I epoch=E mode=M phase=P member=0|1 valid=0|1 x_mm=X y_mm=Y lost=L
//       the robot's state once a radio round, on its own clock T;
//   E t_ms=T robot=I epoch=E mode=M active=0|1 members=ID:X:Y:H:VX:VY:PAYLOADHEX;...
//       an epoch start with its LDMap (mode 0 COOPERATIVE, 1 AUTONOMOUS;
//       phases are not sent: SameKnowledge ignores them); active 1 when the
//       robot looked (newRound on this map), 0 when its activation schedule
//       left it out (SSYNC) or a cycle was under way (ASYNC);
//   held id=I t_ms=T app=NAME
//       the robot is built and waits for its Start frame (`hold 1`); NAME,
//       the rest of the line, is the name of the app compiled into the image
//       (its descriptor's, syrof_app_entry()->name): the app the robot runs,
//       whatever the scenario's `app:` says.
//
// The robot is untrusted input here (a bug, a garbled byte): a line that
// does not parse gives an error naming the field and the column.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "syrof/sync/ldmap.h"
#include "syrof/wire/beacon.h"

namespace syrof::firmware::swarm {

struct RoundLine {
  int64_t t_ms = 0;
  uint16_t robot = 0;
  uint16_t epoch = 0;
  wire::Mode mode = wire::Mode::kAutonomous;
  wire::Phase phase = wire::Phase::kWait;
  bool member = false;
  bool estimate_valid = false;
  double x_m = 0;
  double y_m = 0;
  uint32_t epoch_lines_lost = 0;
};

struct EpochLine {
  int64_t t_ms = 0;
  uint16_t robot = 0;
  bool active = true;  ///< the robot looked at this start
  sync::LDMap map{};
};

/// The image is held: built, its clock not started, running `app`.
struct HeldLine {
  int64_t t_ms = 0;
  uint16_t robot = 0;
  std::string app;  ///< 1 to kMaxAppNameBytes printable ASCII bytes
};

/// The longest app name a held line may carry: what a replay header holds
/// (lab/replay replay.h, kMaxNameBytes).
inline constexpr size_t kMaxAppNameBytes = 256;

/// Why a line was not understood: `column` (0-based) is where in the line.
struct LineError {
  std::string what;
  size_t column = 0;
};

/// Neither R, E nor held (a status line, the app's own printf): nothing to do.
struct OtherLine {};

using ConsoleLine = std::variant<OtherLine, RoundLine, EpochLine, HeldLine, LineError>;

/// Parses one line (without its '\n'). Robot ids and member ids must be
/// below `swarm_size`.
ConsoleLine ParseConsoleLine(std::string_view line, uint16_t swarm_size);

}  // namespace syrof::firmware::swarm
