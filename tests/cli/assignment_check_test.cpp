// `syrof assignment check` grading for real, through the built `syrof`
// (which finds the app host and SyROF's package beside it): a real
// assignment's reference passes; a variant whose expected.yaml is wrong
// fails the check with exit 1, named in the table with what differs; and
// the skeleton `syrof assignment new` writes checks clean as written;
// --probe-students grades the reference on seeds derived for probe
// students, hidden runs only, and names each seed it failed with its rerun.
// coverage is the quickest assignment to check (docs/grading.md, "Writing an
// assignment"); --only keeps each test to one or two subjects.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status;
  std::string output;
};

// `syrof ARGUMENTS` (already quoted for the shell), its output and errors together.
Outcome Syrof(const std::string& arguments) {
  FILE* pipe = popen((std::string(SYROF_EXECUTABLE) + " " + arguments + " 2>&1").c_str(), "r");
  Outcome run{-1, ""};
  char buffer[4096];
  size_t got = 0;
  while (pipe != nullptr && (got = fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, got);
  const int status = pipe == nullptr ? -1 : pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

class AssignmentCheckTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("syrof_assignment_check_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(AssignmentCheckTest, ARealAssignmentsReferenceGetsFullMarks) {
  const Outcome run = Syrof("assignment check " SYROF_ASSIGNMENTS_DIR "/coverage --only reference --jobs 2 --out " +
                        (dir_ / "out").string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("  reference  100.00, loses none  100.00, loses none  PASS"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("All 1 as expected"), std::string::npos) << run.output;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "reference" / "grade.json")) << "the reports, as syrof grade's";
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "reference" / "report.html"));
}

// --gradescope-budget: the reference graded alone, its CPU time projected
// to Gradescope's half a CPU, a warning when that is over half the budget
// (the check's own verdict unchanged).
TEST_F(AssignmentCheckTest, AGradescopeBudgetTooSmallForTheReferenceIsWarnedAbout) {
  const Outcome roomy = Syrof("assignment check " SYROF_ASSIGNMENTS_DIR
                              "/gather --only reference --jobs 2 --gradescope-budget 600 --out " +
                              (dir_ / "roomy").string());
  const Outcome tight = Syrof("assignment check " SYROF_ASSIGNMENTS_DIR
                              "/gather --only reference --jobs 2 --gradescope-budget 1 --out " +
                              (dir_ / "tight").string());

  EXPECT_EQ(roomy.status, 0) << roomy.output;
  EXPECT_NE(roomy.output.find("under Gradescope's half a CPU, within half of the 600 s budget"), std::string::npos)
      << roomy.output;
  EXPECT_EQ(tight.status, 0) << tight.output;
  EXPECT_NE(tight.output.find("under Gradescope's half a CPU, MORE than half of the 1 s budget: a slow submission "
                              "may reach Gradescope's timeout"),
            std::string::npos)
      << tight.output;
}

TEST_F(AssignmentCheckTest, AVariantThatDoesNotGetItsExpectedPointsFailsTheCheckByName) {
  fs::copy(SYROF_ASSIGNMENTS_DIR "/coverage", dir_ / "coverage", fs::copy_options::recursive);
  // own_id gets 87.50 losing goal; say it must lose more.
  std::ofstream(dir_ / "coverage" / "broken" / "own_id" / "expected.yaml") << "points: 80\nloses: [goal, collisions]\n";

  const Outcome run = Syrof("assignment check " + (dir_ / "coverage").string() + " --only reference --only own_id --jobs 2 --out " +
                        (dir_ / "out").string());

  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find("  broken/own_id  80.00, loses goal, collisions  87.50, loses goal"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("FAIL"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("points 87.50, expected 80.00"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("loses goal, expected goal, collisions"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("1 of 2 as expected; not as expected: broken/own_id."), std::string::npos) << run.output;
}

TEST_F(AssignmentCheckTest, ProbeStudentsGradeTheReferenceOnDerivedHiddenSeedsOnly) {
  const Outcome run = Syrof("assignment check " SYROF_ASSIGNMENTS_DIR
                            "/coverage --only reference --probe-students 1 --jobs 2 --out " +
                            (dir_ / "out").string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("and the reference on 1 probe student's hidden seeds (4 runs each)"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("  probe/1    100.00, loses none  100.00, loses none  PASS"), std::string::npos)
      << run.output;
  std::ifstream file(dir_ / "out" / "probe" / "1" / "grade.json");
  const std::string grade((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  EXPECT_NE(grade.find("\"seed_student\": \"probe-1\""), std::string::npos) << grade;
  EXPECT_EQ(grade.find("coverage_6/"), std::string::npos) << "no public run: " << grade;
  EXPECT_NE(grade.find("coverage_7_dead/seed-"), std::string::npos) << grade;
  for (const char* listed : {"seed-101\"", "seed-102\"", "seed-103\"", "seed-104\""}) {
    EXPECT_EQ(grade.find(listed), std::string::npos) << listed << " is a listed seed, not a derived one";
  }
}

TEST_F(AssignmentCheckTest, AProbeThatLosesPointsNamesEachSeedWithItsRerun) {
  fs::copy(SYROF_ASSIGNMENTS_DIR "/coverage", dir_ / "coverage", fs::copy_options::recursive);
  // A goal no run reaches: every hidden seed, listed or derived, loses it.
  const fs::path hidden = dir_ / "coverage" / "hidden" / "coverage_6_bursty.yaml";
  std::ifstream in(hidden);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const size_t at = text.find("deadline_s: 65");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 14, "deadline_s: 1");
  std::ofstream(hidden) << text;

  const Outcome run = Syrof("assignment check " + (dir_ / "coverage").string() +
                            " --only reference --probe-students 1 --jobs 2 --out " + (dir_ / "out").string());

  EXPECT_EQ(run.status, 1) << run.output;
  EXPECT_NE(run.output.find("not as expected: reference, probe/1."), std::string::npos) << run.output;
  const size_t probe = run.output.find("  probe/1 ");
  ASSERT_NE(probe, std::string::npos) << run.output;
  const std::string below = run.output.substr(probe);
  EXPECT_NE(below.find("coverage_6_bursty/seed-"), std::string::npos) << below;
  EXPECT_NE(below.find("rerun: syrof run "), std::string::npos) << below;
  EXPECT_NE(below.find("coverage_6_bursty.yaml --app "), std::string::npos) << below;
}

TEST_F(AssignmentCheckTest, ProbeStudentsNeedTheReference) {
  const Outcome run = Syrof("assignment check " SYROF_ASSIGNMENTS_DIR "/coverage --only starter --probe-students 2");
  EXPECT_EQ(run.status, 2) << run.output;
  EXPECT_NE(run.output.find("--probe-students grades the reference: add it to --only"), std::string::npos)
      << run.output;
}

TEST_F(AssignmentCheckTest, TheSkeletonOfAssignmentNewChecksCleanAsWritten) {
  const Outcome made = Syrof("assignment new spread --dir " + dir_.string());
  ASSERT_EQ(made.status, 0) << made.output;

  const Outcome run = Syrof("assignment check " + (dir_ / "spread").string() + " --jobs 2 --out " + (dir_ / "out").string());

  EXPECT_EQ(run.status, 0) << run.output;
  for (const char* row : {"  reference          100.00, loses none  100.00, loses none  PASS",
                          "  starter            50.00, loses goal   50.00, loses goal   PASS",
                          "  broken/off_by_one  50.00, loses goal   50.00, loses goal   PASS"}) {
    EXPECT_NE(run.output.find(row), std::string::npos) << row << " missing from\n" << run.output;
  }
  EXPECT_NE(run.output.find("All 3 as expected"), std::string::npos) << run.output;
}

}  // namespace
