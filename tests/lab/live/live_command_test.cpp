// JoinLiveAddress: `--live ADDR:PORT` (a space) joined into the only form
// CLI11 reads, `--live=ADDR:PORT`, and nothing else touched. StartLive: the
// live page's start that `syrof run`, `syrof swarm`, `syrof-bridge` and
// `syrof-firmware-swarm` share, and the usage errors they print.
#include "syrof/lab/live/live_command.h"

#include <gtest/gtest.h>

#include <chrono>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "sse_client.h"

namespace syrof::lab::live {
namespace {

std::vector<std::string> Join(std::vector<const char*> argv) {
  return JoinLiveAddress(static_cast<int>(argv.size()), argv.data());
}

using Arguments = std::vector<std::string>;

TEST(JoinLiveAddress, JoinsAnAddressGivenAfterASpace) {
  EXPECT_EQ(Join({"syrof", "run", "a.yaml", "--live", "127.0.0.1:8765"}),
            (Arguments{"syrof", "run", "a.yaml", "--live=127.0.0.1:8765"}));
  EXPECT_EQ(Join({"syrof", "run", "--live", "0.0.0.0:0", "a.yaml"}),
            (Arguments{"syrof", "run", "--live=0.0.0.0:0", "a.yaml"}));
  EXPECT_EQ(Join({"syrof", "swarm", "--live", "[::1]:9000", "a.yaml"}),
            (Arguments{"syrof", "swarm", "--live=[::1]:9000", "a.yaml"}));
  EXPECT_EQ(Join({"syrof", "run", "--live", "8766", "a.yaml"}), (Arguments{"syrof", "run", "--live=8766", "a.yaml"}));
}

TEST(JoinLiveAddress, LeavesAScenarioAfterLiveAndEveryOtherArgumentAlone) {
  EXPECT_EQ(Join({"syrof", "run", "--live", "a.yaml"}), (Arguments{"syrof", "run", "--live", "a.yaml"}));
  EXPECT_EQ(Join({"syrof", "run", "a.yaml", "--live"}), (Arguments{"syrof", "run", "a.yaml", "--live"}));
  EXPECT_EQ(Join({"syrof", "run", "a.yaml", "--live=127.0.0.1:1"}),
            (Arguments{"syrof", "run", "a.yaml", "--live=127.0.0.1:1"}));
  EXPECT_EQ(Join({"syrof", "run", "a.yaml", "--live-linger", "5"}),
            (Arguments{"syrof", "run", "a.yaml", "--live-linger", "5"}));
  EXPECT_EQ(Join({"syrof", "run", "--", "--live", "127.0.0.1:1"}),
            (Arguments{"syrof", "run", "--", "--live", "127.0.0.1:1"}));
  EXPECT_EQ(Join({"--live", "127.0.0.1:1"}), (Arguments{"--live", "127.0.0.1:1"})) << "argv[0] is the program";
}

// A sink that is already there before the live page (the replay's, say).
class OtherSink : public replay::RoundSink {
 public:
  void OnHeader(const replay::Header&) override {}
  void OnRound(uint32_t, int64_t, std::span<const replay::RobotFrame>, std::span<const replay::Event>,
               std::span<const replay::RobotMap>) override {}
  void OnFinish(bool) override {}
};

TEST(StartLive, WithoutLiveStartsNothingAndSaysNothing) {
  OtherSink other;
  std::vector<replay::RoundSink*> sinks{&other};
  std::ostringstream out;
  const LiveResult live = StartLive(LiveCommandOptions{}, "gather", out, sinks);
  EXPECT_TRUE(live.ok());
  EXPECT_EQ(live.server, nullptr);
  EXPECT_EQ(out.str(), "");
  EXPECT_EQ(sinks, std::vector<replay::RoundSink*>{&other});
}

TEST(StartLive, AnAddressItCannotHaveIsTheUsageErrorTheCommandsPrinted) {
  // 192.0.2.1 is TEST-NET-1 (RFC 5737): no host has it.
  OtherSink other;
  std::vector<replay::RoundSink*> sinks{&other};
  std::ostringstream out;
  const LiveResult live = StartLive(LiveCommandOptions{.address = "192.0.2.1:8765"}, "gather", out, sinks);
  ASSERT_FALSE(live.ok());
  EXPECT_EQ(live.server, nullptr);
  // What `syrof run` (and the three others, after their own names) printed
  // before StartLive returned the error.
  EXPECT_EQ("syrof run: " + live.error->ToString(),
            "syrof run: --live: the live page cannot listen on 192.0.2.1:8765: cannot listen there (the port is "
            "taken, or not an address of this host)");
  EXPECT_EQ(out.str(), "") << "no URL for a page that does not listen";
  EXPECT_EQ(sinks, std::vector<replay::RoundSink*>{&other}) << "no sink for a page that does not listen";
}

TEST(StartLive, AnAddressThatDoesNotParseIsNamedAsGiven) {
  std::vector<replay::RoundSink*> sinks;
  std::ostringstream out;
  const LiveResult live = StartLive(LiveCommandOptions{.address = "nowhere"}, "gather", out, sinks);
  ASSERT_FALSE(live.ok());
  EXPECT_EQ(live.error->ToString(), "--live=nowhere: expected ADDR:PORT (like 127.0.0.1:8765) or a port");
  EXPECT_EQ(live.error->where, "--live=nowhere");
  EXPECT_EQ(out.str(), "");
  EXPECT_TRUE(sinks.empty());
}

TEST(StartLive, ListensSaysItsUrlAndFeedsOnTheRunsRoundsUnderItsTitle) {
  OtherSink other;
  std::vector<replay::RoundSink*> sinks{&other};
  std::ostringstream out;
  const LiveResult live = StartLive(LiveCommandOptions{.address = "127.0.0.1:0"}, "gather (DDS swarm)", out, sinks);
  ASSERT_TRUE(live.ok()) << live.error->ToString();
  ASSERT_NE(live.server, nullptr);
  const int port = live.server->listening().port;
  EXPECT_GT(port, 0);
  EXPECT_EQ(out.str(), "  live page: http://127.0.0.1:" + std::to_string(port) + "/\n");
  EXPECT_EQ(sinks, (std::vector<replay::RoundSink*>{&other, live.server.get()}));
  testing::SseClient page;
  ASSERT_TRUE(page.Get(port, "/"));
  page.ReadUntil([&](const auto&) { return page.body().find("</html>") != std::string::npos; },
                 std::chrono::milliseconds(5000));
  EXPECT_EQ(page.status(), 200);
  EXPECT_NE(page.body().find("<title>SyROF live: gather (DDS swarm)</title>"), std::string::npos);
}

}  // namespace
}  // namespace syrof::lab::live
