// syrof-firmware-swarm's command line (swarm_options.h): --live and
// --live-linger take the forms and defaults of `syrof swarm --live`
// (lab/live/live_command.h), and what is no address is refused by name
// with exit 2 before anything starts.
#include "syrof/firmware/swarm/swarm_options.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "syrof/lab/live/live_command.h"

namespace syrof::firmware::swarm {
namespace {

// ParseOptions wants an image it can read; what is in it does not matter here.
std::string AnImage() {
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / "swarm_options_test.elf";
  std::ofstream(path) << "not read by the parser\n";
  return path.string();
}

Options Parse(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), {"syrof-firmware-swarm", "--image", AnImage()});
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  return ParseOptions(static_cast<int>(argv.size()), argv.data());
}

TEST(SwarmOptionsTest, WithoutLiveThereIsNoPage) { EXPECT_FALSE(Parse({"--robots", "3"}).live.on()); }

TEST(SwarmOptionsTest, LiveAloneListensOnThisHostOnly) {
  const Options alone = Parse({"--live"});
  EXPECT_EQ(alone.live.address, lab::live::kDefaultLiveAddress);
  EXPECT_EQ(alone.live.address.rfind("127.0.0.1:", 0), 0u);
  EXPECT_LT(alone.live.linger_s, 0) << "after the run: until Ctrl-C";
  // An option after --live is no address.
  const Options before_option = Parse({"--live", "--seconds", "5"});
  EXPECT_EQ(before_option.live.address, lab::live::kDefaultLiveAddress);
  EXPECT_EQ(before_option.seconds, 5);
}

TEST(SwarmOptionsTest, LiveTakesAnAddressOrAPortAfterASpaceOrAnEqualsSign) {
  EXPECT_EQ(Parse({"--live", "0.0.0.0:9000"}).live.address, "0.0.0.0:9000");
  EXPECT_EQ(Parse({"--live=0.0.0.0:9000"}).live.address, "0.0.0.0:9000");
  EXPECT_EQ(Parse({"--live", "[::1]:0", "--robots", "2"}).live.address, "[::1]:0");
  EXPECT_EQ(Parse({"--live", "8766"}).live.address, "8766");
  const Options linger = Parse({"--live", "--live-linger", "0"});
  EXPECT_TRUE(linger.live.on());
  EXPECT_EQ(linger.live.linger_s, 0);
}

TEST(SwarmOptionsTest, WhatIsNoAddressIsRefusedByName) {
  EXPECT_EXIT(Parse({"--live", "nowhere"}), ::testing::ExitedWithCode(2),
              "--live=nowhere: expected ADDR:PORT \\(like 127.0.0.1:8765\\) or a port");
  EXPECT_EXIT(Parse({"--live=nowhere"}), ::testing::ExitedWithCode(2), "--live=nowhere: expected ADDR:PORT");
  EXPECT_EXIT(Parse({"--live=127.0.0.1:70000"}), ::testing::ExitedWithCode(2), "--live=127.0.0.1:70000: expected");
  EXPECT_EXIT(Parse({"--live="}), ::testing::ExitedWithCode(2), "--live=: expected ADDR:PORT");
}

TEST(SwarmOptionsTest, LiveLingerWithoutLiveIsRefused) {
  EXPECT_EXIT(Parse({"--live-linger", "5"}), ::testing::ExitedWithCode(2), "--live-linger needs --live");
}

TEST(SwarmOptionsTest, TheUsageSaysWhereLiveListens) {
  EXPECT_NE(std::string(kUsage).find(std::string("--live alone on ") + lab::live::kDefaultLiveAddress),
            std::string::npos)
      << kUsage;
}

}  // namespace
}  // namespace syrof::firmware::swarm
