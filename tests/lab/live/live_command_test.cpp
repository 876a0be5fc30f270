// JoinLiveAddress: `--live ADDR:PORT` (a space) joined into the only form
// CLI11 reads, `--live=ADDR:PORT`, and nothing else touched.
#include "syrof/lab/live/live_command.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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

}  // namespace
}  // namespace syrof::lab::live
