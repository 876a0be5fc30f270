// Per-student hidden seeds (grader/src/student_seeds.cpp): the keyed hash,
// the assignment with derived seeds, the course secret's checks and
// Gradescope's submission metadata.
#include "syrof/grader/student_seeds.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::Assignment;
using assignment::ScenarioRun;

constexpr const char* kSecret = "0123456789abcdef-course-secret";

fs::path Fresh(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("seeds_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Assignment TwoSets() {
  Assignment assignment;
  assignment.name = "gather";
  assignment.title = "Gather the swarm";
  ScenarioRun visible;
  visible.name = "gather_6";
  visible.seeds = {1, 2, 3};
  ScenarioRun hidden;
  hidden.name = "gather_10_join";
  hidden.seeds = {101, 102, 103};
  ScenarioRun other;
  other.name = "crash10";
  other.seeds = {7};
  assignment.public_runs = {visible};
  assignment.hidden_runs = {hidden, other};
  return assignment;
}

TEST(DeriveSeedTest, MatchesHmacSha256ComputedIndependently) {
  // Python's hmac module on the same message (a label, then each field
  // length-prefixed, 8 bytes big-endian): a change to the derivation would
  // change every student's hidden seeds, so a regrade would not reproduce.
  EXPECT_EQ(DeriveSeed(kSecret, "Gather the swarm", "gather_10_join", "alice@example.edu", 0),
            14880537815187996066ull);
}

TEST(DeriveSeedTest, TheSameInputsGiveTheSameSeed) {
  EXPECT_EQ(DeriveSeed(kSecret, "A", "s", "alice", 3), DeriveSeed(kSecret, "A", "s", "alice", 3));
}

TEST(DeriveSeedTest, EachInputChangesTheSeed) {
  const uint64_t base = DeriveSeed(kSecret, "A", "s", "alice", 0);
  EXPECT_NE(DeriveSeed("another-course-secret-16", "A", "s", "alice", 0), base) << "secret";
  EXPECT_NE(DeriveSeed(kSecret, "B", "s", "alice", 0), base) << "assignment";
  EXPECT_NE(DeriveSeed(kSecret, "A", "t", "alice", 0), base) << "scenario entry";
  EXPECT_NE(DeriveSeed(kSecret, "A", "s", "bob", 0), base) << "student";
  EXPECT_NE(DeriveSeed(kSecret, "A", "s", "alice", 1), base) << "index";
  // Fields are length-prefixed: moving a byte from one field to the next
  // is another message.
  EXPECT_NE(DeriveSeed(kSecret, "A", "sa", "lice", 0), DeriveSeed(kSecret, "A", "s", "alice", 0));
}

TEST(DeriveSeedTest, AThousandStudentsGetAThousandSeeds) {
  std::set<uint64_t> seeds;
  for (int student = 0; student < 1000; ++student) {
    seeds.insert(DeriveSeed(kSecret, "A", "s", "student-" + std::to_string(student), 0));
  }
  EXPECT_EQ(seeds.size(), 1000u);
}

TEST(WithStudentSeedsTest, ReplacesTheHiddenSeedsOnlyKeepingTheirCount) {
  const Assignment listed = TwoSets();
  const Assignment derived = WithStudentSeeds(listed, {kSecret, "alice@example.edu"});
  EXPECT_EQ(derived.public_runs[0].seeds, listed.public_runs[0].seeds);
  ASSERT_EQ(derived.hidden_runs.size(), 2u);
  ASSERT_EQ(derived.hidden_runs[0].seeds.size(), 3u);
  ASSERT_EQ(derived.hidden_runs[1].seeds.size(), 1u);
  for (uint64_t index = 0; index < 3; ++index) {
    EXPECT_EQ(derived.hidden_runs[0].seeds[index],
              DeriveSeed(kSecret, "Gather the swarm", "gather_10_join", "alice@example.edu", index));
  }
  EXPECT_EQ(derived.hidden_runs[1].seeds[0], DeriveSeed(kSecret, "Gather the swarm", "crash10", "alice@example.edu", 0));
  EXPECT_NE(derived.hidden_runs[0].seeds, listed.hidden_runs[0].seeds);
}

TEST(WithStudentSeedsTest, TwoStudentsShareNoHiddenSeed) {
  const Assignment alice = WithStudentSeeds(TwoSets(), {kSecret, "alice"});
  const Assignment bob = WithStudentSeeds(TwoSets(), {kSecret, "bob"});
  const std::set<uint64_t> alices(alice.hidden_runs[0].seeds.begin(), alice.hidden_runs[0].seeds.end());
  for (const uint64_t seed : bob.hidden_runs[0].seeds) EXPECT_EQ(alices.count(seed), 0u) << seed;
  EXPECT_EQ(HiddenSeedsText(WithStudentSeeds(TwoSets(), {kSecret, "alice"})), HiddenSeedsText(alice));
  EXPECT_NE(HiddenSeedsText(alice), HiddenSeedsText(bob));
  EXPECT_EQ(HiddenSeedsText(TwoSets()), "gather_10_join: 101 102 103; crash10: 7; ");
}

TEST(CourseSecretTest, EmptyAndShortSecretsAreRefused) {
  EXPECT_NE(CheckCourseSecret(""), "");
  EXPECT_NE(CheckCourseSecret("short").find("at least 16"), std::string::npos) << CheckCourseSecret("short");
  EXPECT_EQ(CheckCourseSecret(kSecret), "");
}

TEST(CourseSecretTest, AFileLosesItsTrailingNewlineOnly) {
  const fs::path dir = Fresh("secret_file");
  std::ofstream(dir / "secret") << kSecret << "\n";
  std::string error;
  EXPECT_EQ(ReadCourseSecretFile((dir / "secret").string(), error), std::string(kSecret)) << error;
  std::ofstream(dir / "short") << "abc\n";
  EXPECT_FALSE(ReadCourseSecretFile((dir / "short").string(), error));
  EXPECT_NE(error.find("short: the course secret has 3 bytes"), std::string::npos) << error;
  EXPECT_FALSE(ReadCourseSecretFile((dir / "missing").string(), error));
  EXPECT_NE(error.find("cannot read the course secret file"), std::string::npos) << error;
}

TEST(GradescopeMetadataTest, OneUsersIdIsTheStudent) {
  std::string error;
  const char* text = R"({"id": 123, "users": [{"email": "alice@example.edu", "id": 4242, "name": "Alice"}]})";
  EXPECT_EQ(StudentFromGradescopeMetadata(text, "meta.json", error), std::string("4242")) << error;
}

TEST(GradescopeMetadataTest, AGroupGetsItsSortedIdsWhoeverSubmitted) {
  std::string error;
  const auto first = StudentFromGradescopeMetadata(R"({"users": [{"id": 9}, {"id": 10}, {"id": "x7"}]})", "m", error);
  const auto second = StudentFromGradescopeMetadata(R"({"users": [{"id": "x7"}, {"id": 10}, {"id": 9}]})", "m", error);
  ASSERT_TRUE(first) << error;
  EXPECT_EQ(*first, "10+9+x7");
  EXPECT_EQ(first, second);
}

TEST(GradescopeMetadataTest, MalformedMetadataSaysWhatIsWrong) {
  std::string error;
  EXPECT_FALSE(StudentFromGradescopeMetadata("{\"users\": [", "meta.json", error));
  EXPECT_NE(error.find("meta.json: not JSON"), std::string::npos) << error;
  EXPECT_FALSE(StudentFromGradescopeMetadata(R"({"id": 1})", "meta.json", error));
  EXPECT_NE(error.find("meta.json: no 'users' list"), std::string::npos) << error;
  EXPECT_FALSE(StudentFromGradescopeMetadata(R"({"users": []})", "meta.json", error));
  EXPECT_NE(error.find("no 'users' list"), std::string::npos) << error;
  EXPECT_FALSE(StudentFromGradescopeMetadata(R"({"users": [{"id": 1}, {"email": "b@x"}]})", "meta.json", error));
  EXPECT_NE(error.find("meta.json: users[1] has no 'id'"), std::string::npos) << error;
  EXPECT_FALSE(StudentFromGradescopeMetadata(R"({"users": [{"id": ""}]})", "meta.json", error));
  EXPECT_NE(error.find("users[0] has no 'id'"), std::string::npos) << error;
}

TEST(GradescopeMetadataTest, AMissingFileIsAnError) {
  const fs::path dir = Fresh("metadata");
  std::string error;
  EXPECT_FALSE(StudentFromGradescopeMetadataFile((dir / "submission_metadata.json").string(), error));
  EXPECT_NE(error.find("cannot read Gradescope's submission metadata"), std::string::npos) << error;
  std::ofstream(dir / "submission_metadata.json") << R"({"users": [{"id": 5}]})";
  EXPECT_EQ(StudentFromGradescopeMetadataFile((dir / "submission_metadata.json").string(), error),
            std::string("5"));
}

}  // namespace
}  // namespace syrof::grader
