// One run of a scenario with a seed through the app host (grade.cpp's and
// mix.cpp's shared step), and a search test's runs. Internal to grader/.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/result.h"
#include "syrof/lab/metrics/metrics.h"
#include "syrof/lab/message/message_format.h"
#include "payload_check.h"

namespace syrof::grader::internal {

struct RunOutcome {
  std::optional<lab::metrics::Metrics> metrics;  ///< when the run finished
  std::string run_error;                         ///< why it has no metrics
  double wall_seconds = 0;
  /// With a message format: per robot id, the payloads it set that broke it.
  std::vector<PayloadViolations> payload_violations;
};

/// `library` as the outputs meant for students name it (commands, replay
/// headers, metrics.json): relative to `out_dir` when it lies inside it
/// (`build/libgather.so`), else its file name; never an absolute path.
std::string LibraryPathShown(const std::string& library, const std::string& out_dir);

/// Runs `run` with `seed` into `dir` (metrics.json, robots/<id>.log, with
/// `replay` also replay.bin); robot i runs libraries[i % size], named in the
/// replay and the metrics by shown_libraries (LibraryPathShown), joined by " + ". Hosts are
/// started by the calling thread, which must outlive the call (it does).
/// Stopped at run.time_limit_s of wall time (run_error says so). With
/// `message` (the assignment's format), the replay carries it in place of
/// the scenario's, and every payload each robot sets is checked against it
/// (RunOutcome::payload_violations); the run itself is unchanged.
RunOutcome RunScenario(const assignment::ScenarioRun& run, uint64_t seed, const std::vector<std::string>& libraries,
                       const std::vector<std::string>& shown_libraries, const std::string& dir, bool replay,
                       const lab::message::MessageFormat* message = nullptr);

/// Runs a search test (search_test.cpp) with `library` (named
/// `shown_library` in its replays and metrics) and scores `test`:
/// its one criterion, "search", full when no pattern broke the run. A
/// counterexample is written into `out_dir`/test.output_dir
/// (counterexample.yaml, replay, metrics.json) and test.replay_path names
/// its replay. A search stopped by its time limit sets test.run_error.
/// `fork_server`: the library loaded once, each robot a copy
/// (AppRequest::load_once); false: fresh hosts (GradeOptions::fork_server).
void RunSearchTest(const assignment::SearchTestSpec& spec, const std::string& library,
                   const std::string& shown_library, const std::string& out_dir, bool fork_server,
                   assignment::TestResult& test);

}  // namespace syrof::grader::internal
