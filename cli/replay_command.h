// `syrof replay FILE [--round N] [--robot ID] [--events-only] [--summary]
// [--format text|csv|jsonl] [--table frames|events|maps]`: prints a replay
// file (docs/replay.md) as text, or exports it as CSV or JSON Lines with the
// columns docs/replay.md documents ("Exporting").
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include <CLI/CLI.hpp>

namespace syrof::cli {

/// What `syrof replay` prints.
struct ReplayOptions {
  std::string file;                 ///< the replay file
  std::optional<uint32_t> round{};  ///< only this round index
  std::optional<uint16_t> robot{};  ///< only this robot's frames and the events naming it
  bool events_only = false;         ///< events only, no frames
  bool summary = false;             ///< counts instead of rounds; ignores the three filters
  std::string format = "text";      ///< text, csv or jsonl
  std::string table = "frames";     ///< with csv: frames, events or maps
};

/// Adds the `replay` subcommand to `app`, filling `options` when parsed, and
/// returns it (for the caller's callback or parsed() check). `options` must
/// outlive parsing.
CLI::App* SetupReplayCommand(CLI::App& app, ReplayOptions& options);

/// Prints the header of options.file, then per round a line per robot (time,
/// id, presence, status, phase, mode, epoch, true and estimated pose) and a
/// line per event, or with options.summary the counts (rounds, frames, events
/// by kind) and whether the file is complete. Returns 0 on success; 2 for bad
/// input (unreadable, damaged or truncated file, a robot or round the file
/// does not hold), with the message on `err` after whatever could be printed;
/// 1 for an internal failure (including `out` failing).
int RunReplayCommand(const ReplayOptions& options, std::ostream& out, std::ostream& err);

}  // namespace syrof::cli
