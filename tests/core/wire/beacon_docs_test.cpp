// docs/beacon.md shows the layout rendered from the one definition; this test
// keeps the two from drifting apart. Host only: it reads the source tree.
#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <sstream>
#include <string>

#include "syrof/wire/beacon_layout.h"

namespace syrof::wire {
namespace {

std::string read_doc() {
  std::ifstream file(SYROF_SOURCE_DIR "/docs/beacon.md");
  EXPECT_TRUE(file.is_open()) << "cannot open " SYROF_SOURCE_DIR "/docs/beacon.md";
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

TEST(BeaconDocsTest, ShowsTheLayoutTableFor32Robots) {
  std::array<char, 4096> table{};
  const auto length = RenderLayoutTable(32, table);
  ASSERT_TRUE(length.ok()) << ToString(length.error());
  const std::string expected(table.data(), length.value());

  const std::string doc = read_doc();

  EXPECT_NE(doc.find(expected), std::string::npos)
      << "docs/beacon.md must contain the layout table exactly as rendered:\n"
      << expected;
}

TEST(BeaconDocsTest, SizeTableMatchesEncodedSize) {
  const std::string doc = read_doc();

  for (const uint16_t swarm_size : {8, 16, 32, 48, 64, 128, 256, 257, 1024}) {
    if (swarm_size > kMaxSwarmSize) continue;
    const std::string row =
        "| " + std::to_string(swarm_size) + " | " + std::to_string(EncodedSize(swarm_size)) + " |";
    EXPECT_NE(doc.find(row), std::string::npos) << "docs/beacon.md lacks the size row " << row;
  }
}

}  // namespace
}  // namespace syrof::wire
