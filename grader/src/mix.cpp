#include "syrof/grader/mix.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "run_scenario.h"

namespace syrof::grader {
namespace {

using assignment::ScenarioRun;
using assignment::TestResult;

std::string Format(const char* format, auto... values) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format, values...);
  return buffer;
}

const ScenarioRun* FindRun(const assignment::Assignment& assignment, const std::string& name) {
  for (const auto* runs : {&assignment.public_runs, &assignment.hidden_runs}) {
    for (const ScenarioRun& run : *runs) {
      if (run.name == name) return &run;
    }
  }
  return nullptr;
}

// Attributes each robot's payloads that broke the message format to the
// submission it runs.
void AttributePayloads(const std::vector<internal::PayloadViolations>& violations, size_t k, MixRun& run) {
  for (size_t robot = 0; robot < violations.size(); ++robot) {
    if (violations[robot].count == 0) continue;
    MixShare& share = run.shares[robot % k];
    if (share.format_violations == 0) share.first_format_violation = "robot " + std::to_string(robot) + " " + violations[robot].first;
    share.format_violations += violations[robot].count;
  }
}

// Attributes the run's faults, collisions and first disagreement to the
// submissions whose robots they name.
void Attribute(const lab::metrics::Metrics& metrics, const std::vector<MixEntry>& entries, MixRun& run) {
  const size_t k = entries.size();
  for (uint16_t robot = 0; robot < metrics.robots; ++robot) run.shares[robot % k].robots.push_back(robot);
  for (const lab::metrics::AppFault& fault : metrics.app.faults) {
    MixShare& share = run.shares[fault.robot % k];
    if (share.faults++ == 0) {
      share.first_fault = Format("robot %u in %s at %.2f s: %s", unsigned{fault.robot}, fault.callback.c_str(),
                                 static_cast<double>(fault.time_ns) / 1e9, fault.verdict.c_str());
      if (!fault.detail.empty()) share.first_fault += " (" + fault.detail + ")";
    }
  }
  for (const lab::metrics::CollisionEvent& collision : metrics.collisions.pairs) {
    run.shares[collision.a % k].collisions += 1;
    if (collision.b % k != collision.a % k) run.shares[collision.b % k].collisions += 1;
  }
  if (metrics.app.invalid_commands.first) run.shares[metrics.app.invalid_commands.first->robot % k].invalid_commands = 1;
  if (const auto& first = metrics.agreement ? metrics.agreement->first_disagreement : std::nullopt) {
    // Both sides are named: which of two differing states is "wrong" is not
    // known from the pair alone. The side whose robot departed from the
    // epoch's first state disagreed first (the reference robot is only the
    // one that happened to answer first).
    run.shares[first->robot % k].in_first_disagreement = true;
    run.shares[first->robot % k].disagreed_first = true;
    run.shares[first->reference_robot % k].in_first_disagreement = true;
    run.disagreement = Format("epoch %u: robot %u (%s) returned %u in %s, robot %u (%s) %u", unsigned{first->epoch},
                              unsigned{first->robot}, entries[first->robot % k].name.c_str(), unsigned{first->state},
                              first->callback.c_str(), unsigned{first->reference_robot},
                              entries[first->reference_robot % k].name.c_str(), unsigned{first->reference_state});
  }
}

}  // namespace

std::vector<MixRun> RunMix(const assignment::Assignment& assignment, const std::vector<MixEntry>& entries,
                           const std::string& out_dir, const GradeOptions& options) {
  const std::vector<TestResult> tests = PlanRuns(assignment, options.public_only || assignment.hidden_missing);
  std::vector<MixRun> runs(tests.size());
  std::vector<std::string> libraries;
  for (const MixEntry& entry : entries) libraries.push_back(entry.library);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t index = next++; index < tests.size(); index = next++) {
      const TestResult& test = tests[index];
      MixRun& run = runs[index];
      run.name = test.name;
      run.output_dir = test.output_dir;
      const internal::RunOutcome outcome = internal::RunScenario(
          *FindRun(assignment, test.scenario), test.seed, libraries, libraries,
          (std::filesystem::path(out_dir) / test.output_dir).string(), true,
          assignment.message ? &*assignment.message : nullptr);
      run.run_error = outcome.run_error;
      run.shares.assign(entries.size(), MixShare{});
      AttributePayloads(outcome.payload_violations, entries.size(), run);
      if (outcome.metrics) {
        run.score = assignment::ScoreRun(assignment.rubric, *outcome.metrics);
        Attribute(*outcome.metrics, entries, run);
      }
    }
  };
  const int jobs = std::clamp(options.jobs, 1, 256);
  std::vector<std::thread> workers;
  for (int i = 1; i < jobs && static_cast<size_t>(i) < tests.size(); ++i) workers.emplace_back(work);
  work();
  for (std::thread& worker : workers) worker.join();
  return runs;
}

void PrintMixReport(const std::vector<MixRun>& runs, const std::vector<MixEntry>& entries, std::ostream& out) {
  out << "Mixed swarm of " << entries.size() << " submissions (robot i runs submission i mod " << entries.size()
      << "):";
  for (size_t i = 0; i < entries.size(); ++i) out << " " << i << "=" << entries[i].name;
  out << "\n";
  for (const MixRun& run : runs) {
    out << "\n" << run.name;
    if (!run.run_error.empty()) {
      out << ": " << run.run_error << "\n";
      continue;
    }
    out << Format(": swarm score %.2f/%.2f (%s)\n", run.score.points, run.score.max_points, run.output_dir.c_str());
    for (size_t i = 0; i < entries.size(); ++i) {
      const MixShare& share = run.shares[i];
      std::string robots;
      for (uint16_t robot : share.robots) robots += (robots.empty() ? "" : ",") + std::to_string(robot);
      out << "  " << entries[i].name << " (robots " << robots << "): ";
      std::vector<std::string> problems;
      if (share.format_violations > 0) {
        problems.push_back("broke the message format " + std::to_string(share.format_violations) + " times, first " +
                           share.first_format_violation);
      }
      if (share.faults > 0) problems.push_back(std::to_string(share.faults) + " faulted, first " + share.first_fault);
      if (share.collisions > 0) problems.push_back("in " + std::to_string(share.collisions) + " collisions");
      if (share.invalid_commands > 0) problems.push_back("gave the run's first invalid command");
      if (share.disagreed_first) {
        problems.push_back("disagreed first");
      } else if (share.in_first_disagreement) {
        problems.push_back("in the first disagreement");
      }
      if (problems.empty()) {
        out << "ok\n";
      } else {
        for (size_t p = 0; p < problems.size(); ++p) out << (p == 0 ? "" : "; ") << problems[p];
        out << "\n";
      }
    }
    std::string breakers;
    for (size_t i = 0; i < entries.size(); ++i) {
      if (run.shares[i].format_violations > 0) breakers += (breakers.empty() ? "" : ", ") + entries[i].name;
    }
    if (!breakers.empty()) out << "  message format broken by: " << breakers << "\n";
    if (!run.disagreement.empty()) out << "  first disagreement: " << run.disagreement << "\n";
  }
}

}  // namespace syrof::grader
