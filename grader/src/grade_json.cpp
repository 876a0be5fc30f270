// grade.json written and read back, and the inputs' hash for resuming.
#include "syrof/grader/grade_json.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::CriterionScore;
using assignment::SubmissionResult;
using assignment::TestResult;
using assignment::Visibility;
using Json = nlohmann::ordered_json;

constexpr const char* kFormat = "syrof-grade";

Json TestJson(const TestResult& test) {
  Json criteria = Json::array();
  for (const CriterionScore& criterion : test.score.criteria) {
    criteria.push_back(Json{{"criterion", criterion.criterion},
                            {"points", criterion.points},
                            {"max_points", criterion.max_points},
                            {"reason", criterion.reason}});
  }
  Json json{{"name", test.name},
              {"scenario", test.scenario},
              {"seed", test.seed},
              {"search", test.search},
              {"visibility", test.visibility == Visibility::kHidden ? "hidden" : "public"},
              {"points", test.points},
              {"max_points", test.max_points},
              {"passed", test.passed},
              {"run_error", test.run_error},
              {"message_format", test.message_format},
              {"run_points", test.score.points},
              {"run_max_points", test.score.max_points},
              {"criteria", criteria},
              {"replay_command", test.replay_command},
              {"output_dir", test.output_dir},
              {"replay_path", test.replay_path}};
  // Only when assignment.yaml chose one: grade.json's bytes otherwise as before.
  if (test.gradescope != assignment::GradescopeVisibility::kDefault) json["gradescope"] = ToString(test.gradescope);
  return json;
}

// FNV-1a, 64 bits.
struct Hash {
  uint64_t value = 0xcbf29ce484222325ull;
  void Add(const void* data, size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
      value ^= bytes[i];
      value *= 0x100000001b3ull;
    }
  }
  void Add(const std::string& text) {
    const uint64_t size = text.size();
    Add(&size, sizeof size);
    Add(text.data(), text.size());
  }
};

// Every regular file under `dir` (hidden folders and build/ left out, as the
// build's copy leaves them), by relative name and bytes, in name order.
void AddFolder(Hash& hash, const std::string& dir) {
  std::vector<fs::path> files;
  std::error_code error;
  fs::recursive_directory_iterator it(dir, fs::directory_options::none, error);
  for (; !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (it->is_directory(error)) {
      if (name.empty() || name[0] == '.' || name == "build" || name.starts_with("cmake-build")) {
        it.disable_recursion_pending();
      }
      continue;
    }
    if (!it->is_symlink(error) && it->is_regular_file(error)) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    hash.Add(file.lexically_relative(dir).generic_string());
    std::ifstream in(file, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    hash.Add(bytes.str());
  }
}

template <typename T>
T Get(const nlohmann::json& json, const char* key, const T& fallback) {
  if (!json.is_object() || !json.contains(key)) return fallback;
  try {
    return json.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    return fallback;
  }
}

}  // namespace

std::string SyrofVersion() { return SYROF_VERSION_STRING; }

std::string GradeJson(const GradeFile& file) {
  const SubmissionResult& result = file.result;
  Json tests = Json::array();
  Json test_timings = Json::object();
  for (const TestResult& test : result.tests) {
    tests.push_back(TestJson(test));
    test_timings[test.name] = test.wall_seconds;
  }
  Json root{{"format", kFormat},
            {"version", kGradeJsonVersion},
            {"syrof_version", file.syrof_version},
            {"inputs_hash", file.inputs_hash},
            {"notes", file.notes},
            {"submission", result.submission},
            {"assignment", result.assignment},
            {"title", result.title},
            {"public_only", result.public_only},
            {"seed_student", result.seed_student},
            {"points", result.points},
            {"max_points", result.max_points},
            {"tests_passed", result.tests_passed},
            {"tests_total", result.tests.size()},
            {"build",
             Json{{"verdict", ToString(result.build.verdict)},
                  {"detail", result.build.detail},
                  {"log_path", result.build.log_path},
                  {"library_path", result.build.library_path}}},
            {"tests", tests},
            {"timings", Json{{"build_s", result.build.wall_seconds}, {"tests", test_timings}}}};
  return root.dump(2) + "\n";
}

GradeFileOrError ReadGradeJson(const std::string& path) {
  auto failed = [&path](std::string message) {
    return GradeFileOrError{std::nullopt, lab::Error{.where = path, .message = std::move(message)}};
  };
  std::ifstream in(path, std::ios::binary);
  if (!in) return failed("cannot be read");
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& parse_error) {
    return failed(std::string("not JSON: ") + parse_error.what());
  }
  if (Get<std::string>(root, "format", "") != kFormat || Get<int>(root, "version", 0) != kGradeJsonVersion) {
    return failed(std::string("not a grade.json of format ") + kFormat + " version " + std::to_string(kGradeJsonVersion));
  }
  GradeFile file;
  file.syrof_version = Get<std::string>(root, "syrof_version", "");
  file.inputs_hash = Get<std::string>(root, "inputs_hash", "");
  file.notes = Get<std::vector<std::string>>(root, "notes", {});
  SubmissionResult& result = file.result;
  result.submission = Get<std::string>(root, "submission", "");
  result.assignment = Get<std::string>(root, "assignment", "");
  result.title = Get<std::string>(root, "title", "");
  result.public_only = Get<bool>(root, "public_only", false);
  result.seed_student = Get<std::string>(root, "seed_student", "");
  result.points = Get<double>(root, "points", 0.0);
  result.max_points = Get<double>(root, "max_points", 0.0);
  result.tests_passed = Get<int>(root, "tests_passed", 0);
  const nlohmann::json build = root.value("build", nlohmann::json::object());
  const std::string verdict = Get<std::string>(build, "verdict", "");
  if (const auto named = assignment::BuildVerdictNamed(verdict)) {
    result.build.verdict = *named;
  } else {
    return failed("build.verdict \"" + verdict + "\" is not a build verdict (ok, build_failed, ...)");
  }
  result.build.detail = Get<std::string>(build, "detail", "");
  result.build.log_path = Get<std::string>(build, "log_path", "");
  result.build.library_path = Get<std::string>(build, "library_path", "");
  const nlohmann::json timings = root.value("timings", nlohmann::json::object());
  result.build.wall_seconds = Get<double>(timings, "build_s", 0.0);
  const nlohmann::json test_timings = timings.value("tests", nlohmann::json::object());
  if (!root.contains("tests") || !root["tests"].is_array()) return failed("no tests array");
  for (const nlohmann::json& entry : root["tests"]) {
    TestResult test;
    test.name = Get<std::string>(entry, "name", "");
    test.scenario = Get<std::string>(entry, "scenario", "");
    test.seed = Get<uint64_t>(entry, "seed", 0);
    test.search = Get<bool>(entry, "search", false);
    test.visibility = Get<std::string>(entry, "visibility", "public") == "hidden" ? Visibility::kHidden
                                                                                   : Visibility::kPublic;
    const std::string gradescope = Get<std::string>(entry, "gradescope", "");
    for (const auto candidate : {assignment::GradescopeVisibility::kVisible, assignment::GradescopeVisibility::kHidden,
                                 assignment::GradescopeVisibility::kAfterDueDate,
                                 assignment::GradescopeVisibility::kAfterPublished}) {
      if (gradescope == ToString(candidate)) test.gradescope = candidate;
    }
    test.points = Get<double>(entry, "points", 0.0);
    test.max_points = Get<double>(entry, "max_points", 0.0);
    test.passed = Get<bool>(entry, "passed", false);
    test.run_error = Get<std::string>(entry, "run_error", "");
    test.message_format = Get<std::string>(entry, "message_format", "");
    test.score.points = Get<double>(entry, "run_points", 0.0);
    test.score.max_points = Get<double>(entry, "run_max_points", 0.0);
    for (const nlohmann::json& criterion : entry.value("criteria", nlohmann::json::array())) {
      test.score.criteria.push_back(CriterionScore{Get<std::string>(criterion, "criterion", ""),
                                                   Get<double>(criterion, "points", 0.0),
                                                   Get<double>(criterion, "max_points", 0.0),
                                                   Get<std::string>(criterion, "reason", "")});
    }
    test.replay_command = Get<std::string>(entry, "replay_command", "");
    test.output_dir = Get<std::string>(entry, "output_dir", "");
    test.replay_path = Get<std::string>(entry, "replay_path", "");
    test.wall_seconds = Get<double>(test_timings, test.name.c_str(), 0.0);
    result.tests.push_back(std::move(test));
  }
  return {std::move(file), std::nullopt};
}

std::string InputsHash(const std::string& submission_dir, const std::string& assignment_dir, bool public_only,
                       const std::string& hidden_seeds) {
  Hash hash;
  hash.Add("submission");
  AddFolder(hash, submission_dir);
  hash.Add("assignment");
  AddFolder(hash, assignment_dir);
  hash.Add("syrof " + SyrofVersion());
  hash.Add(public_only ? "public only" : "all tests");
  if (!hidden_seeds.empty()) hash.Add("hidden seeds " + hidden_seeds);  // absent: the hashes of before
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash.value));
  return text;
}

}  // namespace syrof::grader
