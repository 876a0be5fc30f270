// Every assignment's submission folders (starter/, reference/, and each
// broken/<variant>/: its reference with mistake.patch applied, made by the
// build), built as a student's library, graded on every public and hidden
// run: each gets exactly the points its expected.yaml says, and
// loses points only in the criteria it names. The reference's file says
// full marks, so "the reference scores 100% on every seed" is one of these.
//
// expected.yaml (one per submission folder; syrof/assignment/expected.h):
//   points: 62.5          # the submission's total, to the hundredth
//   loses: [agreement]    # criteria below full marks on some run ([] for none)
// compared with CompareWithExpected, as `syrof assignment check` compares.
//
// One test per folder, found by scanning SYROF_ASSIGNMENTS_DIR; the
// libraries come from tests/grader/assignment/CMakeLists.txt under
// SYROF_SUBMISSION_LIBRARIES/<assignment>/<folder>/lib<assignment>.so.
#include <unistd.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "grade_support.h"
#include "syrof/assignment/expected.h"

namespace syrof::grader::assignment {
namespace {

namespace fs = std::filesystem;

struct Submission {
  std::string assignment;  // the assignment folder's name
  std::string folder;      // "starter", "reference", "broken/rand"
};

void PrintTo(const Submission& submission, std::ostream* out) {
  *out << submission.assignment << "/" << submission.folder;
}

std::vector<Submission> FindSubmissions() {
  std::vector<Submission> found;
  for (const fs::directory_entry& entry : fs::directory_iterator(SYROF_ASSIGNMENTS_DIR)) {
    if (!fs::exists(entry.path() / "assignment.yaml")) continue;
    const std::string name = entry.path().filename().string();
    std::vector<std::string> folders = {"starter", "reference"};
    if (fs::is_directory(entry.path() / "broken")) {
      for (const fs::directory_entry& variant : fs::directory_iterator(entry.path() / "broken")) {
        if (variant.is_directory()) folders.push_back("broken/" + variant.path().filename().string());
      }
    }
    for (const std::string& folder : folders) {
      if (fs::exists(entry.path() / folder / "expected.yaml")) found.push_back({name, folder});
    }
  }
  std::sort(found.begin(), found.end(), [](const Submission& a, const Submission& b) {
    return std::tie(a.assignment, a.folder) < std::tie(b.assignment, b.folder);
  });
  return found;
}

std::string TestName(const ::testing::TestParamInfo<Submission>& info) {
  std::string name = info.param.assignment + "_" + info.param.folder;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

class SubmissionTest : public ::testing::TestWithParam<Submission> {};

TEST_P(SubmissionTest, GetsThePointsItsExpectedFileSays) {
  const Submission& submission = GetParam();
  const fs::path folder = fs::path(SYROF_ASSIGNMENTS_DIR) / submission.assignment / submission.folder;
  const Assignment assignment = testing::LoadNamedAssignment(SYROF_ASSIGNMENTS_DIR, submission.assignment);
  const ExpectedLoad expected = LoadExpectedFile((folder / "expected.yaml").string(), assignment);
  ASSERT_TRUE(expected.ok()) << expected.error->ToString();

  const std::string library = std::string(SYROF_SUBMISSION_LIBRARIES) + "/" + submission.assignment + "/" +
                              submission.folder + "/lib" + submission.assignment + ".so";
  ASSERT_TRUE(fs::exists(library)) << library << " was not built";
  const SubmissionResult result = testing::GradeLibrary(
      assignment, library, ::testing::TempDir() + "submission_" + TestName({GetParam(), 0}) + "_" + std::to_string(getpid()));

  // `syrof assignment check`'s comparison (syrof/assignment/expected.h).
  EXPECT_EQ(CompareWithExpected(result, *expected.expected), std::vector<std::string>{}) << testing::Describe(result);
  if (submission.folder == "reference") {
    EXPECT_EQ(result.points, assignment.points) << "a reference scores full marks";
    EXPECT_EQ(result.tests_passed, static_cast<int>(result.tests.size())) << testing::Describe(result);
  }
}

INSTANTIATE_TEST_SUITE_P(Assignments, SubmissionTest, ::testing::ValuesIn(FindSubmissions()), TestName);

}  // namespace
}  // namespace syrof::grader::assignment
