// docs/radio-link.md shows the frame table rendered from the codec's own
// description; this test keeps the two from drifting apart. Host only: it
// reads the source tree.
#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <sstream>
#include <string>

#include "syrof/firmware/drivers/radio_link.h"

namespace syrof::firmware::drivers {
namespace {

std::string ReadDoc() {
  std::ifstream file(SYROF_SOURCE_DIR "/docs/radio-link.md");
  EXPECT_TRUE(file.is_open()) << "cannot open " SYROF_SOURCE_DIR "/docs/radio-link.md";
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

TEST(RadioLinkDocsTest, ShowsTheFrameTable) {
  std::array<char, 4096> table{};
  const auto length = RenderFrameTable(table);
  ASSERT_TRUE(length.ok()) << ToString(length.error());
  const std::string expected(table.data(), length.value());
  EXPECT_NE(ReadDoc().find(expected), std::string::npos)
      << "docs/radio-link.md must contain the frame table exactly as rendered:\n"
      << expected;
}

TEST(RadioLinkDocsTest, StatesTheCrcCheckValueAndTheLimits) {
  const std::string doc = ReadDoc();
  EXPECT_NE(doc.find("0xD64E"), std::string::npos);
  EXPECT_NE(doc.find("at most " + std::to_string(kMaxWireBytes) + " bytes"), std::string::npos);
  EXPECT_NE(doc.find(std::to_string(kMaxLinkBeaconBytes) + " bytes"), std::string::npos);
}

TEST(RadioLinkDocsTest, RenderRefusesAShortBuffer) {
  std::array<char, 16> table{};
  EXPECT_EQ(RenderFrameTable(table).error(), LinkError::kBufferTooSmall);
}

}  // namespace
}  // namespace syrof::firmware::drivers
