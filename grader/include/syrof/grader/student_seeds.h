// Hidden seeds per student (docs/grading.md, "Hidden seeds per student"):
// each student's hidden runs use seeds derived from the student's id and a
// course secret, instead of the seeds assignment.yaml lists, so students
// cannot share which hidden seeds fail. Public seeds stay as listed:
// students run them locally.
//
// A seed is HMAC-SHA256 (OpenSSL's libcrypto), keyed with the course
// secret, of the assignment's title, the scenario entry's name, the
// student's id and the seed's index, each field length-prefixed so no two
// different inputs give the same message; the seed is the digest's first 8
// bytes, big-endian. The same inputs give the same seed on every machine,
// so a regrade gives the same result; without the secret the seeds cannot
// be predicted from the id. The title, not the folder's name, identifies
// the assignment: a Gradescope bundle holds the folder as `assignment/`, and
// the instructor's local regrade must give the bundle's seeds.
//
// The secret is never written to any output: only the student id and the
// derived seeds are (grade.json, the reports).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "syrof/assignment/assignment.h"
#include "syrof/lab/base/error.h"

namespace syrof::grader {

/// The shortest course secret accepted, in bytes: shorter ones can be guessed.
inline constexpr size_t kMinimumCourseSecretBytes = 16;

/// The environment variable `syrof grade` reads the course secret from.
inline constexpr const char* kCourseSecretVariable = "SYROF_COURSE_SECRET";

/// What derives one student's hidden seeds. `course_secret` is never printed.
struct StudentSeeds {
  std::string course_secret;
  std::string student;  ///< the student's id: an email, a roster id, a folder name
};

/// The `index`-th derived seed of scenario entry `scenario` of the
/// assignment titled `assignment` for `student`. Deterministic; a different secret, assignment, entry,
/// student or index gives an unrelated seed.
uint64_t DeriveSeed(std::string_view course_secret, std::string_view assignment, std::string_view scenario,
                    std::string_view student, uint64_t index);

/// `assignment` with every hidden entry's seeds replaced by as many seeds
/// derived for `seeds.student` (indices 0, 1, ...; an index whose seed
/// repeats one already taken in the entry is skipped, so an entry never
/// repeats a seed). Public entries are unchanged.
assignment::Assignment WithStudentSeeds(const assignment::Assignment& assignment, const StudentSeeds& seeds);

/// The hidden entries' seeds as text ("join10: 1 2 3; ..."), for the
/// inputs' hash of a class: derived seeds change when the secret does.
std::string HiddenSeedsText(const assignment::Assignment& assignment);

/// Why `secret` cannot be used (empty, too short); nothing when it can.
std::optional<lab::Error> CheckCourseSecret(std::string_view secret);

/// A course secret, or why there is none.
struct CourseSecretOrError {
  std::optional<std::string> secret;
  std::optional<lab::Error> error;
  bool ok() const { return secret.has_value(); }
};

/// The course secret in file `path`: its bytes without trailing newlines
/// (as `echo` or an editor leaves them). An error, where the file, when it
/// cannot be read or the secret fails CheckCourseSecret.
CourseSecretOrError ReadCourseSecretFile(const std::string& path);

/// A student id, or why there is none.
struct StudentOrError {
  std::optional<std::string> student;
  std::optional<lab::Error> error;
  bool ok() const { return student.has_value(); }
};

/// The student id of a Gradescope submission from the text of its
/// /autograder/submission_metadata.json: the `id` of every entry of
/// `users` (a number or a string), sorted and joined with '+', so a group
/// submission gets the same id whoever of the group submitted. An error,
/// where `source`, when the text is not JSON, has no `users`, or a user
/// has no id.
StudentOrError StudentFromGradescopeMetadata(std::string_view text, const std::string& source);

/// The same, reading the file `path` (a missing file is an error).
StudentOrError StudentFromGradescopeMetadataFile(const std::string& path);

/// Which submission of its student(s), or why it cannot be told.
struct SubmissionNumberOrError {
  std::optional<int> number;
  std::optional<lab::Error> error;
  bool ok() const { return number.has_value(); }
};

/// Which submission of its student(s) Gradescope's submission_metadata.json
/// describes: 1 + the length of its `previous_submissions` list (1 when it
/// has none). An error naming the file and the problem when the file
/// cannot be read or `previous_submissions` is not a list.
SubmissionNumberOrError SubmissionNumberFromGradescopeMetadataFile(const std::string& path);

}  // namespace syrof::grader
