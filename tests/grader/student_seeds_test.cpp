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
  ASSERT_TRUE(CheckCourseSecret(""));
  EXPECT_EQ(CheckCourseSecret("")->ToString(), "the course secret is empty");
  ASSERT_TRUE(CheckCourseSecret("short"));
  EXPECT_EQ(CheckCourseSecret("short")->ToString(),
            "the course secret has 5 bytes; it needs at least 16 (for example `openssl rand -hex 32`)");
  EXPECT_FALSE(CheckCourseSecret(kSecret));
}

TEST(CourseSecretTest, AFileLosesItsTrailingNewlineOnly) {
  const fs::path dir = Fresh("secret_file");
  std::ofstream(dir / "secret") << kSecret << "\n";
  const CourseSecretOrError read = ReadCourseSecretFile((dir / "secret").string());
  ASSERT_TRUE(read.ok()) << read.error->ToString();
  EXPECT_EQ(*read.secret, std::string(kSecret));
  EXPECT_FALSE(read.error);
  std::ofstream(dir / "short") << "abc\n";
  const CourseSecretOrError too_short = ReadCourseSecretFile((dir / "short").string());
  ASSERT_FALSE(too_short.ok());
  EXPECT_EQ(too_short.error->where, (dir / "short").string());
  EXPECT_EQ(too_short.error->ToString(), (dir / "short").string() +
                                              ": the course secret has 3 bytes; it needs at least 16 (for example "
                                              "`openssl rand -hex 32`)");
  const CourseSecretOrError missing = ReadCourseSecretFile((dir / "missing").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error->ToString(), "cannot read the course secret file '" + (dir / "missing").string() + "'");
}

TEST(GradescopeMetadataTest, OneUsersIdIsTheStudent) {
  const char* text = R"({"id": 123, "users": [{"email": "alice@example.edu", "id": 4242, "name": "Alice"}]})";
  const StudentOrError read = StudentFromGradescopeMetadata(text, "meta.json");
  ASSERT_TRUE(read.ok()) << read.error->ToString();
  EXPECT_EQ(*read.student, "4242");
}

TEST(GradescopeMetadataTest, AGroupGetsItsSortedIdsWhoeverSubmitted) {
  const auto first = StudentFromGradescopeMetadata(R"({"users": [{"id": 9}, {"id": 10}, {"id": "x7"}]})", "m");
  const auto second = StudentFromGradescopeMetadata(R"({"users": [{"id": "x7"}, {"id": 10}, {"id": 9}]})", "m");
  ASSERT_TRUE(first.ok()) << first.error->ToString();
  EXPECT_EQ(*first.student, "10+9+x7");
  EXPECT_EQ(first.student, second.student);
}

TEST(GradescopeMetadataTest, MalformedMetadataSaysWhatIsWrong) {
  auto error_of = [](std::string_view text) {
    const StudentOrError read = StudentFromGradescopeMetadata(text, "meta.json");
    EXPECT_FALSE(read.ok()) << text;
    return read.error ? read.error->ToString() : std::string("(no error)");
  };
  EXPECT_EQ(error_of("{\"users\": ["),
            "meta.json: not JSON (Gradescope's submission metadata is a JSON object with a 'users' list)");
  EXPECT_EQ(error_of(R"({"id": 1})"),
            "meta.json: no 'users' list naming who submitted (Gradescope's submission metadata has one)");
  EXPECT_EQ(error_of(R"({"users": []})"),
            "meta.json: no 'users' list naming who submitted (Gradescope's submission metadata has one)");
  EXPECT_EQ(error_of(R"({"users": [{"id": 1}, {"email": "b@x"}]})"),
            "meta.json: users[1] has no 'id' (a number or a non-empty string)");
  EXPECT_EQ(error_of(R"({"users": [{"id": ""}]})"), "meta.json: users[0] has no 'id' (a number or a non-empty string)");
}

TEST(GradescopeMetadataTest, AMissingFileIsAnError) {
  const fs::path dir = Fresh("metadata");
  const std::string path = (dir / "submission_metadata.json").string();
  const StudentOrError missing = StudentFromGradescopeMetadataFile(path);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error->ToString(), "cannot read Gradescope's submission metadata '" + path + "'");
  std::ofstream(path) << R"({"users": [{"id": 5}]})";
  const StudentOrError read = StudentFromGradescopeMetadataFile(path);
  ASSERT_TRUE(read.ok()) << read.error->ToString();
  EXPECT_EQ(*read.student, "5");
}

TEST(GradescopeMetadataTest, TheSubmissionNumberCountsThePreviousOnes) {
  const fs::path dir = Fresh("submission_number");
  const std::string path = (dir / "submission_metadata.json").string();
  const SubmissionNumberOrError missing = SubmissionNumberFromGradescopeMetadataFile(path);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error->ToString(), "cannot read Gradescope's submission metadata '" + path + "'");
  std::ofstream(path) << R"({"users": [{"id": 5}]})";
  SubmissionNumberOrError read = SubmissionNumberFromGradescopeMetadataFile(path);
  ASSERT_TRUE(read.ok()) << read.error->ToString();
  EXPECT_EQ(*read.number, 1);
  std::ofstream(path, std::ios::trunc) << R"({"previous_submissions": [{}, {}]})";
  read = SubmissionNumberFromGradescopeMetadataFile(path);
  ASSERT_TRUE(read.ok()) << read.error->ToString();
  EXPECT_EQ(*read.number, 3);
  std::ofstream(path, std::ios::trunc) << R"({"previous_submissions": 2})";
  read = SubmissionNumberFromGradescopeMetadataFile(path);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->ToString(), path + ": 'previous_submissions' is not a list");
  std::ofstream(path, std::ios::trunc) << "[1]";
  read = SubmissionNumberFromGradescopeMetadataFile(path);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error->ToString(), path + ": not a JSON object (Gradescope's submission metadata is one)");
}

}  // namespace
}  // namespace syrof::grader
