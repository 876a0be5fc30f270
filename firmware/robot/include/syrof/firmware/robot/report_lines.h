// The two console lines an emulated robot prints for the swarm host when
// ImageConfig::report_rounds is on (robot_image.h), formatted here so the
// host's parser (firmware/swarm/console_lines.h) is tested against this very
// code (tests/firmware/robot/report_lines_test.cpp):
//
//   R t_ms=T robot=I epoch=E mode=M phase=P member=0|1 valid=0|1 x_mm=X y_mm=Y lost=L
//   E t_ms=T robot=I epoch=E mode=M active=0|1 members=ID:X:Y:H:VX:VY:PAYLOADHEX;...
//
// Both are ASCII, end with '\n', and fit `out` or are not written (0).
// No allocation; snprintf only (newlib's on the M4).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/sync/ldmap.h"
#include "syrof/sync/synchronizer.h"

namespace syrof::firmware::robot {

/// The "R" line: the robot's state at `now_ns` (its own clock). `lost`:
/// epoch lines it could not print.
size_t FormatRoundLine(uint16_t robot, int64_t now_ns, const sync::SyncState& state, bool estimate_valid, float x_m,
                       float y_m, uint32_t lost, std::span<char> out);

/// The "E" line: `robot` started `ldmap.epoch` at `now_ns` with this map;
/// `active`: the robot's own activation decision (docs/activation.md), it
/// looked (newRound) at this start. Members and snapshots in full (phases are not: SameKnowledge ignores
/// them), so the host can rebuild the map and compare it. 32 members with
/// full payloads take about 1.6 KB.
size_t FormatEpochLine(uint16_t robot, int64_t now_ns, const sync::LDMap& ldmap, bool active, std::span<char> out);

}  // namespace syrof::firmware::robot
