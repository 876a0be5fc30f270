// What the bridge reports at the end: its counts and rejections (printed,
// and DIR/bridge.json, docs/bridge.md "bridge.json"), and what its replay
// says when read back (each robot's epochs), so a check reads the file
// itself rather than the station's memory.
#pragma once

#include <cstdint>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "syrof/bridge/base_station.h"
#include "syrof/lab/base/error.h"

namespace syrof::bridge {

/// One robot in a replay the bridge wrote.
struct RobotReplayFacts {
  uint16_t id = 0;
  uint32_t running_rounds = 0;      ///< rounds with presence RUNNING
  bool seen = false;                ///< RUNNING in at least one round
  uint16_t first_epoch = 0;         ///< epoch of its first RUNNING frame
  uint16_t last_epoch = 0;          ///< epoch of its last RUNNING frame
  uint32_t epoch_starts = 0;        ///< EPOCH_START events
  uint32_t cooperative_starts = 0;  ///< of which COOPERATIVE
};

struct ReplayFacts {
  bool read = false;      ///< the header and every round read, end marker included
  std::optional<lab::Error> error;  ///< the reader's error when not read
  uint32_t rounds = 0;
  std::vector<RobotReplayFacts> robots;  ///< per header robot, in id order
};

/// Reads a replay back (lab/replay's Reader) and tallies it.
ReplayFacts ReadReplayFacts(std::istream& in);

/// Where the bridge's bytes came from and where its beacons went, for the report.
struct BridgeRunInfo {
  std::string input;        ///< "serial /dev/ttyACM0 at 1000000 baud", "socket PATH", "file PATH"
  double wall_s = 0;        ///< how long it ran
  bool dds = false;         ///< it published on DDS
  uint32_t dds_domain = 0;
  uint64_t dds_published = 0;
  uint64_t dds_failed = 0;
  std::string replay_path;  ///< empty: no replay
  std::string end;          ///< why it stopped: "end of input", "--seconds", "signal", "link error: ..."
};

/// The JSON document of docs/bridge.md ("bridge.json"), two-space indented.
std::string SummaryJson(const BaseStation& station, const BridgeRunInfo& run, const std::optional<ReplayFacts>& replay);

/// The human summary: counts, each robot's latest word, and one line per
/// non-zero rejection reason ("rejected: CrcMismatch 3").
std::string SummaryText(const BaseStation& station, const BridgeRunInfo& run);

}  // namespace syrof::bridge
