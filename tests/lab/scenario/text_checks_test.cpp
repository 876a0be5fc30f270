#include "text_checks.h"

#include <gtest/gtest.h>

#include <string>

#include "scenario_test_util.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::kMinimal;
using testing::Load;

TEST(CheckScenarioText, RefusesTextOverTheSizeCapBeforeParsing) {
  // Valid YAML of the right shape but one byte too long.
  std::string text = kMinimal;
  text += "#" + std::string(kMaxScenarioBytes - text.size(), 'x');
  ASSERT_EQ(text.size(), kMaxScenarioBytes + 1);

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 0, 0, {std::to_string(kMaxScenarioBytes + 1).c_str(),
                                     std::to_string(kMaxScenarioBytes).c_str(), "limit"}));
}

TEST(CheckScenarioText, RefusesDeepFlowNestingBeforeParsing) {
  const std::string text(100000, '[');

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 1, kMaxScenarioDepth + 1, {"nest more than 16"}));
}

TEST(CheckScenarioText, RefusesDeepFlowNestingInsideAValue) {
  const std::string text = "app: builtin:idle\nrobots: " + std::string(40, '{') + "\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 2, 9 + kMaxScenarioDepth, {"nest"}));
}

TEST(FlowDepth, IgnoresBracketsInQuotesCommentsAndBlockScalars) {
  const std::string text =
      "a: \"[[[[[[[[[[[[[[[[[[[[\"\n"
      "b: '{{{{{{{{{{{{{{{{{{{{'\n"
      "# [[[[[[[[[[[[[[[[[[[[[[[[[[\n"
      "c: x [[[[[[[[[[[[[[[[[[[[ # [[[[[\n"
      "d: |\n"
      "  [[[[[[[[[[[[[[[[[[[[[[[\n"
      "  {{{{{{{{{{{{{{{{{{{{{{{\n"
      "e: [[1, [2]], {f: [3]}]\n";
  size_t offset = 0;

  const int depth = FlowDepth(text, kMaxScenarioDepth, offset);

  EXPECT_EQ(depth, 3);
}

TEST(FlowDepth, CountsBracketsAfterAQuoteInsideAFlowPlainScalar) {
  // In flow context "a 'b" is one plain scalar and the '[' after it opens a
  // list: the quote must not hide the brackets.
  const std::string text = "x: [a 'b [[[ ]]] ]\n";
  size_t offset = 0;

  const int depth = FlowDepth(text, kMaxScenarioDepth, offset);

  EXPECT_EQ(depth, 4);
}

TEST(CheckScenarioText, RefusesBinaryGarbage) {
  const std::string text("\x7f" "ELF\x02\x01\x01\x00\x00\xff\xfe", 11);

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 1, 1, {"control character 0x7f"}));
}

TEST(CheckScenarioText, RefusesInvalidUtf8) {
  const std::string text = std::string(kMinimal) + "name: caf\xe9\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 3, 10, {"0xe9", "UTF-8"}));
}

TEST(CheckScenarioText, RefusesNulBytes) {
  const std::string text = std::string("robots:\n  count: 4\x00\n", 20);

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 2, 11, {"control character 0x00"}));
}

TEST(CheckScenarioText, AcceptsUtf8TextInComments) {
  const std::string text = std::string(kMinimal) + "# caf\xc3\xa9 \xe2\x9c\x93\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(result.ok()) << result.error->ToString();
}

TEST(CheckScenarioText, RefusesTabIndentation) {
  const std::string text = "robots:\n\tcount: 4\napp: builtin:idle\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 2, 1, {"tab in indentation"}));
}

TEST(CheckScenarioText, AcceptsTabsAfterValues) {
  const std::string text = "robots: { count: 4 }\t# four\napp: builtin:idle\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(result.ok()) << result.error->ToString();
}

TEST(CheckScenarioText, RefusesASecondDocument) {
  const std::string text = std::string(kMinimal) + "---\nrobots: { count: 2 }\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 3, 1, {"second YAML document"}));
}

TEST(CheckScenarioText, RefusesContentAfterTheDocumentEnd) {
  const std::string text = std::string(kMinimal) + "...\nname: other\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(FailsAt(result, 4, 1, {"after the end of the document"}));
}

TEST(CheckScenarioText, AcceptsOneMarkedDocument) {
  const std::string text = "%YAML 1.2\n# a comment\n--- # start\n" + std::string(kMinimal) + "...\n# done\n";

  const LoadResult result = Load(text);

  EXPECT_TRUE(result.ok()) << result.error->ToString();
}

TEST(CheckScenarioText, RefusesAnEmptyFile) {
  const LoadResult result = Load("");

  EXPECT_TRUE(FailsAt(result, 0, 0, {"empty"}));
}

TEST(CheckScenarioText, RefusesAFileOfCommentsOnly) {
  const LoadResult result = Load("# nothing here\n\n");

  EXPECT_TRUE(FailsAt(result, 0, 0, {"empty"}));
}

}  // namespace
}  // namespace syrof::lab::scenario
