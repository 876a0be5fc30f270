// `syrof view`'s page: one self-contained HTML file showing a replay (the
// arena, time controls, events, a robot inspector with its LDMap, plots).
//
// The replay is untrusted. lab/replay's reader decodes it; only what the
// reader accepted becomes the page's data, embedded as JSON (docs/viewer.md,
// "The page's data"). A replay that is empty, cut short, damaged or of a
// newer format still gives a page, which says so in words (with what was
// read before the problem, if anything).
#pragma once

#include <cstddef>
#include <istream>
#include <optional>
#include <string>

#include "syrof/lab/base/error.h"
#include "syrof/lab/metrics/metrics.h"

namespace syrof::lab::scenario {
struct Scenario;  // syrof/lab/scenario/scenario.h (not included: it brings Eigen, which lab/live's HTTP headers break)
}  // namespace syrof::lab::scenario

namespace syrof::lab::view {

/// Limits of the page's data.
struct PageOptions {
  /// Frames kept for drawing: when robots x rounds exceeds this, every
  /// k-th round's frames are kept (the smallest k that fits). Events and
  /// maps are never dropped.
  size_t max_robot_frames = 600'000;
  /// The run's metrics, for the verdict banner (verdict.h); unset: the
  /// page judges what the replay alone shows and says the goal is unknown.
  std::optional<metrics::Metrics> metrics;
  /// The run's scenario, for the goal's target in the arena (verdict.h:
  /// GoalTargets); null: no target drawn. Outlives the call.
  const scenario::Scenario* scenario = nullptr;
};

/// The page and what went into it.
struct Page {
  std::string html;             ///< the whole HTML file
  bool complete = false;        ///< the replay was read to a valid end marker
  std::optional<Error> error;   ///< why not; the page shows the same message
  size_t rounds = 0;            ///< rounds read
  size_t events = 0;            ///< events read (all of them are in the page)
  size_t frame_stride = 1;      ///< 1: every round's frames are in the page
};

/// Reads a replay from `in` (`name` names it in messages and the page's
/// title) and builds its page. Never throws for bad input.
Page BuildPage(std::istream& in, const std::string& name, const PageOptions& options = {});

/// The page's data for `in`, the JSON text BuildPage embeds (for tests and
/// tools). Fills `page` except `html`.
std::string ReplayJson(std::istream& in, const std::string& name, const PageOptions& options, Page& page);

/// The page around `data_json` (trusted JSON text, as ReplayJson makes it).
std::string RenderPage(const std::string& data_json, const std::string& title);

/// The same page for the live server (lab/live): its Content-Security-Policy
/// also allows connecting to its own origin (connect-src 'self', for
/// /events); `data_json` says "live" (docs/viewer.md, "Live").
std::string RenderLivePage(const std::string& data_json, const std::string& title);

}  // namespace syrof::lab::view
