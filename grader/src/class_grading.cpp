// A class: students on worker threads, resume, shards, the CSV and summary.
#include "syrof/grader/class_grading.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "syrof/grader/grade_json.h"
#include "syrof/grader/outputs.h"
#include "syrof/report/reports.h"
#include "shared_text.h"

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::SubmissionResult;
using assignment::TestResult;

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// The scenarios in the order the tests name them (first student first).
std::vector<std::string> ScenarioColumns(const std::vector<SubmissionResult>& students) {
  std::vector<std::string> columns;
  std::set<std::string> seen;
  for (const SubmissionResult& student : students) {
    for (const TestResult& test : student.tests) {
      const std::string column = test.search ? test.name : test.scenario;
      if (seen.insert(column).second) columns.push_back(column);
    }
  }
  return columns;
}

}  // namespace

ShardOrError ParseShard(const std::string& text) {
  const size_t slash = text.find('/');
  Shard shard;
  auto number = [](std::string_view part, int& value) {
    const auto [end, status] = std::from_chars(part.data(), part.data() + part.size(), value);
    return status == std::errc() && end == part.data() + part.size();
  };
  if (slash == std::string::npos || !number(std::string_view(text).substr(0, slash), shard.index) ||
      !number(std::string_view(text).substr(slash + 1), shard.count)) {
    return {std::nullopt, lab::Error{.where = "", .message = "--shard must be I/N (for example 2/4), not '" + text + "'"}};
  }
  if (shard.count < 1 || shard.count > 10000 || shard.index < 1 || shard.index > shard.count) {
    return {std::nullopt,
            lab::Error{.where = "", .message = "--shard I/N needs 1 <= I <= N <= 10000, not '" + text + "'"}};
  }
  return {shard, std::nullopt};
}

std::vector<std::string> ListStudents(const std::string& submissions_dir) {
  std::vector<std::string> students;
  std::error_code error;
  for (fs::directory_iterator it(submissions_dir, error); !error && it != fs::directory_iterator();
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.' || !it->is_directory(error)) continue;
    students.push_back(name);
  }
  std::sort(students.begin(), students.end());
  return students;
}

std::vector<std::string> ShardOf(const std::vector<std::string>& students, const Shard& shard) {
  const size_t n = students.size();
  const size_t begin = n * static_cast<size_t>(shard.index - 1) / static_cast<size_t>(shard.count);
  const size_t end = n * static_cast<size_t>(shard.index) / static_cast<size_t>(shard.count);
  return {students.begin() + static_cast<std::ptrdiff_t>(begin), students.begin() + static_cast<std::ptrdiff_t>(end)};
}

ClassResult GradeClass(const assignment::Assignment& assignment, const std::string& submissions_dir,
                       const std::string& out_dir, const ClassOptions& options) {
  const std::vector<std::string> students = ShardOf(ListStudents(submissions_dir), options.shard);
  ClassResult result;
  result.students.resize(students.size());
  std::vector<bool> resumed(students.size(), false);
  std::mutex mutex;
  std::set<std::string> notes;
  std::atomic<size_t> next{0};
  GradeOptions grade = options.grade;
  grade.jobs = 1;
  grade.on_test = nullptr;
  const bool public_only = options.grade.public_only || assignment.hidden_missing;
  auto work = [&] {
    for (size_t index = next++; index < students.size(); index = next++) {
      const fs::path submission = fs::path(submissions_dir) / students[index];
      const fs::path out = fs::path(out_dir) / students[index];
      // With per-student seeds, the folder's name is the student's id.
      GradeOptions student_grade = grade;
      if (student_grade.student_seeds) student_grade.student_seeds->student = students[index];
      const std::string hidden_seeds =
          student_grade.student_seeds && !public_only
              ? HiddenSeedsText(WithStudentSeeds(assignment, *student_grade.student_seeds))
              : std::string();
      const std::string hash = InputsHash(submission.string(), options.assignment_dir, public_only, hidden_seeds);
      std::optional<GradeFile> previous;
      if (options.resume) previous = ReadGradeJson((out / "grade.json").string()).file;
      if (previous && previous->inputs_hash == hash) {
        result.students[index] = previous->result;
        resumed[index] = true;
        // The reports again, in the form asked this time: switching forms
        // needs no regrade.
        report::ReportOptions report_options;
        report_options.form = options.full_report ? report::ReportForm::kFull : report::ReportForm::kStudent;
        report::WriteSubmissionReports(result.students[index], out.string(), report_options);
      } else {
        std::vector<std::string> student_notes;
        result.students[index] =
            GradeSubmission(assignment, submission.string(), out.string(), student_grade, student_notes);
        result.students[index].submission = students[index];
        WriteSubmissionOutputs(result.students[index], hash, student_notes, out.string(), options.full_report);
        const std::lock_guard<std::mutex> lock(mutex);
        notes.insert(student_notes.begin(), student_notes.end());
      }
      if (options.on_student) {
        const std::lock_guard<std::mutex> lock(mutex);
        options.on_student(result.students[index], resumed[index]);
      }
    }
  };
  const int jobs = std::clamp(options.jobs, 1, 256);
  std::vector<std::thread> workers;
  for (int i = 1; i < jobs && static_cast<size_t>(i) < students.size(); ++i) workers.emplace_back(work);
  work();
  for (std::thread& worker : workers) worker.join();
  for (bool was_resumed : resumed) (was_resumed ? result.resumed : result.graded) += 1;
  result.notes.assign(notes.begin(), notes.end());
  WriteClassFiles(result.students, out_dir);
  return result;
}

std::string ClassCsv(const std::vector<SubmissionResult>& students) {
  const std::vector<std::string> columns = ScenarioColumns(students);
  std::string csv = "student,points,max_points,tests_passed,tests,build";
  for (const std::string& column : columns) csv += "," + CsvField(column);
  csv += "\n";
  for (const SubmissionResult& student : students) {
    std::map<std::string, double> per_scenario;
    for (const TestResult& test : student.tests) per_scenario[test.search ? test.name : test.scenario] += test.points;
    csv += CsvField(student.submission) + "," + PointsText(student.points) + "," + PointsText(student.max_points) + "," +
           std::to_string(student.tests_passed) + "," + std::to_string(student.tests.size()) + "," +
           CsvField(ToString(student.build.verdict));
    for (const std::string& column : columns) {
      const auto found = per_scenario.find(column);
      csv += "," + (found == per_scenario.end() ? std::string() : PointsText(found->second));
    }
    csv += "\n";
  }
  return csv;
}

std::string ClassSummary(const std::vector<SubmissionResult>& students) {
  std::ostringstream text;
  if (students.empty()) return "No submissions.\n";
  const SubmissionResult& first = students.front();
  text << first.title << " (" << first.assignment << "): " << students.size() << " submission"
       << (students.size() == 1 ? "" : "s") << "\n";
  std::vector<double> points;
  double sum = 0;
  for (const SubmissionResult& student : students) {
    points.push_back(student.points);
    sum += student.points;
  }
  std::sort(points.begin(), points.end());
  const size_t n = points.size();
  const double median = n % 2 == 1 ? points[n / 2] : (points[n / 2 - 1] + points[n / 2]) / 2.0;
  const double max_points = first.max_points;
  text << "Points: mean " << PointsText(sum / static_cast<double>(n)) << ", median " << PointsText(median) << ", min "
       << PointsText(points.front()) << ", max " << PointsText(points.back()) << " (out of " << PointsText(max_points) << ")\n";
  text << "Histogram (tenths of the points):\n";
  int bins[10] = {0};
  for (double value : points) {
    const double fraction = max_points > 0 ? value / max_points : 0.0;
    bins[std::clamp(static_cast<int>(fraction * 10.0 + 1e-9), 0, 9)] += 1;
  }
  for (int i = 0; i < 10; ++i) {
    char label[64];
    std::snprintf(label, sizeof label, "  %3d-%3d%%%s %4d  ", i * 10, (i + 1) * 10, i == 9 ? "]" : ")", bins[i]);
    text << label << std::string(static_cast<size_t>(bins[i]), '#') << "\n";
  }
  std::vector<const SubmissionResult*> failed_builds;
  for (const SubmissionResult& student : students) {
    if (!student.build.ok()) failed_builds.push_back(&student);
  }
  text << "Builds failed: " << failed_builds.size() << "\n";
  for (const SubmissionResult* student : failed_builds) {
    text << "  " << student->submission << ": " << ToString(student->build.verdict) << ": " << student->build.detail << "\n";
  }
  std::map<std::string, int> failures;
  std::vector<std::string> order;
  for (const SubmissionResult& student : students) {
    if (!student.build.ok()) continue;
    for (const TestResult& test : student.tests) {
      if (!failures.contains(test.name)) order.push_back(test.name);
      failures[test.name] += test.passed ? 0 : 1;
    }
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](const std::string& a, const std::string& b) { return failures[a] > failures[b]; });
  const size_t built = students.size() - failed_builds.size();
  text << "Most-failed tests (of " << built << " submission" << (built == 1 ? "" : "s") << " that built):\n";
  size_t shown = 0;
  for (const std::string& name : order) {
    if (failures[name] == 0 || shown == 5) break;
    text << "  " << name << ": failed by " << failures[name] << "\n";
    ++shown;
  }
  if (shown == 0) text << "  none\n";
  return text.str();
}

std::optional<lab::Error> WriteClassFiles(const std::vector<SubmissionResult>& students, const std::string& out_dir) {
  std::error_code error;
  fs::create_directories(out_dir, error);
  std::ofstream csv(fs::path(out_dir) / "class.csv", std::ios::binary | std::ios::trunc);
  csv << ClassCsv(students);
  std::ofstream summary(fs::path(out_dir) / "summary.txt", std::ios::binary | std::ios::trunc);
  summary << ClassSummary(students);
  if (!csv || !summary) return lab::Error{.where = "", .message = "cannot write class.csv or summary.txt in " + out_dir};
  return std::nullopt;
}

MergedClass MergeClassOutputs(const std::vector<std::string>& shard_dirs, const std::string& out_dir) {
  auto failed = [](std::string where, std::string message) {
    return MergedClass{std::nullopt, lab::Error{.where = std::move(where), .message = std::move(message)}};
  };
  std::map<std::string, SubmissionResult> by_student;
  for (const std::string& dir : shard_dirs) {
    std::error_code io_error;
    if (!fs::is_directory(dir, io_error)) {
      return failed(dir, "not a folder");
    }
    // A shard writes class.csv last, once every student of it is graded: a
    // shard stopped on the way (scancel, a lost node, a time limit) has
    // none, and merging it would drop its students without a word.
    if (!fs::is_regular_file(fs::path(dir) / "class.csv", io_error)) {
      return failed(dir, "this shard did not finish (it has no class.csv): grade it again, it resumes where it stopped");
    }
    for (const std::string& student : ListStudents(dir)) {
      const fs::path path = fs::path(dir) / student / "grade.json";
      if (!fs::exists(path, io_error)) {
        return failed((fs::path(dir) / student).string(),
                      "no grade.json: this shard did not finish grading the student: grade it again, it resumes");
      }
      GradeFileOrError read = ReadGradeJson(path.string());
      if (!read.ok()) return {std::nullopt, std::move(read.error)};
      read.file->result.submission = student;
      if (!by_student.emplace(student, std::move(read.file->result)).second) {
        return failed("", "student '" + student + "' is in two of the folders merged (" + path.string() + ")");
      }
    }
  }
  std::vector<SubmissionResult> students;
  for (auto& [name, result] : by_student) students.push_back(std::move(result));
  if (std::optional<lab::Error> problem = WriteClassFiles(students, out_dir)) return {std::nullopt, std::move(problem)};
  return {std::move(students), std::nullopt};
}

}  // namespace syrof::grader
