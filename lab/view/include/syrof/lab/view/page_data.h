// The viewer's page data, piece by piece (docs/viewer.md, "The page's
// data"): what the file page (view.h: BuildPage) and the live page
// (lab/live: LiveServer) both make of a replay's header, frames, events and
// maps, so the two pages draw the same run the same way.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

#include "syrof/lab/replay/replay.h"

namespace syrof::lab::view {

/// Version of the page's data layout; the page checks it.
inline constexpr int kDataVersion = 1;

/// The page's fields that come from the replay's header: data_version,
/// kinds (event kind names by number), replay_version, scenario, app, seed
/// (a string: a u64 does not fit a JS number), round_ns, arena, anchors,
/// robots (id, kind, radius, inputs) and message (the format's text or null).
nlohmann::json HeaderData(const replay::Header& header, int replay_version);

/// A frame's state word as the page reads it: presence | status << 2 |
/// phase << 3 | mode << 5.
int64_t FrameState(const replay::RobotFrame& frame);

/// Millimetres (or milliradians) as an integer for the page. The reader
/// accepts any float bits, so a value JSON cannot hold (NaN, infinity) or an
/// absurd one is drawn at 0 or at the clamp instead of breaking the page.
int32_t Milli(float value);

/// One event as the page lists it, in the round at page position `position`:
/// [position, kind, robot, other, epoch, mode, time_us, partition], -1 for
/// no robot or partition.
nlohmann::json EventData(const replay::Event& event, int64_t position);

/// One epoch map as the page's inspector shows it: [epoch, mode, members],
/// each member [id, phase, x_mm, y_mm, heading_mrad, vx_mm_s, vy_mm_s,
/// payload hex, payload decoded with `header`'s message format or null].
nlohmann::json MapData(const replay::EpochMap& map, const replay::Header& header);

}  // namespace syrof::lab::view
