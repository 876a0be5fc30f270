// Each example assignment's reference solution, built as a student's
// library and run through the app host on every public scenario and seed,
// earns full marks: the goal checks pass, nothing collides, the robots
// agree, nothing faults.
#include <unistd.h>

#include <gtest/gtest.h>

#include <string>

#include "grade_support.h"

namespace syrof::grader::assignment {
namespace {

TEST(ReferenceTest, TheGatherReferenceScoresFullMarksOnEveryPublicRun) {
  const Assignment assignment = testing::LoadNamedAssignment(SYROF_ASSIGNMENTS_DIR, "gather");
  const SubmissionResult result =
      testing::GradeLibrary(assignment, SYROF_GATHER_REFERENCE,
                            ::testing::TempDir() + "gather_reference_" + std::to_string(getpid()), true);
  EXPECT_EQ(result.tests.size(), 5u);
  EXPECT_EQ(result.tests_passed, 5) << testing::Describe(result);
  EXPECT_EQ(result.points, assignment.points) << testing::Describe(result);
}

}  // namespace
}  // namespace syrof::grader::assignment
