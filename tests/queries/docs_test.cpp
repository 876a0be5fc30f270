// docs/queries.md has a row per error: the value, the C API's status name
// and the C++ name. This test keeps the table complete. Host only: it reads
// the source tree.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include "syrof/queries/query_error.h"

namespace syrof::queries {
namespace {

std::string ReadDoc() {
  std::ifstream file(SYROF_SOURCE_DIR "/docs/queries.md");
  EXPECT_TRUE(file.is_open()) << "cannot open " SYROF_SOURCE_DIR "/docs/queries.md";
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// "DuplicateId" -> "DUPLICATE_ID"
std::string ScreamingSnake(const std::string& name) {
  std::string result;
  for (size_t index = 0; index < name.size(); ++index) {
    const char letter = name[index];
    if (index > 0 && letter >= 'A' && letter <= 'Z') result += '_';
    result += static_cast<char>(letter >= 'a' && letter <= 'z' ? letter - 'a' + 'A' : letter);
  }
  return result;
}

TEST(QueriesDocsTest, ErrorTableHasEveryError) {
  const std::string doc = ReadDoc();
  for (uint8_t value = 0; value <= static_cast<uint8_t>(QueryError::kWorkspaceTooSmall); ++value) {
    const std::string name = ToString(static_cast<QueryError>(value));
    const std::string row =
        "| " + std::to_string(value) + " | `SYROF_QUERIES_" + ScreamingSnake(name) + "` | `k" + name + "` |";
    EXPECT_NE(doc.find(row), std::string::npos) << "docs/queries.md lacks the error row starting " << row;
  }
}

}  // namespace
}  // namespace syrof::queries
