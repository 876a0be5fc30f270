// JUnit XML: well-formed (read back with the tests' own strict reader), the
// counts and names CI systems show, the first lost criterion as the failure
// message, every criterion in system-out, < & " ' > escaped wherever they
// come from, and a build failure as one failing testcase.
#include <gtest/gtest.h>

#include "report_test_support.h"
#include "syrof/report/reports.h"

namespace syrof::grader::report {
namespace {

using testing::ExampleResult;
using testing::XmlElement;
using testing::XmlReader;

XmlElement Parse(const std::string& xml) {
  XmlReader reader(xml);
  std::optional<XmlElement> root = reader.Document();
  EXPECT_TRUE(root.has_value()) << reader.error() << "\n" << xml;
  return root.value_or(XmlElement{});
}

std::vector<const XmlElement*> Testcases(const XmlElement& root) {
  std::vector<const XmlElement*> cases;
  const XmlElement* suite = root.Child("testsuite");
  if (suite == nullptr) return cases;
  for (const XmlElement& child : suite->children) {
    if (child.name == "testcase") cases.push_back(&child);
  }
  return cases;
}

// The reader itself: what it must refuse, so a pass below means something.
TEST(JunitXmlTest, TheTestsXmlReaderRefusesWhatIsNotWellFormed) {
  for (const std::string bad : {"<a>", "<a></b>", "<a>x < y</a>", "<a>R&D</a>", "<a b=\"<\"/>", "<a b='1' b='2'/>",
                                "<a>&nbsp;</a>", "<a>&#0;</a>", "<a>\x01</a>", "<a>\xff</a>", "<a/><b/>",
                                "<a b=1/>"}) {
    XmlReader reader(bad);
    EXPECT_FALSE(reader.Document().has_value()) << bad;
  }
  XmlReader good("<?xml version=\"1.0\"?>\n<a b=\"&lt;&amp;&quot;&apos;&#10;\">x &gt; y<c/></a>\n");
  const std::optional<XmlElement> root = good.Document();
  ASSERT_TRUE(root.has_value()) << good.error();
  EXPECT_EQ(root->attributes.at("b"), "<&\"'\n");
  EXPECT_EQ(root->text, "x > y");
}

TEST(JunitXmlTest, OneTestcasePerRunWithTheCountsCiSystemsShow) {
  const XmlElement root = Parse(JunitXml(ExampleResult()));

  EXPECT_EQ(root.name, "testsuites");
  EXPECT_EQ(root.attributes.at("tests"), "4");
  EXPECT_EQ(root.attributes.at("failures"), "2");
  const XmlElement* suite = root.Child("testsuite");
  ASSERT_NE(suite, nullptr);
  EXPECT_EQ(suite->attributes.at("name"), "gather");
  EXPECT_EQ(suite->attributes.at("tests"), "4");
  EXPECT_EQ(suite->attributes.at("failures"), "2");
  const std::vector<const XmlElement*> cases = Testcases(root);
  ASSERT_EQ(cases.size(), 4u);
  EXPECT_EQ(cases[0]->attributes.at("classname"), "gather");
  EXPECT_EQ(cases[0]->attributes.at("name"), "gather_6/seed-1");
  EXPECT_EQ(cases[0]->Child("failure"), nullptr);
  EXPECT_EQ(cases[3]->attributes.at("name"), "crash10/seed-102");
}

TEST(JunitXmlTest, AFailureIsItsFirstLostCriterionAndSystemOutHoldsThemAll) {
  const std::vector<const XmlElement*> cases = [] {
    static const XmlElement root = Parse(JunitXml(ExampleResult()));
    return Testcases(root);
  }();
  ASSERT_EQ(cases.size(), 4u);

  const XmlElement* failure = cases[1]->Child("failure");
  ASSERT_NE(failure, nullptr);
  EXPECT_EQ(failure->attributes.at("message"),
            "goal 25/50: 1 of 2 checks passed; gathered: robot 3 is 0.900 m from (1.000, 1.000); the limit is 0.500 m");
  const XmlElement* out = cases[1]->Child("system-out");
  ASSERT_NE(out, nullptr);
  for (const std::string line : {"goal 25/50: ", "collisions 20/20: ", "agreement 30/30: ", "run total 75/100",
                                 "replay: syrof run gather/scenarios/gather_6.yaml"}) {
    EXPECT_NE(out->text.find(line), std::string::npos) << line << " in " << out->text;
  }

  const XmlElement* timeout = cases[2]->Child("failure");
  ASSERT_NE(timeout, nullptr);
  EXPECT_EQ(timeout->attributes.at("message"), "the run has no score: time limit of 120 s reached");
  EXPECT_EQ(timeout->attributes.at("type"), "run_error");
}

TEST(JunitXmlTest, ReasonsAreEscapedWhereverTheyGo) {
  assignment::SubmissionResult result = ExampleResult();
  const std::string nasty = "a<b && c>\"d\" 'e' </failure>]]>\tf\nsecond line";
  result.tests[1].score.criteria[0].reason = nasty;
  result.tests[1].name = "gather_6/seed-2 <\"&'>";
  result.submission = "o'brien & <co>";

  const XmlElement root = Parse(JunitXml(result));

  const std::vector<const XmlElement*> cases = Testcases(root);
  ASSERT_EQ(cases.size(), 4u);
  EXPECT_EQ(cases[1]->attributes.at("name"), "gather_6/seed-2 <\"&'>");
  ASSERT_NE(cases[1]->Child("failure"), nullptr);
  // The newline and tab in an attribute survive as character references.
  EXPECT_EQ(cases[1]->Child("failure")->attributes.at("message"), "goal 25/50: " + nasty);
  EXPECT_NE(cases[1]->Child("system-out")->text.find("goal 25/50: " + nasty), std::string::npos);
  const XmlElement* properties = root.Child("testsuite")->Child("properties");
  ASSERT_NE(properties, nullptr);
  EXPECT_EQ(properties->children.at(0).attributes.at("value"), "o'brien & <co>");
}

TEST(JunitXmlTest, ControlCharactersAndBadBytesStillGiveWellFormedXml) {
  assignment::SubmissionResult result = ExampleResult();
  result.tests[1].score.criteria[0].reason = std::string("nul\0 bell\x07 esc\x1b bad\xc3\x28", 21);

  const XmlElement root = Parse(JunitXml(result));

  const std::string message = Testcases(root).at(1)->Child("failure")->attributes.at("message");
  EXPECT_EQ(message.find('\x07'), std::string::npos);
  EXPECT_NE(message.find("bell\xEF\xBF\xBD"), std::string::npos) << message;
}

TEST(JunitXmlTest, ABuildFailureIsOneFailingTestcaseNamedBuild) {
  assignment::SubmissionResult result = ExampleResult();
  result.build.verdict = assignment::BuildVerdict::kBuildFailed;
  result.build.detail = "app.c:3:1: error: expected ';' before '}' token";
  result.points = 0;
  result.tests_passed = 0;
  for (assignment::TestResult& test : result.tests) test.passed = false;

  const XmlElement root = Parse(JunitXml(result));

  EXPECT_EQ(root.attributes.at("tests"), "1");
  EXPECT_EQ(root.attributes.at("failures"), "1");
  const std::vector<const XmlElement*> cases = Testcases(root);
  ASSERT_EQ(cases.size(), 1u);
  EXPECT_EQ(cases[0]->attributes.at("name"), "build");
  ASSERT_NE(cases[0]->Child("failure"), nullptr);
  EXPECT_EQ(cases[0]->Child("failure")->attributes.at("message"),
            "the submission did not build (build_failed): app.c:3:1: error: expected ';' before '}' token");
  EXPECT_NE(cases[0]->Child("system-out")->text.find("build log: build.log"), std::string::npos);
}

TEST(JunitXmlTest, TimingsAppearOnlyInTimeAttributesAndCanBeZeroed) {
  assignment::SubmissionResult slower = ExampleResult();
  slower.build.wall_seconds = 99;
  for (assignment::TestResult& test : slower.tests) test.wall_seconds *= 3;
  ReportOptions zero;
  zero.zero_timings = true;

  EXPECT_NE(JunitXml(ExampleResult()), JunitXml(slower));
  EXPECT_EQ(JunitXml(ExampleResult(), zero), JunitXml(slower, zero));
  const XmlElement root = Parse(JunitXml(slower, zero));
  EXPECT_EQ(root.attributes.at("time"), "0.000");
  EXPECT_EQ(Testcases(root).at(2)->attributes.at("time"), "0.000");
  EXPECT_EQ(Testcases(Parse(JunitXml(ExampleResult()))).at(2)->attributes.at("time"), "120.200");
}

}  // namespace
}  // namespace syrof::grader::report
