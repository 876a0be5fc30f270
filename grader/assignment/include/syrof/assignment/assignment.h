// An assignment, as data: `assignments/<name>/assignment.yaml` read,
// validated and resolved (docs/grading.md, "The assignment file"). The
// grader runs every scenario of a set with every seed of it and scores each
// run with the rubric (score.h).
//
// The file is untrusted text held to the scenario files' standard: the same
// YAML reader (syrof/lab/scenario/yaml/), errors as file:line:column with
// the key path and the nearest valid key, and every scenario it names loaded
// and validated (its own errors keep its own file and place).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"
#include "syrof/lab/goals/goals.h"
#include "syrof/lab/message/message_format.h"

namespace syrof::grader::assignment {

/// Whether students see a set: public sets are in their folder, hidden sets
/// only the grader has.
enum class Visibility : uint8_t { kPublic = 0, kHidden = 1 };

/// When students see a test's result on Gradescope (results.json's
/// per-test `visibility`); `gradescope:` on a scenario entry or a search
/// test. kDefault: kVisible for a public set's test, kAfterDueDate for a
/// hidden set's.
enum class GradescopeVisibility : uint8_t { kDefault = 0, kVisible, kHidden, kAfterDueDate, kAfterPublished };

/// The `gradescope:` word of `visibility` ("" for kDefault).
const char* ToString(GradescopeVisibility visibility);

/// One scenario of a set, with the seeds it runs.
struct ScenarioRun {
  std::string name;               ///< `name`, default the file's stem
  std::string file;               ///< as written, relative to the assignment folder
  std::string path;               ///< resolved: assignment folder / file
  std::vector<uint64_t> seeds;    ///< each seed is one graded run, in file order
  double time_limit_s = 60;       ///< wall time for one run (the grader's limit, not simulated time)
  /// The assignment's `goal:` resolved against this scenario; empty when the
  /// assignment declares none (the scenario's own `goal:` is then used).
  std::vector<lab::goals::GoalCheck> goal;
  bool scenario_has_goal = false; ///< the scenario file declares `goal:` itself
  GradescopeVisibility gradescope = GradescopeVisibility::kDefault;  ///< `gradescope:`
};

/// A search test (docs/grading.md, "Search tests"): the submission run
/// under every pattern of up to `max_losses` lost beacons in the first
/// `epochs` epochs of a scenario (lab/search, `syrof search`), or, with
/// `activations: ssync`, under every SSYNC schedule of those epochs
/// (`syrof search --activations ssync`, docs/activation.md). It earns all
/// its points when no pattern breaks the run, none when one does.
struct SearchTestSpec {
  std::string name;               ///< `name`, default the file's stem; unique among the assignment's tests
  std::string file;               ///< `scenario:` as written, relative to the assignment folder
  std::string path;               ///< resolved: assignment folder / file
  int max_losses = 1;             ///< F (a loss search)
  /// `activations: ssync` or `async`: search schedules instead of losses
  /// (lab::search::SearchOptions::activations); `max_losses` is then absent.
  bool activations = false;
  bool async = false;             ///< `activations: async`: ASYNC cycles, not SSYNC's active subsets
  int max_inactive = 0;           ///< SSYNC `max_inactive`: most robot-epochs a schedule leaves out; 0: every schedule
  int fair_within = 0;            ///< SSYNC `fair_within`: no robot left out of this many epochs in a row; 0: no bound
  int max_delay = 0;              ///< ASYNC `max_delay`: the delay bound D; 0: the scenario's max_delay_epochs
  double min_move_m = -1;         ///< ASYNC `min_move_m`: cut moves at this; < 0: the scenario's (rigid unless ASYNC)
  int max_deviations = 0;         ///< ASYNC `max_deviations`: most deviating cycles; 0: every schedule
  int epochs = 2;                 ///< E
  double points = 0;              ///< taken from the assignment's points; the runs share the rest
  double time_limit_s = 300;      ///< wall time for the whole search (the grader's limit)
  Visibility visibility = Visibility::kPublic;  ///< `hidden: true`: only the grader has the file
  GradescopeVisibility gradescope = GradescopeVisibility::kDefault;  ///< `gradescope:`
};

/// Points for a criterion; every criterion is optional (absent: not scored).
/// The scoring rules are docs/grading.md's ("Scoring one run").
struct GoalCriterion {
  double points = 0;
  bool per_check = true;  ///< points shared among the checks; false: all or nothing
};
struct CollisionCriterion {
  double points = 0;
  double per_collision = 0;     ///< lost per body-body collision (default: all the points)
  double per_wall_contact = 0;  ///< lost per wall contact
};
struct SafetyCriterion {
  double points = 0;
  double per_intervention = 0;  ///< lost per safety-filter intervention
};
struct SynchronyCriterion {
  double points = 0;
  int64_t max_skew_rounds = 2;  ///< full points when every epoch's start skew is at most this
};
struct CommonKnowledgeCriterion {
  double points = 0;            ///< full points without a P3 violation
};
struct AgreementCriterion {
  double points = 0;
  double min_fraction = 1.0;    ///< full points at or above this agreed fraction, else points x fraction
};
struct FaultCriterion {
  double points = 0;
  double per_fault = 0;             ///< lost per robot whose app faulted (default: all the points)
  double per_invalid_command = 0;   ///< lost per refused command
  double per_refused_payload = 0;   ///< lost per refused sendMessageData
};

struct Rubric {
  std::optional<GoalCriterion> goal;
  std::optional<CollisionCriterion> collisions;
  std::optional<SafetyCriterion> safety;
  std::optional<SynchronyCriterion> synchrony;
  std::optional<CommonKnowledgeCriterion> common_knowledge;
  std::optional<AgreementCriterion> agreement;
  std::optional<FaultCriterion> faults;
};

struct Assignment {
  std::string name;    ///< the folder's name
  std::string folder;  ///< where assignment.yaml is
  std::string title;
  double points = 100;  ///< the rubric's criteria add up to this
  std::vector<ScenarioRun> public_runs;
  std::vector<ScenarioRun> hidden_runs;
  Rubric rubric;
  /// `mixable: true`: the README specifies the robots' message format, so
  /// robots of different submissions can share a swarm (`syrof grade --mix`).
  bool mixable = false;
  /// `message:`: the payload's wire format, which the README states in
  /// prose; absent when the file declares none. A mixable assignment must
  /// declare it (`none` when the robots send nothing): `syrof grade --mix`
  /// checks every payload against it and names the side that broke it.
  std::optional<lab::message::MessageFormat> message;
  /// `search:`: search tests, after the runs. Their points add up to less
  /// than `points`; every run shares what is left.
  std::vector<SearchTestSpec> search_tests;
  /// `hidden_feedback_submissions: N`: on Gradescope, a student's first N
  /// submissions see the hidden tests' results as their `gradescope:` says;
  /// from the (N+1)-th on, a hidden test that would be `visible` shows only
  /// after the due date (fewer chances to probe the hidden tests). 0: no cap.
  int hidden_feedback_submissions = 0;
  /// Loaded with LoadOptions::allow_missing_hidden and a hidden scenario file
  /// was missing: hidden_runs is empty and only the public sets can be graded.
  bool hidden_missing = false;
};

/// How to load an assignment.
struct LoadOptions {
  /// A student's copy has no hidden scenario files. With this set, a hidden
  /// entry whose file is missing is no error: the hidden sets are dropped
  /// and Assignment::hidden_missing says so. Every other error still fails.
  bool allow_missing_hidden = false;
};

/// Either an assignment or the first error found (in assignment.yaml, or in
/// a scenario it names, with that file's place).
struct LoadResult {
  std::optional<Assignment> assignment;
  std::optional<lab::Error> error;
  bool ok() const { return assignment.has_value(); }
};

/// Reads `path` (an assignment.yaml; or a folder holding one).
LoadResult LoadAssignmentFile(const std::string& path, const LoadOptions& options = {});

/// Most seeds in one set entry, and most scenarios in one set.
inline constexpr size_t kMaxSeeds = 1000;
inline constexpr size_t kMaxScenariosPerSet = 100;
/// Most search tests an assignment declares.
inline constexpr size_t kMaxSearchTests = 20;

/// The points the runs share: the assignment's, less those of the search
/// tests graded (`with_hidden`: the hidden ones too).
double RunPoints(const Assignment& assignment, bool with_hidden);

}  // namespace syrof::grader::assignment
