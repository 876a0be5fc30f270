#include "syrof/lab/live/live_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <thread>

#include "syrof/lab/view/view.h"

namespace syrof::lab::live {
namespace {

std::atomic<bool> g_live_stop{false};
void StopLinger(int) { g_live_stop.store(true); }

// What an address that ParseLiveAddress refuses should have been.
std::string AddressExpected() { return fmt::format("expected ADDR:PORT (like {}) or a port", kDefaultLiveAddress); }

}  // namespace

void SetupLiveOptions(CLI::App& command, LiveCommandOptions& options) {
  // A flag with an optional `=value`: `--live SCENARIO.yaml` must not take
  // the scenario for an address.
  // `--live ADDR:PORT` (a space) reaches here as `--live=ADDR:PORT`: the
  // main joins it first (JoinLiveAddress).
  command.add_flag(std::string("--live{") + kDefaultLiveAddress + "}", options.address,
                   fmt::format("Serve the live page while the run runs (docs/viewer.md \"Live\"): --live on {}, "
                               "--live ADDR:PORT or --live=ADDR:PORT elsewhere (port 0: a free one). Only this "
                               "host can open it unless you give another address.",
                               kDefaultLiveAddress));
  command.add_option("--live-linger", options.linger_s,
                     "After the run, keep the live page up this many seconds (default: until Ctrl-C)");
}

std::vector<std::string> JoinLiveAddress(int argc, const char* const* argv) {
  std::vector<std::string> arguments(argv, argv + argc);
  for (size_t i = 1; i + 1 < arguments.size(); ++i) {
    if (arguments[i] == "--") break;
    if (arguments[i] != "--live") continue;
    std::string address, problem;
    int port = 0;
    if (!ParseLiveAddress(arguments[i + 1], address, port, problem)) continue;
    arguments[i] += "=" + arguments[i + 1];
    arguments.erase(arguments.begin() + static_cast<std::ptrdiff_t>(i) + 1);
  }
  return arguments;
}

bool ParseLiveAddress(const std::string& text, std::string& address, int& port, std::string& problem) {
  std::string port_text = text;
  address = "127.0.0.1";
  if (const size_t colon = text.rfind(':'); colon != std::string::npos) {
    address = text.substr(0, colon);
    port_text = text.substr(colon + 1);
    if (address.size() >= 2 && address.front() == '[' && address.back() == ']') {
      address = address.substr(1, address.size() - 2);
    }
  }
  const bool digits = !port_text.empty() && port_text.size() <= 5 &&
                      port_text.find_first_not_of("0123456789") == std::string::npos;
  if (address.empty() || !digits || std::stoi(port_text) > 65535) {
    problem = fmt::format("--live={}: {}", text, AddressExpected());
    return false;
  }
  port = std::stoi(port_text);
  return true;
}

LiveResult StartLive(const LiveCommandOptions& options, const std::string& subject, std::ostream& out,
                     std::vector<replay::RoundSink*>& sinks) {
  LiveResult result;
  if (!options.on()) return result;
  std::string address, problem;
  int port = 0;
  if (!ParseLiveAddress(options.address, address, port, problem)) {
    result.error = Error{.where = "--live=" + options.address, .message = AddressExpected()};
    return result;
  }
  LiveOptions live_options;
  live_options.replay_page_follows = true;
  live_options.title = "SyROF live: " + subject;
  auto server = std::make_unique<LiveServer>(live_options);
  if (const std::optional<Error> error = server->Start(address, port)) {
    result.error = Error{.where = "--live", .message = "the live page cannot listen on " + error->ToString()};
    return result;
  }
  fmt::print(out, "  live page: {}\n", server->listening().url);
  out.flush();
  sinks.push_back(server.get());
  result.server = std::move(server);
  return result;
}

void EndLive(LiveServer& server, const LiveCommandOptions& options, const std::string& replay_path,
             std::ostream& out) {
  std::optional<std::string> page;
  if (!replay_path.empty()) {
    std::ifstream in(replay_path, std::ios::binary);
    if (in) page = lab::view::BuildPage(in, replay_path).html;
  }
  server.SetReplayPage(std::move(page));
  if (options.linger_s == 0) return;
  g_live_stop.store(false);
  struct sigaction action {};
  struct sigaction old_int {}, old_term {};
  action.sa_handler = StopLinger;
  sigaction(SIGINT, &action, &old_int);
  sigaction(SIGTERM, &action, &old_term);
  if (options.linger_s < 0) {
    fmt::print(out, "  the run ended; the live page stays up at {} until Ctrl-C\n", server.listening().url);
  } else {
    fmt::print(out, "  the run ended; the live page stays up at {} for {:g} s (Ctrl-C ends it now)\n",
               server.listening().url, options.linger_s);
  }
  out.flush();
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::max(0.0, options.linger_s));
  while (!g_live_stop.load() && (options.linger_s < 0 || std::chrono::steady_clock::now() < until)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
}

}  // namespace syrof::lab::live
