#include "syrof/lab/live/live_server.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "sse_client.h"

namespace syrof::lab::live {
namespace {

using nlohmann::json;
using std::chrono::milliseconds;
using testing::SseClient;
using testing::SseEvent;

constexpr int64_t kRoundNs = 50'000'000;

replay::Header MakeHeader(uint16_t robots) {
  replay::Header header;
  header.seed = 7;
  header.radio_round_ns = kRoundNs;
  header.arena_width_m = 10;
  header.arena_height_m = 8;
  header.scenario_name = "live test";
  header.app_name = "builtin:idle";
  for (uint16_t id = 0; id < robots; ++id) header.robots.push_back(replay::RobotInfo{id, 0, 0.1f, {}});
  return header;
}

// Round `n` of a run of `robots`: every robot running at x = n mm.
void PushRound(LiveServer& server, uint16_t robots, uint32_t n, std::vector<replay::Event> events = {}) {
  std::vector<replay::RobotFrame> frames(robots);
  for (uint16_t id = 0; id < robots; ++id) {
    frames[id].id = id;
    frames[id].presence = replay::Presence::kRunning;
    frames[id].true_x_m = static_cast<float>(n) / 1000.0f;
  }
  server.OnRound(n, static_cast<int64_t>(n + 1) * kRoundNs, frames, events, {});
}

std::unique_ptr<LiveServer> Started(const LiveOptions& options = {}) {
  auto server = std::make_unique<LiveServer>(options);
  EXPECT_FALSE(server->Start("127.0.0.1", 0).has_value());
  return server;
}

size_t Count(const std::vector<SseEvent>& events, const std::string& name) {
  return static_cast<size_t>(std::count_if(events.begin(), events.end(), [&](const SseEvent& e) { return e.name == name; }));
}
auto HasEvent(const std::string& name) {
  return [name](const std::vector<SseEvent>& events) { return Count(events, name) > 0; };
}
auto HasRounds(size_t rounds) {
  return [rounds](const std::vector<SseEvent>& events) { return Count(events, "round") >= rounds; };
}

TEST(LiveServer, ListensOnLoopbackAtTheGivenOrAFreePort) {
  LiveServer server;
  ASSERT_FALSE(server.Start("127.0.0.1", 0).has_value());
  EXPECT_GT(server.listening().port, 0);
  EXPECT_EQ(server.listening().url, "http://127.0.0.1:" + std::to_string(server.listening().port) + "/");
  LiveServer same_port;
  EXPECT_TRUE(same_port.Start("127.0.0.1", server.listening().port).has_value());  // taken: said, not thrown
}

TEST(LiveServer, ServesThePageInLiveModeWithItsPolicyAndNothingElse) {
  auto server = Started();
  SseClient page;
  ASSERT_TRUE(page.Get(server->listening().port, "/"));
  page.ReadUntil([&](const auto&) { return page.body().find("</html>") != std::string::npos; }, milliseconds(5000));
  EXPECT_EQ(page.status(), 200);
  EXPECT_NE(page.headers().find("connect-src 'self'"), std::string::npos);
  EXPECT_NE(page.body().find("connect-src 'self'"), std::string::npos);  // the page's own meta policy
  EXPECT_NE(page.body().find(R"("live":{"events":"events"})"), std::string::npos);
  for (const std::string path : {"/../etc/passwd", "/viewer.js", "/index.html", "/replay"}) {
    SseClient other;
    ASSERT_TRUE(other.Get(server->listening().port, path));
    other.ReadUntil([&](const auto&) { return other.status() != 0; }, milliseconds(5000));
    EXPECT_EQ(other.status(), 404) << path;
  }
  SseClient replay_page;  // before the run ended
  ASSERT_TRUE(replay_page.Get(server->listening().port, "/replay.html"));
  replay_page.ReadUntil([&](const auto&) { return replay_page.status() != 0; }, milliseconds(5000));
  EXPECT_EQ(replay_page.status(), 404);
}

TEST(LiveServer, OnLoopbackItAnswersOnlyRequestsThatNameALoopbackHost) {
  auto server = Started();
  for (const std::string host : {"127.0.0.1", "localhost:8765", "127.0.0.1:1"}) {
    SseClient client;
    ASSERT_TRUE(client.Get(server->listening().port, "/", 0, host));
    client.ReadUntil([&](const auto&) { return client.status() != 0; }, milliseconds(5000));
    EXPECT_EQ(client.status(), 200) << host;
  }
  for (const std::string host : {"attacker.example", "attacker.example:8765", "127.0.0.1.attacker.example"}) {
    SseClient client;
    ASSERT_TRUE(client.Get(server->listening().port, "/events", 0, host));
    client.ReadUntil([&](const auto&) { return client.status() != 0; }, milliseconds(5000));
    EXPECT_EQ(client.status(), 421) << host;
  }
}

TEST(LiveServer, StreamsTheHeaderThenTheRoundsAsTheyComeThenTheEndWithTheLink) {
  LiveOptions options;
  options.replay_page_follows = true;
  auto server = Started(options);
  server->OnHeader(MakeHeader(3));
  SseClient client;
  ASSERT_TRUE(client.Get(server->listening().port, "/events"));
  ASSERT_TRUE(client.ReadUntil(HasEvent("header"), milliseconds(5000))) << client.headers() << "\n" << client.body();
  EXPECT_NE(client.headers().find("text/event-stream"), std::string::npos);
  const json header = json::parse(client.events()[0].data);
  EXPECT_EQ(header["scenario"], "live test");
  EXPECT_EQ(header["robots"].size(), 3u);

  replay::Event crash{replay::EventKind::kCrash, 1, replay::kNoRobot, 4, 0, 2 * kRoundNs, replay::kNoPartition};
  for (uint32_t n = 0; n < 10; ++n) PushRound(*server, 3, n, n == 1 ? std::vector{crash} : std::vector<replay::Event>{});
  ASSERT_TRUE(client.ReadUntil(HasRounds(10), milliseconds(5000)));
  const json second = json::parse(client.events()[2].data);
  EXPECT_EQ(client.events()[2].id, "1");
  EXPECT_EQ(second["i"], 1);
  EXPECT_EQ(second["t"], 2 * kRoundNs / 1000);
  ASSERT_EQ(second["f"].size(), 3u);
  EXPECT_EQ(second["f"][0][2], 1);  // x in mm
  ASSERT_EQ(second["ev"].size(), 1u);
  EXPECT_EQ(second["ev"][0][1], static_cast<int>(replay::EventKind::kCrash));

  server->OnFinish(true);
  EXPECT_FALSE(client.ReadUntil(HasEvent("end"), milliseconds(300)));  // waits for the replay page
  server->SetReplayPage("<html>the replay</html>");
  ASSERT_TRUE(client.ReadUntil(HasEvent("end"), milliseconds(5000)));
  const json end = json::parse(client.events().back().data);
  EXPECT_EQ(end["complete"], true);
  EXPECT_EQ(end["replay"], "replay.html");

  SseClient replay_page;
  ASSERT_TRUE(replay_page.Get(server->listening().port, "/replay.html"));
  replay_page.ReadUntil([&](const auto&) { return replay_page.body().find("</html>") != std::string::npos; },
                        milliseconds(5000));
  EXPECT_EQ(replay_page.status(), 200);
  EXPECT_EQ(replay_page.body(), "<html>the replay</html>");
}

// A command that exits right after the run (`--live-linger 0`) stops its
// server at once: a browser still taking the last rounds gets them all and
// the end with the replay's link first. (The stream was cut where it was,
// the end never sent: a page left saying Live.)
TEST(LiveServer, StoppingRightAfterTheEndStillSendsEachBrowserTheRestAndTheEnd) {
  LiveOptions options;
  options.replay_page_follows = true;
  options.history_s = 3600;       // the ring keeps every round: none skipped
  options.write_timeout_s = 120;  // the browser reads only after the stop: not dropped for it
  auto server = Started(options);
  server->OnHeader(MakeHeader(100));
  SseClient client;
  // A small window, read only after the stop: with megabytes of rounds
  // (3,000 rounds of 100 robots) the stream is still writing when Stop() comes.
  ASSERT_TRUE(client.Get(server->listening().port, "/events", 4096));
  ASSERT_TRUE(client.ReadUntil(HasEvent("header"), milliseconds(5000)));
  for (uint32_t n = 0; n < 3000; ++n) PushRound(*server, 100, n);
  server->OnFinish(true);
  server->SetReplayPage("<html>the replay</html>");
  std::thread stopping([&server] { server->Stop(); });
  const bool ended = client.ReadUntil(HasEvent("end"), milliseconds(30000));
  stopping.join();
  ASSERT_TRUE(ended) << Count(client.events(), "round") << " rounds, closed " << client.closed();
  EXPECT_EQ(Count(client.events(), "round"), 3000u);
  EXPECT_EQ(Count(client.events(), "skipped"), 0u);
  EXPECT_EQ(json::parse(client.events().back().data)["replay"], "replay.html");
  EXPECT_EQ(server->clients(), 0u);
}

TEST(LiveServer, ABrowserThatOpensLateSeesTheLastMinute) {
  auto server = Started();
  server->OnHeader(MakeHeader(2));
  for (uint32_t n = 0; n < 1800; ++n) PushRound(*server, 2, n);  // 90 s
  SseClient client;
  ASSERT_TRUE(client.Get(server->listening().port, "/events"));
  ASSERT_TRUE(client.ReadUntil(HasRounds(1201), milliseconds(10000)));
  const json first = json::parse(client.events()[1].data);
  EXPECT_EQ(first["t"], int64_t{1800} * kRoundNs / 1000 - 60'000'000);  // 60 s before the newest
  EXPECT_EQ(Count(client.events(), "skipped"), 0u);
  PushRound(*server, 2, 1800);  // and goes on live
  ASSERT_TRUE(client.ReadUntil(HasRounds(1202), milliseconds(5000)));
}

TEST(LiveServer, ABrowserThatNeverReadsDoesNotSlowTheRecordingAndIsDropped) {
  LiveOptions options;
  // Long enough that a push which waited on the stalled socket would stand
  // out from any machine's slowness: under AddressSanitizer on a loaded CI
  // machine a push took 104 ms, past the 50 ms bound this test once had.
  options.write_timeout_s = 2.0;
  options.keepalive_s = 0.1;
  auto server = Started(options);
  server->OnHeader(MakeHeader(100));
  SseClient stalled;
  ASSERT_TRUE(stalled.Get(server->listening().port, "/events", 4096));  // and never reads again
  SseClient reader;
  ASSERT_TRUE(reader.Get(server->listening().port, "/events"));
  const auto until = std::chrono::steady_clock::now() + milliseconds(3000);
  while (server->clients() < 2 && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(milliseconds(5));
  ASSERT_EQ(server->clients(), 2u);

  // The other browser reads all along, on a thread of its own (reading
  // only now and then, it was itself dropped as stalled under ASan, where
  // the pushes below take longer than the write timeout).
  bool reached_newest = false;
  std::thread reading([&reader, &reached_newest] {
    reached_newest = reader.ReadUntil(
        [](const std::vector<SseEvent>& events) { return !events.empty() && events.back().id == "2999"; },
        milliseconds(60000));
  });
  // 100 robots, 3,000 rounds: megabytes the stalled browser cannot take.
  int64_t slowest_us = 0;
  for (uint32_t n = 0; n < 3000; ++n) {
    const auto start = std::chrono::steady_clock::now();
    PushRound(*server, 100, n);
    slowest_us = std::max<int64_t>(
        slowest_us, std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start).count());
  }
  // A round's conversion is a few hundred µs; a push that waited for the
  // stalled socket would take the whole write timeout (2 s). Half of it
  // tells the two apart on any machine.
  EXPECT_LT(slowest_us, 1'000'000);
  // The reading browser gets to the newest round.
  reading.join();
  ASSERT_TRUE(reached_newest);
  const auto dropped_by = std::chrono::steady_clock::now() + milliseconds(10000);
  while (server->clients() > 1 && std::chrono::steady_clock::now() < dropped_by) std::this_thread::sleep_for(milliseconds(20));
  EXPECT_EQ(server->clients(), 1u);  // the stalled one, after its write timeout
}

TEST(LiveServer, ABrowserThatFallsBehindTheRingSkipsAheadAndIsTold) {
  LiveOptions options;
  options.max_rounds = 50;
  options.batch_rounds = 10;
  // The browser reads nothing until the 3000 rounds are pushed, which took
  // over 5 s under AddressSanitizer on a loaded machine (CI, 2026-11-29):
  // the default write timeout then dropped it before it could skip ahead.
  // Being dropped is another test's subject.
  options.write_timeout_s = 120;
  auto server = Started(options);
  server->OnHeader(MakeHeader(100));
  SseClient client;
  ASSERT_TRUE(client.Get(server->listening().port, "/events", 4096));
  ASSERT_TRUE(client.ReadUntil(HasEvent("header"), milliseconds(5000)));
  // Rounds of 100 robots (kilobytes each) pushed while the browser reads
  // nothing: its socket fills, its stream waits, and the rounds it has not
  // read leave the ring (50 rounds) long before it reads again.
  for (uint32_t n = 0; n < 3000; ++n) PushRound(*server, 100, n);
  server->OnFinish(true);
  ASSERT_TRUE(client.ReadUntil(HasEvent("end"), milliseconds(10000)));
  EXPECT_GT(Count(client.events(), "skipped"), 0u);
  EXPECT_LT(Count(client.events(), "round"), 3000u);
  const json last = json::parse(client.events()[client.events().size() - 2].data);
  EXPECT_EQ(last["i"], 2999);  // it still got to the newest round
  EXPECT_EQ(json::parse(client.events().back().data)["replay"], nullptr);  // no page was promised
}

TEST(LiveServer, SeveralBrowsersGetTheSameRoundsAndOneThatLeavesIsForgotten) {
  LiveOptions options;
  options.keepalive_s = 0.05;
  auto server = Started(options);
  server->OnHeader(MakeHeader(2));
  std::vector<std::unique_ptr<SseClient>> clients;
  for (int i = 0; i < 5; ++i) {
    clients.push_back(std::make_unique<SseClient>());
    ASSERT_TRUE(clients.back()->Get(server->listening().port, "/events"));
    ASSERT_TRUE(clients.back()->ReadUntil(HasEvent("header"), milliseconds(5000)));
  }
  clients[4]->Close();  // a browser tab closed
  for (uint32_t n = 0; n < 200; ++n) PushRound(*server, 2, n);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(clients[i]->ReadUntil(HasRounds(200), milliseconds(5000)));
    EXPECT_EQ(clients[i]->events()[200].data, clients[0]->events()[200].data);
  }
  const auto until = std::chrono::steady_clock::now() + milliseconds(5000);
  while (server->clients() > 4 && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(milliseconds(10));
  EXPECT_EQ(server->clients(), 4u);
}

TEST(LiveServer, RefusesBrowsersBeyondItsLimit) {
  LiveOptions options;
  options.max_clients = 2;
  auto server = Started(options);
  server->OnHeader(MakeHeader(1));
  SseClient a, b, c;
  ASSERT_TRUE(a.Get(server->listening().port, "/events"));
  ASSERT_TRUE(a.ReadUntil(HasEvent("header"), milliseconds(5000)));
  ASSERT_TRUE(b.Get(server->listening().port, "/events"));
  ASSERT_TRUE(b.ReadUntil(HasEvent("header"), milliseconds(5000)));
  ASSERT_TRUE(c.Get(server->listening().port, "/events"));
  c.ReadUntil([&](const auto&) { return c.status() != 0; }, milliseconds(5000));
  EXPECT_EQ(c.status(), 503);
}

TEST(LiveServer, ABrowserThatReconnectsResumesAfterItsLastRound) {
  auto server = Started();
  server->OnHeader(MakeHeader(1));
  for (uint32_t n = 0; n < 20; ++n) PushRound(*server, 1, n);
  SseClient client;
  ASSERT_TRUE(client.Get(server->listening().port, "/events"));
  // Last-Event-ID by hand: the request SseClient sends has none.
  client.Close();
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(server->listening().port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  const std::string request = "GET /events HTTP/1.1\r\nHost: 127.0.0.1\r\nLast-Event-ID: 14\r\n\r\n";
  ASSERT_EQ(send(fd, request.data(), request.size(), MSG_NOSIGNAL), static_cast<ssize_t>(request.size()));
  std::string got;
  const auto until = std::chrono::steady_clock::now() + milliseconds(5000);
  while (got.find("id: 19") == std::string::npos && std::chrono::steady_clock::now() < until) {
    char buffer[4096];
    pollfd poll_fd{fd, POLLIN, 0};
    if (poll(&poll_fd, 1, 100) <= 0) continue;
    const ssize_t n = recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    got.append(buffer, static_cast<size_t>(n));
  }
  close(fd);
  EXPECT_EQ(got.find("id: 14\n"), std::string::npos);
  EXPECT_NE(got.find("id: 15\n"), std::string::npos);
  EXPECT_NE(got.find("id: 19\n"), std::string::npos);
}

}  // namespace
}  // namespace syrof::lab::live
