// expected.yaml: every example assignment's files load; a wrong file gets an
// error with file:line:column and what to write instead; and the comparison
// with a graded submission names each difference (points, criteria lost).
#include "syrof/assignment/expected.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace syrof::grader::assignment {
namespace {

namespace fs = std::filesystem;

Assignment GatherLike() {
  Assignment assignment;
  assignment.points = 100;
  assignment.rubric.goal = GoalCriterion{50};
  assignment.rubric.safety = SafetyCriterion{5, 0.5};
  assignment.rubric.agreement = AgreementCriterion{45};
  return assignment;
}

class ExpectedFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    file_ = fs::temp_directory_path() / ("syrof_expected_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
  }
  void TearDown() override { fs::remove(file_); }
  ExpectedLoad Load(const std::string& text) {
    std::ofstream(file_) << text;
    return LoadExpectedFile(file_.string(), GatherLike());
  }
  std::string ErrorOf(const std::string& text) {
    const ExpectedLoad loaded = Load(text);
    EXPECT_FALSE(loaded.ok()) << text;
    return loaded.ok() ? "" : loaded.error->ToString();
  }
  fs::path file_;
};

TEST(ExpectedTest, EveryExampleAssignmentsExpectedFilesLoad) {
  int files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(SYROF_ASSIGNMENTS_DIR)) {
    if (!fs::exists(entry.path() / "assignment.yaml")) continue;
    const LoadResult assignment = LoadAssignmentFile(entry.path().string());
    ASSERT_TRUE(assignment.ok()) << assignment.error->ToString();
    for (const fs::directory_entry& file : fs::recursive_directory_iterator(entry.path())) {
      if (file.path().filename() != "expected.yaml") continue;
      const ExpectedLoad loaded = LoadExpectedFile(file.path().string(), *assignment.assignment);
      EXPECT_TRUE(loaded.ok()) << loaded.error->ToString();
      ++files;
    }
  }
  EXPECT_GE(files, 3);
}

TEST_F(ExpectedFileTest, ReadsPointsAndTheCriteriaInTheRubricsOrder) {
  const ExpectedLoad loaded = Load("points: 34.94\nloses: [agreement, goal]\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();
  EXPECT_EQ(loaded.expected->points, 34.94);
  EXPECT_EQ(loaded.expected->loses, (std::vector<std::string>{"goal", "agreement"}));
  EXPECT_EQ(loaded.expected->points_line, 1);
}

TEST_F(ExpectedFileTest, AWrongFileSaysWhereAndWhat) {
  const std::string f = file_.string();
  EXPECT_EQ(ErrorOf("points: 50\nloses: [gaol]\n"),
            f + ":2:9: loses[0]: unknown value 'gaol' (did you mean 'goal'?); expected one of goal, safety, agreement");
  EXPECT_EQ(ErrorOf("points: 50\nloses: [collisions]\n").substr(f.size()),
            ":2:9: loses[0]: unknown value 'collisions'; expected one of goal, safety, agreement")
      << "a criterion the rubric does not score";
  EXPECT_EQ(ErrorOf("points: 50\nloses: [goal, goal]\n"), f + ":2:15: loses[1]: 'goal' is listed twice");
  EXPECT_EQ(ErrorOf("points: 120\nloses: []\n"), f + ":1:9: points: must be in [0, 100], got 120");
  EXPECT_EQ(ErrorOf("points: 84.375\nloses: [goal]\n"),
            f + ":1:9: points: a submission's points are rounded to the hundredth; 84.375 has more decimals");
  EXPECT_NE(ErrorOf("point: 50\nloses: []\n").find("unknown key 'point' (did you mean 'points'?)"), std::string::npos);
  EXPECT_NE(ErrorOf("points: 50\n").find("missing required key 'loses'"), std::string::npos);
  EXPECT_NE(ErrorOf("").find("the file is empty"), std::string::npos);
}

SubmissionResult Graded(double points, const std::vector<std::pair<std::string, double>>& criteria) {
  SubmissionResult result;
  result.points = points;
  result.max_points = 100;
  TestResult test;
  for (const auto& [criterion, earned] : criteria) test.score.criteria.push_back({criterion, earned, 50, ""});
  result.tests = {TestResult{}, test};
  return result;
}

TEST(ExpectedTest, TheSameResultHasNoDifference) {
  const Expected expected{84.38, {"goal"}};
  EXPECT_EQ(CompareWithExpected(Graded(84.38, {{"goal", 20}, {"agreement", 50}}), expected),
            std::vector<std::string>{});
}

TEST(ExpectedTest, EachDifferenceIsNamed) {
  const Expected expected{30, {"goal", "safety"}};
  EXPECT_EQ(CompareWithExpected(Graded(34.94, {{"goal", 0}, {"agreement", 10}}), expected),
            (std::vector<std::string>{"points 34.94, expected 30.00",
                                      "loses goal, agreement, expected goal, safety"}));
  EXPECT_EQ(CompareWithExpected(Graded(30, {{"goal", 50}}), Expected{30, {}}),
            std::vector<std::string>{}) << "a criterion at full points is not lost";
  EXPECT_EQ(CompareWithExpected(Graded(30.01, {}), Expected{30, {}}),
            std::vector<std::string>{"points 30.01, expected 30.00"}) << "no tolerance: both are to the hundredth";
}

}  // namespace
}  // namespace syrof::grader::assignment
