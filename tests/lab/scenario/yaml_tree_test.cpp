#include "yaml_tree.h"

#include <gtest/gtest.h>

#include <string>

#include "syrof/base/split_mix64.h"
#include "text_checks.h"

namespace syrof::lab::scenario {
namespace {

bool Read(const std::string& text, YamlNode& root, Diagnostics& diagnostics) {
  return ReadYamlDocument(text, root, diagnostics);
}

TEST(ReadYamlDocument, BuildsMapsListsAndScalarsWithPlaces) {
  const std::string text =
      "name: demo\n"
      "robots:\n"
      "  count: 4\n"
      "  poses: [ {x_m: 1}, 'two' ]\n";
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  ASSERT_TRUE(Read(text, root, diagnostics));

  ASSERT_TRUE(root.is_map());
  ASSERT_EQ(root.keys.size(), 2u);
  const YamlNode* robots = root.Find("robots");
  ASSERT_NE(robots, nullptr);
  EXPECT_EQ(robots->line, 3);
  EXPECT_EQ(robots->column, 3);
  const YamlNode* count = robots->Find("count");
  ASSERT_NE(count, nullptr);
  EXPECT_EQ(count->scalar, "4");
  EXPECT_FALSE(count->quoted);
  EXPECT_EQ(count->line, 3);
  EXPECT_EQ(count->column, 10);
  const YamlNode* poses = robots->Find("poses");
  ASSERT_NE(poses, nullptr);
  ASSERT_TRUE(poses->is_sequence());
  ASSERT_EQ(poses->values.size(), 2u);
  EXPECT_TRUE(poses->values[0].is_map());
  EXPECT_TRUE(poses->values[1].quoted);
  EXPECT_EQ(poses->values[1].scalar, "two");
  EXPECT_EQ(poses->values[1].column, 22);
}

TEST(ReadYamlDocument, RefusesAnchorsAtTheirPlace) {
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  EXPECT_FALSE(Read("a: 1\nb: &x 2\n", root, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_EQ(diagnostics.error()->line, 2);
  EXPECT_EQ(diagnostics.error()->column, 4);
  EXPECT_NE(diagnostics.error()->message.find("anchors"), std::string::npos);
}

TEST(ReadYamlDocument, RefusesAliasesAtTheirPlace) {
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  // With its anchor the anchor is refused first; alone, an alias refers to
  // nothing and the parser stops on it.
  EXPECT_FALSE(Read("a: 1\nb: *x\n", root, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_EQ(diagnostics.error()->line, 2);
  EXPECT_EQ(diagnostics.error()->column, 4);
  EXPECT_NE(diagnostics.error()->message.find("aliases"), std::string::npos);
}

TEST(ReadYamlDocument, RefusesDuplicateKeys) {
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  EXPECT_FALSE(Read("robots:\n  count: 1\n  count: 2\n", root, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_EQ(diagnostics.error()->line, 3);
  EXPECT_EQ(diagnostics.error()->column, 3);
  EXPECT_NE(diagnostics.error()->message.find("duplicate key 'count' (in 'robots')"), std::string::npos);
}

TEST(ReadYamlDocument, RefusesExplicitTags) {
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  EXPECT_FALSE(Read("seed: !!str 5\n", root, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_NE(diagnostics.error()->message.find("tags"), std::string::npos);
}

TEST(ReadYamlDocument, RefusesMapsAsKeys) {
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  EXPECT_FALSE(Read("? [a, b]\n: 1\n", root, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_NE(diagnostics.error()->message.find("map key"), std::string::npos);
}

TEST(ReadYamlDocument, StopsDeepBlockNestingAtTheDepthCap) {
  // Block lists nest without brackets, so the text check cannot see them;
  // the tree builder stops the parser at the first level too deep.
  std::string text;
  for (int level = 0; level < 5000; ++level) text += "- ";
  text += "x\n";
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  EXPECT_FALSE(Read(text, root, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_EQ(diagnostics.error()->line, 1);
  EXPECT_EQ(diagnostics.error()->column, 2 * kMaxScenarioDepth + 1);
  EXPECT_NE(diagnostics.error()->message.find("nest more than 16"), std::string::npos);
}

TEST(ReadYamlDocument, StopsAtTheNodeCap) {
  // A list file far larger than a scenario (a scripted channel's lost_file)
  // bounds its tree by nodes: each costs a hundred bytes or more in memory.
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  EXPECT_FALSE(ReadYamlDocument("[[0, 0, 1], [0, 1, 0], [1, 0, 1]]\n", root, diagnostics, 9));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_EQ(diagnostics.error()->line, 1);
  EXPECT_EQ(diagnostics.error()->column, 24);  // the third entry, the 10th node (the root list is the 1st)
  EXPECT_NE(diagnostics.error()->message.find("more than 9 maps, lists and values"), std::string::npos)
      << diagnostics.error()->ToString();
  Diagnostics fits("t.yaml");
  EXPECT_TRUE(ReadYamlDocument("[[0, 0, 1], [0, 1, 0]]\n", root, fits, 9));
}

TEST(ReadYamlDocument, ReportsSyntaxErrorsWithTheirPlace) {
  YamlNode root;
  Diagnostics diagnostics("t.yaml");

  EXPECT_FALSE(Read("robots: [1, 2\napp: x\n", root, diagnostics));

  ASSERT_TRUE(diagnostics.failed());
  EXPECT_GT(diagnostics.error()->line, 0);
  EXPECT_GT(diagnostics.error()->column, 0);
  EXPECT_NE(diagnostics.error()->message.find("YAML syntax error"), std::string::npos);
}

TEST(ReadYamlDocument, SurvivesSeededRandomText) {
  // Printable noise built from YAML's indicator characters: every input
  // must end in a tree or an error, never a crash or a hang.
  static constexpr char kAlphabet[] = "[]{}:,-?#&*!|>'\"%@` \n\tab1.";
  base::SplitMix64 generator(42);
  int failures = 0;
  for (int sample = 0; sample < 300; ++sample) {
    std::string text(1 + generator.Below(60), ' ');
    for (char& c : text) c = kAlphabet[generator.Below(sizeof kAlphabet - 1)];
    YamlNode root;
    Diagnostics diagnostics("t.yaml");

    const bool read = CheckScenarioText(text, diagnostics) && Read(text, root, diagnostics);

    EXPECT_EQ(read, !diagnostics.failed());
    failures += read ? 0 : 1;
  }
  EXPECT_GT(failures, 0);
}

}  // namespace
}  // namespace syrof::lab::scenario
