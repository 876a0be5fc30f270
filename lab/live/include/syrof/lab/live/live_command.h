// `--live[=ADDR:PORT]` and `--live-linger SECONDS`, shared by `syrof run`,
// `syrof swarm`, `syrof-bridge` and `syrof-firmware-swarm` (docs/viewer.md,
// "Live"): the live page's server started before the run, given the
// replay's page after it, and kept serving after the end for a while or
// until Ctrl-C. The CLI11 commands declare the options with
// SetupLiveOptions; a program with a parser of its own reads the same forms
// with ParseLiveAddress and kDefaultLiveAddress.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/lab/live/live_server.h"

namespace CLI {
class App;  // CLI11's; only SetupLiveOptions needs it, and its callers include it
}  // namespace CLI

namespace syrof::lab::live {

/// Where `--live` listens when given without a value: this host only.
inline constexpr const char* kDefaultLiveAddress = "127.0.0.1:8765";

struct LiveCommandOptions {
  std::string address;   ///< not empty: serve the live page there ("ADDR:PORT", "PORT", "[V6]:PORT")
  double linger_s = -1;  ///< after the end: serve this long; < 0: until Ctrl-C
  bool on() const { return !address.empty(); }
};

/// Declares --live and --live-linger on `command`.
void SetupLiveOptions(CLI::App& command, LiveCommandOptions& options);

/// The command line `argv[0..argc)` with each `--live ADDR` (a space)
/// joined into `--live=ADDR`, for a main to parse instead of argv: CLI11
/// gives a flag's optional value only after '=', and reads a spaced one as
/// an unexpected positional. Only an argument that ParseLiveAddress
/// accepts is joined (`--live run.yaml` keeps the scenario); nothing after
/// a `--` is touched.
std::vector<std::string> JoinLiveAddress(int argc, const char* const* argv);

/// "ADDR:PORT" (or "PORT": on 127.0.0.1) as an address and a port; false
/// with `problem` said for anything else.
bool ParseLiveAddress(const std::string& text, std::string& address, int& port, std::string& problem);

/// Starts `server` where `options` says and prints its URL on `out`; false
/// with the reason on `err` (prefixed by `command`).
bool StartLive(LiveServer& server, const LiveCommandOptions& options, const std::string& command,
               std::ostream& out, std::ostream& err);

/// After the run: gives `server` the page of the replay at `replay_path`
/// (none when empty), then serves on for `options.linger_s` or until
/// SIGINT/SIGTERM, saying so on `out`.
void EndLive(LiveServer& server, const LiveCommandOptions& options, const std::string& replay_path,
             std::ostream& out);

}  // namespace syrof::lab::live
