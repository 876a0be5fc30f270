// The live page: the viewer's page (lab/view) served over HTTP while a run
// runs, updated through Server-Sent Events (docs/viewer.md, "Live").
//
// A LiveServer is a plain replay::RoundSink: give it to a RoundRecorder (the
// lab's SimulationOptions::sinks, `syrof swarm`'s SwarmOptions::sinks) or
// call it from any program that has rounds (`syrof-bridge`). It serves
//   GET /             the viewer's page in live mode (its data says "live,
//                     connect to /events"), assets inline;
//   GET /events       the SSE stream: `header` (the page's header data),
//                     then `round` events (id: the round's sequence number),
//                     `skipped` when this browser fell behind the ring, and
//                     `end` once the run ended (with the replay page's link);
//   GET /replay.html  the replay's page, once SetReplayPage gave it;
// and nothing else (404).
//
// Threads: the On* calls come on the recording thread and only convert the
// round (O(its size)) and push it into the ring under a short lock; they
// never wait for a browser. Each browser is served on an HTTP thread of its
// own with its own cursor into the ring; no lock is held while writing to a
// socket. A browser that opens late gets the last `history_s` of world
// time; one that reads too slowly skips ahead; one that does not read for
// `write_timeout_s` is disconnected. Memory is the ring's, bounded by
// LiveOptions, plus a bounded batch per browser.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/live/round_ring.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/replay/round_sink.h"

namespace syrof::lab::live {

struct LiveOptions {
  double history_s = 60;                  ///< world time a browser that opens late sees
  size_t max_rounds = 20'000;             ///< the ring's bound in rounds, whatever the round
  size_t max_bytes = 64u << 20;           ///< the ring's bound in bytes of text
  size_t max_clients = 16;                ///< browsers streaming at once; more get 503
  size_t batch_rounds = 64;               ///< rounds a browser is sent per write, at most
  double write_timeout_s = 5;             ///< a browser that takes no data this long is dropped
  double keepalive_s = 1;                 ///< a comment this often when idle (finds closed browsers)
  /// The end event waits for SetReplayPage (the command builds the replay's
  /// page after the run): the page then links it.
  bool replay_page_follows = false;
  std::string title = "SyROF live";       ///< the page's title
};

/// Where Start bound: "http://127.0.0.1:8080/".
struct Listening {
  std::string address;
  int port = 0;
  std::string url;
};

class LiveServer : public replay::RoundSink {
 public:
  explicit LiveServer(const LiveOptions& options = {});
  ~LiveServer() override;  // Stop()
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;

  /// Binds `address` (an IP address, "127.0.0.1" for this host only) and
  /// `port` (0: a free one) and serves on a thread of its own. Fails (with
  /// the reason) when the address cannot be bound. At most once.
  std::optional<Error> Start(const std::string& address, int port);
  /// Where it listens, after a successful Start.
  const Listening& listening() const { return listening_; }
  /// Sends each browser streaming now the rounds it has not had and, once
  /// the run ended (and the replay's page was decided), the end; then ends
  /// every stream and stops serving, and waits for the server's threads. A
  /// browser that does not read holds it up to write_timeout_s.
  void Stop();

  // replay::RoundSink: the recording thread's calls.
  void OnHeader(const replay::Header& header) override;
  void OnRound(uint32_t index, int64_t time_ns, std::span<const replay::RobotFrame> robots,
               std::span<const replay::Event> events, std::span<const replay::RobotMap> maps) override;
  void OnFinish(bool complete) override;

  /// The replay's page (served at /replay.html, linked from the end), or
  /// none (no replay was written): either lets the end event go out when
  /// LiveOptions::replay_page_follows.
  void SetReplayPage(std::optional<std::string> html);

  /// Whether OnFinish came.
  bool finished() const;
  /// Browsers streaming now (for tests and the bench).
  size_t clients() const;
  /// Rounds recorded since the start (the ring's end sequence).
  uint64_t rounds() const;

 private:
  struct Impl;
  LiveOptions options_;
  Listening listening_;
  std::unique_ptr<Impl> impl_;
  std::thread thread_;
};

}  // namespace syrof::lab::live
