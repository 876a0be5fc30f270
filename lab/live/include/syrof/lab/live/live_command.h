// `--live[=ADDR:PORT]` and `--live-linger SECONDS`, shared by `syrof run`,
// `syrof swarm`, `syrof-bridge` and `syrof-firmware-swarm` (docs/viewer.md,
// "Live"): the live page's server started before the run, given the
// replay's page after it, and kept serving after the end for a while or
// until Ctrl-C. The CLI11 commands declare the options with
// SetupLiveOptions; a program with a parser of its own reads the same forms
// with ParseLiveAddress and kDefaultLiveAddress.
#pragma once

#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/live/live_server.h"
#include "syrof/lab/replay/round_sink.h"

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

/// A run's live page (StartLive), or why it could not start.
struct LiveResult {
  std::unique_ptr<LiveServer> server;  ///< null when --live is off, or on an error
  std::optional<Error> error;          ///< a usage error: the caller exits 2
  bool ok() const { return !error.has_value(); }
};

/// The live page of a run, when `options.on()`: a LiveServer titled
/// "SyROF live: SUBJECT" whose end waits for the replay's page (EndLive),
/// listening where `options` says, its URL printed on `out`, and put last
/// into `sinks` (the rounds it shows). With --live off: no server, nothing
/// printed, `sinks` unchanged. An address that does not parse
/// ("--live=TEXT: expected ADDR:PORT ...") or that this host cannot listen
/// on ("--live: the live page cannot listen on ADDR:PORT: ...") is the
/// error; the caller prints it after its name, as `syrof run: ` does.
LiveResult StartLive(const LiveCommandOptions& options, const std::string& subject, std::ostream& out,
                     std::vector<replay::RoundSink*>& sinks);

/// After the run: gives `server` the page of the replay at `replay_path`
/// (none when empty), then serves on for `options.linger_s` or until
/// SIGINT/SIGTERM, saying so on `out`.
void EndLive(LiveServer& server, const LiveCommandOptions& options, const std::string& replay_path,
             std::ostream& out);

}  // namespace syrof::lab::live
