// Per-student hidden seeds: the keyed hash, the secret's checks and
// Gradescope's submission metadata.
#include "syrof/grader/student_seeds.h"

#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <vector>

namespace syrof::grader {
namespace {

using assignment::Assignment;
using assignment::ScenarioRun;

// Appends `value` as 8 bytes, big-endian.
void AppendUint64(std::string& message, uint64_t value) {
  for (int shift = 56; shift >= 0; shift -= 8) message += static_cast<char>((value >> shift) & 0xff);
}

// A field with its length first: ("ab", "c") and ("a", "bc") differ.
void AppendField(std::string& message, std::string_view field) {
  AppendUint64(message, field.size());
  message.append(field);
}

}  // namespace

uint64_t DeriveSeed(std::string_view course_secret, std::string_view assignment, std::string_view scenario,
                    std::string_view student, uint64_t index) {
  std::string message = "syrof hidden seed v1";  // a new derivation gets a new label
  AppendField(message, assignment);
  AppendField(message, scenario);
  AppendField(message, student);
  AppendUint64(message, index);
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int digest_size = 0;
  const unsigned char* done =
      HMAC(EVP_sha256(), course_secret.data(), static_cast<int>(course_secret.size()),
           reinterpret_cast<const unsigned char*>(message.data()), message.size(), digest, &digest_size);
  // HMAC-SHA256 fails only when libcrypto cannot allocate: grading cannot go on.
  if (done == nullptr || digest_size < 8) std::abort();
  uint64_t seed = 0;
  for (int i = 0; i < 8; ++i) seed = (seed << 8) | digest[i];
  return seed;
}

Assignment WithStudentSeeds(const Assignment& assignment, const StudentSeeds& seeds) {
  Assignment derived = assignment;
  for (ScenarioRun& run : derived.hidden_runs) {
    const size_t count = run.seeds.size();
    std::vector<uint64_t> chosen;
    std::set<uint64_t> taken;
    for (uint64_t index = 0; chosen.size() < count; ++index) {
      const uint64_t seed = DeriveSeed(seeds.course_secret, assignment.title, run.name, seeds.student, index);
      if (taken.insert(seed).second) chosen.push_back(seed);
    }
    run.seeds = std::move(chosen);
  }
  return derived;
}

std::string HiddenSeedsText(const Assignment& assignment) {
  std::string text;
  for (const ScenarioRun& run : assignment.hidden_runs) {
    text += run.name + ":";
    for (const uint64_t seed : run.seeds) text += " " + std::to_string(seed);
    text += "; ";
  }
  return text;
}

std::optional<lab::Error> CheckCourseSecret(std::string_view secret) {
  if (secret.empty()) return lab::Error{.where = "", .message = "the course secret is empty"};
  if (secret.size() < kMinimumCourseSecretBytes) {
    return lab::Error{.where = "",
                      .message = "the course secret has " + std::to_string(secret.size()) + " bytes; it needs at least " +
                                 std::to_string(kMinimumCourseSecretBytes) + " (for example `openssl rand -hex 32`)"};
  }
  return std::nullopt;
}

namespace {

// The bytes of the file at `path`, or an error saying that `what` cannot be
// read.
struct FileOrError {
  std::optional<std::string> bytes;
  std::optional<lab::Error> error;
};

FileOrError ReadWholeFile(const std::string& path, const std::string& what) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return {std::nullopt, lab::Error{.where = "", .message = "cannot read " + what + " '" + path + "'"}};
  std::ostringstream bytes;
  bytes << file.rdbuf();
  return {bytes.str(), std::nullopt};
}

// An error at `where` (a file, or the text's source).
lab::Error ErrorAt(const std::string& where, std::string message) {
  return lab::Error{.where = where, .message = std::move(message)};
}

}  // namespace

CourseSecretOrError ReadCourseSecretFile(const std::string& path) {
  FileOrError read = ReadWholeFile(path, "the course secret file");
  if (!read.bytes) return {std::nullopt, std::move(read.error)};
  std::string secret = *std::move(read.bytes);
  while (!secret.empty() && (secret.back() == '\n' || secret.back() == '\r')) secret.pop_back();
  if (std::optional<lab::Error> problem = CheckCourseSecret(secret)) {
    return {std::nullopt, ErrorAt(path, std::move(problem->message))};
  }
  return {std::move(secret), std::nullopt};
}

StudentOrError StudentFromGradescopeMetadata(std::string_view text, const std::string& source) {
  const nlohmann::json root = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) {
    return {std::nullopt,
            ErrorAt(source, "not JSON (Gradescope's submission metadata is a JSON object with a 'users' list)")};
  }
  if (!root.is_object() || !root.contains("users") || !root["users"].is_array() || root["users"].empty()) {
    return {std::nullopt,
            ErrorAt(source, "no 'users' list naming who submitted (Gradescope's submission metadata has one)")};
  }
  std::vector<std::string> ids;
  for (size_t i = 0; i < root["users"].size(); ++i) {
    const nlohmann::json& user = root["users"][i];
    const nlohmann::json* id = user.is_object() && user.contains("id") ? &user["id"] : nullptr;
    if (id != nullptr && id->is_number_integer()) {
      ids.push_back(std::to_string(id->get<int64_t>()));
    } else if (id != nullptr && id->is_string() && !id->get<std::string>().empty()) {
      ids.push_back(id->get<std::string>());
    } else {
      return {std::nullopt,
              ErrorAt(source, "users[" + std::to_string(i) + "] has no 'id' (a number or a non-empty string)")};
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::string student;
  for (const std::string& id : ids) student += (student.empty() ? "" : "+") + id;
  return {std::move(student), std::nullopt};
}

StudentOrError StudentFromGradescopeMetadataFile(const std::string& path) {
  FileOrError text = ReadWholeFile(path, "Gradescope's submission metadata");
  if (!text.bytes) return {std::nullopt, std::move(text.error)};
  return StudentFromGradescopeMetadata(*text.bytes, path);
}

SubmissionNumberOrError SubmissionNumberFromGradescopeMetadataFile(const std::string& path) {
  FileOrError text = ReadWholeFile(path, "Gradescope's submission metadata");
  if (!text.bytes) return {std::nullopt, std::move(text.error)};
  const nlohmann::json root = nlohmann::json::parse(*text.bytes, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) {
    return {std::nullopt, ErrorAt(path, "not a JSON object (Gradescope's submission metadata is one)")};
  }
  if (!root.contains("previous_submissions")) return {1, std::nullopt};
  const nlohmann::json& previous = root["previous_submissions"];
  if (!previous.is_array()) return {std::nullopt, ErrorAt(path, "'previous_submissions' is not a list")};
  return {static_cast<int>(std::min<size_t>(previous.size(), 1000000)) + 1, std::nullopt};
}

}  // namespace syrof::grader
