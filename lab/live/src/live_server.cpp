#include "syrof/lab/live/live_server.h"

#include <fmt/format.h>
#include <httplib.h>
#include <sys/socket.h>

#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>

#include "syrof/base/check.h"
#include "syrof/lab/view/page_data.h"
#include "syrof/lab/view/view.h"

namespace syrof::lab::live {
namespace {

using nlohmann::json;

// The page's policy (lab/view/assets/viewer.html) with the one thing the
// live page adds: its own /events.
constexpr const char* kPagePolicy =
    "default-src 'none'; style-src 'unsafe-inline'; script-src 'unsafe-inline'; img-src data:; connect-src 'self'";

int64_t WallMicroseconds() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string SseEvent(std::string_view name, const std::string& data, std::optional<uint64_t> id = std::nullopt) {
  std::string text;
  text.reserve(data.size() + 40);
  if (id) text += fmt::format("id: {}\n", *id);
  text += "event: ";
  text += name;
  text += "\ndata: ";
  text += data;  // JSON from nlohmann: one line
  text += "\n\n";
  return text;
}

// A server on a loopback address answers only requests that name a loopback
// host: a web page elsewhere that points a name of its own at 127.0.0.1 (DNS
// rebinding) gets 421, not the run.
bool IsLoopback(std::string_view address) {
  const bool dotted = !address.empty() && address.find_first_not_of("0123456789.") == std::string_view::npos;
  return (dotted && address.rfind("127.", 0) == 0) || address == "::1" || address == "localhost";
}
bool NamesLoopback(std::string_view host) {
  if (host.empty()) return true;  // HTTP/1.0: no Host
  if (host.front() == '[') return host.rfind("[::1]", 0) == 0;
  const std::string_view name = host.substr(0, host.find(':'));
  return IsLoopback(name);
}

std::chrono::milliseconds Milliseconds(double seconds) {
  return std::chrono::milliseconds(std::max<int64_t>(1, std::llround(seconds * 1000)));
}

}  // namespace

struct LiveServer::Impl {
  explicit Impl(const LiveOptions& live_options)
      : options(live_options),
        ring(std::llround(live_options.history_s * 1e9), live_options.max_rounds, live_options.max_bytes) {}

  // What a browser streaming /events has been sent.
  struct Client {
    uint64_t cursor = 0;
    bool header_sent = false;
  };
  bool Stream(Client& client, httplib::DataSink& sink);
  bool EndReady() const { return finished && (!options.replay_page_follows || replay_page_decided); }

  const LiveOptions options;
  httplib::Server server;

  // The recording thread's own: the header and each robot's latest frame
  // (a round may leave a robot out; the page wants every robot each round).
  replay::Header header;
  std::vector<replay::RobotFrame> current;
  uint64_t next_sequence = 0;

  // Shared with the HTTP threads, under `mutex`.
  mutable std::mutex mutex;
  std::condition_variable changed;
  RoundRing ring;
  std::shared_ptr<const std::string> header_event;
  std::shared_ptr<const std::string> replay_page;
  bool finished = false;
  bool complete = false;
  bool replay_page_decided = false;
  // Stop(): first every stream is sent what it has not had (draining), then
  // the server stops (stopping).
  bool draining = false;
  bool stopping = false;
  size_t clients = 0;
};

bool LiveServer::Impl::Stream(Client& client, httplib::DataSink& sink) {
  std::shared_ptr<const std::string> header_text;
  RoundRing::Taken taken;
  bool end = false;
  bool with_link = false;
  bool run_complete = false;
  bool closing = false;
  {
    std::unique_lock lock(mutex);
    changed.wait_for(lock, Milliseconds(options.keepalive_s), [&] {
      return stopping || draining || (!client.header_sent && header_event) ||
             (client.header_sent && (ring.end() > client.cursor || EndReady()));
    });
    if (stopping) return false;
    // Draining: the last write of this stream, with all the ring holds
    // past its cursor (httplib calls no stream again once it stops).
    closing = draining;
    if (!client.header_sent && header_event) {
      header_text = header_event;
      client.header_sent = true;
    }
    if (client.header_sent) {
      taken = ring.Take(client.cursor, closing ? ring.size() : options.batch_rounds);
      client.cursor = taken.next;
      end = EndReady() && client.cursor == ring.end();
      with_link = replay_page != nullptr;
      run_complete = complete;
    }
  }
  // No lock from here: a slow socket holds up this browser only.
  std::string out;
  if (header_text) out += *header_text;
  if (taken.skipped > 0) out += SseEvent("skipped", json{{"rounds", taken.skipped}}.dump());
  for (const auto& text : taken.texts) out += *text;
  if (end) {
    out += SseEvent("end", json{{"complete", run_complete},
                                {"replay", with_link ? json("replay.html") : json(nullptr)}}.dump());
  }
  if (out.empty() && closing) return false;
  if (out.empty()) out = ": idle\n\n";  // a write finds a browser that went away
  if (!sink.write(out.data(), out.size())) return false;
  // After the end, and when draining (that was the stream's last write),
  // the connection closes: a finished response would keep it open for
  // another request, and stopping the server would wait for that (httplib's
  // keep-alive, 5 s). The page closes its EventSource at the end anyway.
  return !end && !closing;
}

LiveServer::LiveServer(const LiveOptions& options) : options_(options), impl_(std::make_unique<Impl>(options)) {
  Impl& impl = *impl_;
  const size_t threads = options.max_clients + 4;  // the streams and a few page loads
  impl.server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  const auto seconds = static_cast<time_t>(options.write_timeout_s);
  impl.server.set_write_timeout(seconds, static_cast<time_t>((options.write_timeout_s - seconds) * 1e6));
  impl.server.set_payload_max_length(4096);  // nothing here takes a body
  // httplib's default also sets SO_REUSEPORT: a second server (another
  // run's) would then share the port and take half the browsers. Only
  // SO_REUSEADDR, so a taken port is an error Start reports.
  impl.server.set_socket_options([](socket_t socket) {
    int yes = 1;
    setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });

  const std::string page = view::RenderLivePage(
      json{{"data_version", view::kDataVersion}, {"status", "live"}, {"live", {{"events", "events"}}}}.dump(),
      options.title);
  impl.server.Get("/", [page](const httplib::Request&, httplib::Response& response) {
    response.set_header("Content-Security-Policy", kPagePolicy);
    response.set_header("X-Content-Type-Options", "nosniff");
    response.set_header("Cache-Control", "no-store");
    response.set_content(page, "text/html; charset=utf-8");
  });
  impl.server.Get("/replay.html", [&impl](const httplib::Request&, httplib::Response& response) {
    std::shared_ptr<const std::string> html;
    {
      std::lock_guard lock(impl.mutex);
      html = impl.replay_page;
    }
    response.set_header("X-Content-Type-Options", "nosniff");
    if (!html) {
      response.status = 404;
      response.set_content("No replay page (yet): the run has not ended, or wrote no replay.\n", "text/plain");
      return;
    }
    response.set_content(*html, "text/html; charset=utf-8");
  });
  impl.server.Get("/events", [&impl](const httplib::Request& request, httplib::Response& response) {
    auto client = std::make_shared<Impl::Client>();
    {
      std::lock_guard lock(impl.mutex);
      if (impl.clients >= impl.options.max_clients || impl.draining || impl.stopping) {
        response.status = 503;
        response.set_content("Too many browsers are watching this run.\n", "text/plain");
        return;
      }
      ++impl.clients;
      client->cursor = impl.ring.begin();
      // A browser that reconnects (EventSource does by itself) resumes
      // after the last round it had, if the ring still holds it.
      if (request.has_header("Last-Event-ID")) {
        try {
          const uint64_t last = std::stoull(request.get_header_value("Last-Event-ID"));
          client->cursor = std::min(last + 1, impl.ring.end());
        } catch (const std::exception&) {
          // not ours: from the start of the ring
        }
      }
    }
    response.set_header("Cache-Control", "no-store");
    response.set_header("X-Content-Type-Options", "nosniff");
    response.set_chunked_content_provider(
        "text/event-stream",
        [&impl, client](size_t, httplib::DataSink& sink) { return impl.Stream(*client, sink); },
        [&impl](bool) {
          {
            std::lock_guard lock(impl.mutex);
            --impl.clients;
          }
          impl.changed.notify_all();  // Stop() waits for the streams to end
        });
  });
}

LiveServer::~LiveServer() { Stop(); }

std::optional<Error> LiveServer::Start(const std::string& address, int port) {
  SYROF_CHECK(!thread_.joinable());
  const std::string where = fmt::format("{}:{}", address, port);
  if (port < 0 || port > 65535) return Error{.where = where, .message = "the port must be 0 to 65535"};
  int bound = port;
  if (port == 0) {
    bound = impl_->server.bind_to_any_port(address);
    if (bound < 0) return Error{.where = where, .message = "cannot listen there (not an address of this host?)"};
  } else if (!impl_->server.bind_to_port(address, port)) {
    return Error{.where = where, .message = "cannot listen there (the port is taken, or not an address of this host)"};
  }
  if (IsLoopback(address)) {
    impl_->server.set_pre_routing_handler([](const httplib::Request& request, httplib::Response& response) {
      if (NamesLoopback(request.get_header_value("Host"))) return httplib::Server::HandlerResponse::Unhandled;
      response.status = 421;
      response.set_content("This page answers only to 127.0.0.1 or localhost.\n", "text/plain");
      return httplib::Server::HandlerResponse::Handled;
    });
  }
  const bool v6 = address.find(':') != std::string::npos;
  listening_ = Listening{address, bound, fmt::format("http://{}{}{}:{}/", v6 ? "[" : "", address, v6 ? "]" : "", bound)};
  thread_ = std::thread([this] { impl_->server.listen_after_bind(); });
  // Until it listens, httplib's stop() does nothing: a Stop() right after
  // Start() would then wait for a server that never stops.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!impl_->server.is_running() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return std::nullopt;
}

void LiveServer::Stop() {
  {
    // Each browser streaming now first gets the rounds it has not had and,
    // once the run ended, the end with the replay's link: a command that
    // exits right after EndLive (--live-linger 0) leaves every page ended.
    // One that does not read is dropped after write_timeout_s, as always.
    std::unique_lock lock(impl_->mutex);
    impl_->draining = true;
    impl_->changed.notify_all();
    impl_->changed.wait_for(lock, Milliseconds(options_.write_timeout_s + options_.keepalive_s),
                            [&] { return impl_->clients == 0; });
    impl_->stopping = true;
  }
  impl_->changed.notify_all();
  impl_->server.stop();
  if (thread_.joinable()) thread_.join();
}

void LiveServer::OnHeader(const replay::Header& header) {
  impl_->header = header;
  impl_->current.assign(header.robots.size(), replay::RobotFrame{});
  for (size_t slot = 0; slot < header.robots.size(); ++slot) impl_->current[slot].id = header.robots[slot].id;
  auto text = std::make_shared<const std::string>(
      SseEvent("header", view::HeaderData(header, replay::kFormatVersion).dump()));
  {
    std::lock_guard lock(impl_->mutex);
    impl_->header_event = std::move(text);
  }
  impl_->changed.notify_all();
}

void LiveServer::OnRound(uint32_t index, int64_t time_ns, std::span<const replay::RobotFrame> robots,
                         std::span<const replay::Event> events, std::span<const replay::RobotMap> maps) {
  Impl& impl = *impl_;
  // Frames in increasing id order, as the header's robots (the writer's
  // contract): one walk carries them into every robot's latest.
  size_t slot = 0;
  for (const replay::RobotFrame& frame : robots) {
    while (slot < impl.current.size() && impl.current[slot].id < frame.id) ++slot;
    if (slot < impl.current.size() && impl.current[slot].id == frame.id) impl.current[slot] = frame;
  }
  json frames = json::array();
  for (const replay::RobotFrame& frame : impl.current) {
    frames.push_back({view::FrameState(frame), frame.epoch, view::Milli(frame.true_x_m), view::Milli(frame.true_y_m),
                      view::Milli(frame.true_heading_rad), view::Milli(frame.est_x_m), view::Milli(frame.est_y_m),
                      view::Milli(frame.est_heading_rad)});
  }
  json event_rows = json::array();
  for (const replay::Event& event : events) event_rows.push_back(view::EventData(event, 0));
  // Robots that started an epoch with the same map share it: sent once.
  json map_rows = json::array();
  json starts = json::array();
  std::map<const replay::EpochMap*, size_t> numbers;
  for (const replay::RobotMap& entry : maps) {
    if (!entry.map) continue;
    auto [found, inserted] = numbers.emplace(entry.map.get(), numbers.size());
    if (inserted) map_rows.push_back(view::MapData(*entry.map, impl.header));
    starts.push_back({entry.robot, found->second});
  }
  const json data = {{"i", index},          {"t", time_ns / 1000}, {"w", WallMicroseconds()}, {"f", std::move(frames)},
                     {"ev", std::move(event_rows)}, {"m", std::move(map_rows)}, {"st", std::move(starts)}};
  auto text = std::make_shared<const std::string>(SseEvent("round", data.dump(), impl.next_sequence++));
  {
    std::lock_guard lock(impl.mutex);
    impl.ring.Push(time_ns, std::move(text));
  }
  impl.changed.notify_all();
}

void LiveServer::OnFinish(bool complete) {
  {
    std::lock_guard lock(impl_->mutex);
    if (impl_->finished) return;
    impl_->finished = true;
    impl_->complete = complete;
  }
  impl_->changed.notify_all();
}

void LiveServer::SetReplayPage(std::optional<std::string> html) {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->replay_page_decided = true;
    if (html) impl_->replay_page = std::make_shared<const std::string>(std::move(*html));
  }
  impl_->changed.notify_all();
}

bool LiveServer::finished() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->finished;
}

size_t LiveServer::clients() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->clients;
}

uint64_t LiveServer::rounds() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->ring.end();
}

}  // namespace syrof::lab::live
