// `syrof view REPLAY [-o FILE.html]`: writes the replay's page, one
// self-contained HTML file (lab/view, docs/viewer.md).
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

#include "syrof/lab/base/error.h"

namespace syrof::lab::view {
struct PageOptions;  // syrof/lab/view/view.h
}  // namespace syrof::lab::view

namespace syrof::cli {

struct ViewOptions {
  std::string file{};    ///< the replay
  std::string output{};  ///< the page; default: the replay's path with .html
  /// The run's metrics.json, for the verdict; default: metrics.json beside
  /// the replay, when there is one.
  std::string metrics{};
  std::string scenario{};  ///< the run's scenario, for the goal's target; none by default
};

/// Declares the subcommand on `app`.
CLI::App* SetupViewCommand(CLI::App& app, ViewOptions& options);

/// Writes the page. Returns 0 when the replay was complete; 2 for bad input
/// (a replay that cannot be opened, or is empty, cut short, damaged or of a
/// newer format: the page is still written and says so, and `err` says
/// why); 1 when the page cannot be written.
int RunViewCommand(const ViewOptions& options, std::ostream& out, std::ostream& err);

/// The page's path for a replay when no -o is given: REPLAY.html next to it.
std::string DefaultPagePath(const std::string& replay_path);

/// Writes the page of the replay at `replay_path` to `page_path` (for `syrof
/// run --html` and `syrof search`, which hand the run's metrics and
/// scenario in `options`: the verdict and the goal's target). Returns what
/// went wrong, if anything (a replay that is not whole: its reader's error).
std::optional<lab::Error> WritePage(const std::string& replay_path, const std::string& page_path,
                                    const lab::view::PageOptions& options);

}  // namespace syrof::cli
