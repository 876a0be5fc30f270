// The summary `syrof run` and `syrof swarm` print after a run, from its
// metrics (lab/metrics, docs/metrics.md): synchrony, common knowledge,
// collisions, safety, agreement, estimation, membership, round phase, the
// goal and the app's misbehaviour, one line each. It reads the typed
// structure metrics.json is written from, so a renamed field is a compile
// error here, never a silent "-".
#pragma once

#include <filesystem>
#include <ostream>
#include <string_view>

#include "syrof/lab/metrics/metrics.h"

namespace syrof::cli {

/// Prints the summary of the run whose metrics are `m` and whose outputs are
/// in `dir`: `replay` and `html` name the files written, `library` a
/// student's library (its robots' logs, and a note when no goal is
/// declared), `clocks` real clocks (the round-phase line). `title` starts
/// the first line ("SyROF run", "SyROF swarm").
void PrintSummary(std::ostream& out, const lab::metrics::Metrics& m, const std::filesystem::path& dir, bool replay,
                  bool library, bool html, bool clocks, std::string_view title = "SyROF run");

/// Whether the app faulted, returned an invalid command or had a payload
/// refused in the run of `m` (`syrof run --strict` exits 3 then).
bool AppMisbehaved(const lab::metrics::Metrics& m);

}  // namespace syrof::cli
