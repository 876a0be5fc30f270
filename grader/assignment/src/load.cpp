// assignment.yaml: the top level, the scenario sets (each scenario loaded
// and validated), the assignment's goal checks against each scenario, and
// the rubric, whose points must add up to the total.
#include <cmath>
#include <filesystem>
#include <set>
#include <string_view>

#include "syrof/assignment/assignment.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/scenario/yaml/document.h"
#include "syrof/lab/search/search.h"

namespace syrof::grader::assignment {

const char* ToString(GradescopeVisibility visibility) {
  switch (visibility) {
    case GradescopeVisibility::kDefault: return "";
    case GradescopeVisibility::kVisible: return "visible";
    case GradescopeVisibility::kHidden: return "hidden";
    case GradescopeVisibility::kAfterDueDate: return "after_due_date";
    case GradescopeVisibility::kAfterPublished: return "after_published";
  }
  return "";
}
namespace {

using lab::scenario::CheckKeys;
using lab::scenario::Diagnostics;
using lab::scenario::ExpectList;
using lab::scenario::ExpectMap;
using lab::scenario::FailAt;
using lab::scenario::FormatNumber;
using lab::scenario::IndexPath;
using lab::scenario::JoinPath;
using lab::scenario::NumberRange;
using lab::scenario::ReadNumber;
using lab::scenario::ReadNumberAt;
using lab::scenario::ReadString;
using lab::scenario::ReadUnsigned64;
using lab::scenario::RequireKey;
using lab::scenario::YamlNode;

constexpr double kMaxPoints = 10000;
constexpr double kMaxTimeLimitS = 86400;

bool IsValidName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

// The loaded scenarios, kept to check the goal against them.
struct Context {
  std::string folder;
  const YamlNode* goal = nullptr;  // the assignment's goal:, if any
  const lab::message::MessageFormat* message = nullptr;  // the assignment's message:, if any
  std::set<std::string> names;
  bool skip_missing = false;       // reading the hidden sets with LoadOptions::allow_missing_hidden
  bool missing = false;            // a file was missing and skipped
};

// `gradescope:` on a scenario entry or a search test, if given.
bool ReadGradescopeVisibility(const YamlNode& node, const std::string& path, GradescopeVisibility& visibility,
                              Diagnostics& diagnostics) {
  const YamlNode* word = node.Find("gradescope");
  if (word == nullptr) return true;
  static constexpr GradescopeVisibility kWords[] = {GradescopeVisibility::kVisible, GradescopeVisibility::kHidden,
                                                    GradescopeVisibility::kAfterDueDate,
                                                    GradescopeVisibility::kAfterPublished};
  if (word->is_scalar() && !word->quoted) {
    for (const GradescopeVisibility candidate : kWords) {
      if (word->scalar == ToString(candidate)) {
        visibility = candidate;
        return true;
      }
    }
  }
  return FailAt(*word, JoinPath(path, "gradescope"),
                "expected Gradescope's visibility of the test: visible, hidden, after_due_date or after_published",
                diagnostics);
}

bool ReadRun(const YamlNode& node, const std::string& path, Context& context, ScenarioRun& run,
             std::optional<lab::Error>& scenario_error, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"file", "name", "seeds", "time_limit_s", "gradescope"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics) ||
      !RequireKey(node, path, "file", diagnostics) || !RequireKey(node, path, "seeds", diagnostics) ||
      !ReadString(*node.Find("file"), JoinPath(path, "file"), run.file, diagnostics)) {
    return false;
  }
  const YamlNode& file = *node.Find("file");
  if (run.file.empty() || std::filesystem::path(run.file).is_absolute()) {
    return FailAt(file, JoinPath(path, "file"),
                  "expected a scenario file's path relative to the assignment folder, got '" + run.file + "'",
                  diagnostics);
  }
  run.path = (std::filesystem::path(context.folder) / run.file).string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(run.path, error)) {
    if (context.skip_missing) {
      context.missing = true;
      return true;
    }
    return FailAt(file, JoinPath(path, "file"), "no such scenario file '" + run.file + "' (looked for " + run.path + ")",
                  diagnostics);
  }
  run.name = std::filesystem::path(run.file).stem().string();
  if (const YamlNode* name = node.Find("name")) {
    if (!ReadString(*name, JoinPath(path, "name"), run.name, diagnostics)) return false;
  }
  if (!IsValidName(run.name)) {
    const YamlNode& at = node.Find("name") ? *node.Find("name") : file;
    return FailAt(at, JoinPath(path, "name"),
                  "a run's name must be 1 to 64 letters, digits, '_', '-' or '.', got '" + run.name +
                      "' (give 'name' to choose one)",
                  diagnostics);
  }
  if (!context.names.insert(run.name).second) {
    const YamlNode& at = node.Find("name") ? *node.Find("name") : file;
    return FailAt(at, JoinPath(path, "name"),
                  "another scenario of the assignment is already named '" + run.name + "'", diagnostics);
  }
  const YamlNode& seeds = *node.Find("seeds");
  if (!ExpectList(seeds, JoinPath(path, "seeds"), diagnostics)) return false;
  if (seeds.values.empty() || seeds.values.size() > kMaxSeeds) {
    return FailAt(seeds, JoinPath(path, "seeds"),
                  "needs 1 to " + std::to_string(kMaxSeeds) + " seeds, got " + std::to_string(seeds.values.size()),
                  diagnostics);
  }
  std::set<uint64_t> seen;
  for (size_t i = 0; i < seeds.values.size(); ++i) {
    uint64_t seed = 0;
    if (!ReadUnsigned64(seeds.values[i], IndexPath(JoinPath(path, "seeds"), i), seed, diagnostics)) return false;
    if (!seen.insert(seed).second) {
      return FailAt(seeds.values[i], IndexPath(JoinPath(path, "seeds"), i),
                    "seed " + std::to_string(seed) + " is listed twice", diagnostics);
    }
    run.seeds.push_back(seed);
  }
  if (!ReadNumberAt(node, path, "time_limit_s", NumberRange{0, kMaxTimeLimitS, true}, run.time_limit_s, diagnostics) ||
      !ReadGradescopeVisibility(node, path, run.gradescope, diagnostics)) {
    return false;
  }
  // The scenario itself, with its own file and places in any error.
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(run.path);
  if (!loaded.ok()) {
    scenario_error = loaded.error;
    return false;
  }
  run.scenario_has_goal = !loaded.scenario->goal.empty();
  if (context.message != nullptr && loaded.scenario->message && *loaded.scenario->message != *context.message) {
    return FailAt(file, JoinPath(path, "file"),
                  "scenario '" + run.file + "' declares the message format " + loaded.scenario->message->ToString() +
                      ", but the assignment's is " + context.message->ToString(),
                  diagnostics);
  }
  if (context.goal != nullptr) {
    return lab::scenario::ReadGoalChecks(*context.goal, "goal", *loaded.scenario, run.goal, diagnostics);
  }
  return true;
}

// What a search test searches: `max_losses` (lost beacons) or
// `activations: ssync` (schedules, with `max_inactive` and `fair_within`)
// or `activations: async` (cycles, with `max_delay`, `min_move_m` and
// `max_deviations`), one of them, as `syrof search` takes them.
bool ReadSearchKind(const YamlNode& node, const std::string& path, SearchTestSpec& test, Diagnostics& diagnostics) {
  static constexpr const char* kSsyncKeys[] = {"max_inactive", "fair_within"};
  static constexpr const char* kAsyncKeys[] = {"max_delay", "min_move_m", "max_deviations"};
  const auto refuse = [&](const auto& keys, const char* only) {
    for (const char* key : keys) {
      if (const YamlNode* found = node.Find(key)) {
        FailAt(*found, JoinPath(path, key), std::string("applies to ") + only, diagnostics);
        return true;
      }
    }
    return false;
  };
  const YamlNode* model = node.Find("activations");
  if (model == nullptr) {
    if (refuse(kSsyncKeys, "a schedule search only ('activations: ssync')") ||
        refuse(kAsyncKeys, "an ASYNC schedule search only ('activations: async')")) {
      return false;
    }
    if (node.Find("max_losses") != nullptr) return true;
    return FailAt(node, path,
                  "missing required key '" + JoinPath(path, "max_losses") +
                      "' (or 'activations: ssync' or 'async' to search schedules)",
                  diagnostics);
  }
  const std::string at = JoinPath(path, "activations");
  if (!model->is_scalar() || model->quoted) {
    return FailAt(*model, at, "expected the activation model to search: ssync or async", diagnostics);
  }
  if (model->scalar != "ssync" && model->scalar != "async") {
    return FailAt(*model, at,
                  "unknown activation model '" + model->scalar + "'; a search test searches ssync or async",
                  diagnostics);
  }
  if (const YamlNode* losses = node.Find("max_losses")) {
    return FailAt(*losses, JoinPath(path, "max_losses"),
                  "a search test searches losses or schedules, one at a time: drop 'max_losses' or 'activations'",
                  diagnostics);
  }
  test.activations = true;
  test.async = model->scalar == "async";
  if (test.async ? refuse(kSsyncKeys, "an SSYNC schedule search only ('activations: ssync')")
                 : refuse(kAsyncKeys, "an ASYNC schedule search only ('activations: async')")) {
    return false;
  }
  return true;
}

// One entry of `search:`. A hidden entry whose file is missing (a
// student's copy) is skipped when context.skip_missing.
bool ReadSearchTest(const YamlNode& node, const std::string& path, Context& context, SearchTestSpec& test,
                    bool& skipped, std::optional<lab::Error>& scenario_error, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {
      "scenario",  "name",       "max_losses",     "activations", "max_inactive", "fair_within",  "max_delay",
      "min_move_m", "max_deviations", "epochs", "points",      "hidden",       "time_limit_s", "gradescope"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics) ||
      !RequireKey(node, path, "scenario", diagnostics) || !ReadSearchKind(node, path, test, diagnostics) ||
      !RequireKey(node, path, "points", diagnostics) ||
      !ReadString(*node.Find("scenario"), JoinPath(path, "scenario"), test.file, diagnostics)) {
    return false;
  }
  if (const YamlNode* hidden = node.Find("hidden")) {
    if (!hidden->is_scalar() || hidden->quoted || (hidden->scalar != "true" && hidden->scalar != "false")) {
      return FailAt(*hidden, JoinPath(path, "hidden"), "expected true or false", diagnostics);
    }
    test.visibility = hidden->scalar == "true" ? Visibility::kHidden : Visibility::kPublic;
  }
  if (!ReadGradescopeVisibility(node, path, test.gradescope, diagnostics)) return false;
  const YamlNode& file = *node.Find("scenario");
  if (test.file.empty() || std::filesystem::path(test.file).is_absolute()) {
    return FailAt(file, JoinPath(path, "scenario"),
                  "expected a scenario file's path relative to the assignment folder, got '" + test.file + "'",
                  diagnostics);
  }
  test.path = (std::filesystem::path(context.folder) / test.file).string();
  std::error_code error;
  if (!std::filesystem::is_regular_file(test.path, error)) {
    if (test.visibility == Visibility::kHidden && context.skip_missing) {
      skipped = true;
      return true;
    }
    return FailAt(file, JoinPath(path, "scenario"),
                  "no such scenario file '" + test.file + "' (looked for " + test.path + ")", diagnostics);
  }
  test.name = std::filesystem::path(test.file).stem().string();
  if (const YamlNode* name = node.Find("name")) {
    if (!ReadString(*name, JoinPath(path, "name"), test.name, diagnostics)) return false;
  }
  const YamlNode& name_at = node.Find("name") ? *node.Find("name") : file;
  if (!IsValidName(test.name)) {
    return FailAt(name_at, JoinPath(path, "name"),
                  "a search test's name must be 1 to 64 letters, digits, '_', '-' or '.', got '" + test.name +
                      "' (give 'name' to choose one)",
                  diagnostics);
  }
  if (!context.names.insert("search/" + test.name).second) {
    return FailAt(name_at, JoinPath(path, "name"), "another search test is already named '" + test.name + "'",
                  diagnostics);
  }
  int64_t max_losses = 0;
  int64_t epochs = test.epochs;
  int64_t max_inactive = 0;
  int64_t fair_within = 0;
  int64_t max_delay = 0;
  int64_t max_deviations = 0;
  if (!lab::scenario::ReadIntegerAt(node, path, "max_losses", 0, lab::search::kMaxSearchLosses, max_losses,
                                    diagnostics) ||
      !lab::scenario::ReadIntegerAt(node, path, "epochs", 1, lab::search::kMaxSearchEpochs, epochs, diagnostics) ||
      !lab::scenario::ReadIntegerAt(node, path, "max_inactive", 1, lab::search::kMaxSearchInactive, max_inactive,
                                    diagnostics) ||
      !lab::scenario::ReadIntegerAt(node, path, "fair_within", 1, lab::search::kMaxSearchEpochs, fair_within,
                                    diagnostics) ||
      !lab::scenario::ReadIntegerAt(node, path, "max_delay", 1, sync::kMaxAsyncDelayEpochs, max_delay, diagnostics) ||
      !lab::scenario::ReadIntegerAt(node, path, "max_deviations", 1, lab::search::kMaxSearchDeviations,
                                    max_deviations, diagnostics) ||
      (node.Find("min_move_m") != nullptr &&
       !ReadNumberAt(node, path, "min_move_m", NumberRange{0, 30, true}, test.min_move_m, diagnostics)) ||
      !ReadNumberAt(node, path, "points", NumberRange{0, kMaxPoints, true}, test.points, diagnostics) ||
      !ReadNumberAt(node, path, "time_limit_s", NumberRange{0, kMaxTimeLimitS, true}, test.time_limit_s,
                    diagnostics)) {
    return false;
  }
  if (fair_within > epochs) {
    // As `syrof search --fair-within`: a bound above the window is no bound.
    return FailAt(*node.Find("fair_within"), JoinPath(path, "fair_within"),
                  "must be at most the " + std::to_string(epochs) + " epochs searched ('epochs'), got " +
                      std::to_string(fair_within),
                  diagnostics);
  }
  test.max_losses = static_cast<int>(max_losses);
  test.epochs = static_cast<int>(epochs);
  test.max_inactive = static_cast<int>(max_inactive);
  test.fair_within = static_cast<int>(fair_within);
  test.max_delay = static_cast<int>(max_delay);
  test.max_deviations = static_cast<int>(max_deviations);
  const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(test.path);
  if (!loaded.ok()) {
    scenario_error = loaded.error;
    return false;
  }
  if (test.async && test.max_delay == 0 && loaded.scenario->activation.model != sync::ActivationModel::kAsync) {
    // As `syrof search --activations async`: the delay bound is the
    // scenario's only when the scenario is ASYNC.
    return FailAt(*node.Find("activations"), JoinPath(path, "activations"),
                  "an ASYNC search needs a delay bound: give 'max_delay' (1 .. " +
                      std::to_string(sync::kMaxAsyncDelayEpochs) + " epochs), or search a scenario whose activation "
                      "is async (" + test.file + " is " + sync::ToString(loaded.scenario->activation.model) + ")",
                  diagnostics);
  }
  return true;
}

bool ReadSearchTests(const YamlNode& node, double total, bool allow_missing_hidden, Context& context,
                     std::vector<SearchTestSpec>& tests, std::optional<lab::Error>& scenario_error,
                     Diagnostics& diagnostics) {
  if (!ExpectList(node, "search", diagnostics)) return false;
  if (node.values.empty() || node.values.size() > kMaxSearchTests) {
    return FailAt(node, "search",
                  "needs 1 to " + std::to_string(kMaxSearchTests) + " search tests, got " +
                      std::to_string(node.values.size()),
                  diagnostics);
  }
  context.skip_missing = allow_missing_hidden;
  double points = 0;
  for (size_t i = 0; i < node.values.size(); ++i) {
    SearchTestSpec test;
    bool skipped = false;
    if (!ReadSearchTest(node.values[i], IndexPath("search", i), context, test, skipped, scenario_error,
                        diagnostics)) {
      return false;
    }
    points += test.points;
    if (!skipped) tests.push_back(std::move(test));
  }
  context.skip_missing = false;
  if (points >= total) {
    return FailAt(node, "search",
                  "the search tests' points add up to " + FormatNumber(points) +
                      ", which leaves nothing for the runs: they must be less than the assignment's 'points' (" +
                      FormatNumber(total) + ")",
                  diagnostics);
  }
  return true;
}

bool ReadSet(const YamlNode& node, const std::string& path, Context& context, std::vector<ScenarioRun>& runs,
             std::optional<lab::Error>& scenario_error, Diagnostics& diagnostics) {
  if (!ExpectList(node, path, diagnostics)) return false;
  if (node.values.empty() || node.values.size() > kMaxScenariosPerSet) {
    return FailAt(node, path,
                  "needs 1 to " + std::to_string(kMaxScenariosPerSet) + " scenarios, got " +
                      std::to_string(node.values.size()),
                  diagnostics);
  }
  runs.resize(node.values.size());
  for (size_t i = 0; i < runs.size(); ++i) {
    if (!ReadRun(node.values[i], IndexPath(path, i), context, runs[i], scenario_error, diagnostics)) return false;
  }
  return true;
}

// A criterion: a number (its points) or a map with `points` and its own keys.
bool ReadPoints(const YamlNode& node, const std::string& path, std::span<const std::string_view> keys, double& points,
                Diagnostics& diagnostics) {
  const NumberRange range{0, kMaxPoints};
  if (node.is_scalar()) return ReadNumber(node, path, range, points, diagnostics);
  if (!node.is_map()) {
    return FailAt(node, path, "expected a number of points, or a map with 'points' and the criterion's keys",
                  diagnostics);
  }
  return CheckKeys(node, path, keys, diagnostics) && RequireKey(node, path, "points", diagnostics) &&
         ReadNumberAt(node, path, "points", range, points, diagnostics);
}

bool ReadRubric(const YamlNode& node, const std::string& path, double total, Rubric& rubric,
                Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"goal",   "collisions",       "safety", "synchrony",
                                               "common_knowledge", "agreement", "faults"};
  if (!ExpectMap(node, path, diagnostics) || !CheckKeys(node, path, kKeys, diagnostics)) return false;
  const NumberRange penalty{0, kMaxPoints};
  double sum = 0;
  for (size_t i = 0; i < node.keys.size(); ++i) {
    const std::string& key = node.keys[i].scalar;
    const YamlNode& value = node.values[i];
    const std::string at = JoinPath(path, key);
    double points = 0;
    if (key == "goal") {
      static constexpr std::string_view kGoal[] = {"points", "per_check"};
      GoalCriterion criterion;
      if (!ReadPoints(value, at, kGoal, points, diagnostics)) return false;
      criterion.points = points;
      if (const YamlNode* per_check = value.is_map() ? value.Find("per_check") : nullptr) {
        static constexpr std::string_view kBool[] = {"false", "true"};
        size_t index = 0;
        if (!lab::scenario::ReadChoice(*per_check, JoinPath(at, "per_check"), kBool, index, diagnostics)) return false;
        criterion.per_check = index == 1;
      }
      rubric.goal = criterion;
    } else if (key == "collisions") {
      static constexpr std::string_view kCollisions[] = {"points", "per_collision", "per_wall_contact"};
      CollisionCriterion criterion;
      if (!ReadPoints(value, at, kCollisions, points, diagnostics)) return false;
      criterion.points = points;
      criterion.per_collision = points;
      if (value.is_map() && (!ReadNumberAt(value, at, "per_collision", penalty, criterion.per_collision, diagnostics) ||
                             !ReadNumberAt(value, at, "per_wall_contact", penalty, criterion.per_wall_contact,
                                           diagnostics))) {
        return false;
      }
      rubric.collisions = criterion;
    } else if (key == "safety") {
      static constexpr std::string_view kSafety[] = {"points", "per_intervention"};
      SafetyCriterion criterion;
      if (!ReadPoints(value, at, kSafety, points, diagnostics)) return false;
      criterion.points = points;
      if (value.is_map() &&
          !ReadNumberAt(value, at, "per_intervention", penalty, criterion.per_intervention, diagnostics)) {
        return false;
      }
      rubric.safety = criterion;
    } else if (key == "synchrony") {
      static constexpr std::string_view kSynchrony[] = {"points", "max_skew_rounds"};
      SynchronyCriterion criterion;
      if (!ReadPoints(value, at, kSynchrony, points, diagnostics)) return false;
      criterion.points = points;
      if (value.is_map() && !lab::scenario::ReadIntegerAt(value, at, "max_skew_rounds", 0, 1000000,
                                                          criterion.max_skew_rounds, diagnostics)) {
        return false;
      }
      rubric.synchrony = criterion;
    } else if (key == "common_knowledge") {
      static constexpr std::string_view kKnowledge[] = {"points"};
      if (!ReadPoints(value, at, kKnowledge, points, diagnostics)) return false;
      rubric.common_knowledge = CommonKnowledgeCriterion{points};
    } else if (key == "agreement") {
      static constexpr std::string_view kAgreement[] = {"points", "min_fraction"};
      AgreementCriterion criterion;
      if (!ReadPoints(value, at, kAgreement, points, diagnostics)) return false;
      criterion.points = points;
      if (value.is_map() &&
          !ReadNumberAt(value, at, "min_fraction", NumberRange{0, 1}, criterion.min_fraction, diagnostics)) {
        return false;
      }
      rubric.agreement = criterion;
    } else {  // faults
      static constexpr std::string_view kFaults[] = {"points", "per_fault", "per_invalid_command",
                                                     "per_refused_payload"};
      FaultCriterion criterion;
      if (!ReadPoints(value, at, kFaults, points, diagnostics)) return false;
      criterion.points = points;
      criterion.per_fault = points;
      if (value.is_map() &&
          (!ReadNumberAt(value, at, "per_fault", penalty, criterion.per_fault, diagnostics) ||
           !ReadNumberAt(value, at, "per_invalid_command", penalty, criterion.per_invalid_command, diagnostics) ||
           !ReadNumberAt(value, at, "per_refused_payload", penalty, criterion.per_refused_payload, diagnostics))) {
        return false;
      }
      rubric.faults = criterion;
    }
    sum += points;
  }
  if (std::abs(sum - total) > 1e-9 * std::max(1.0, total)) {
    return FailAt(node, path,
                  "the criteria's points add up to " + FormatNumber(sum) + ", but the assignment's 'points' is " +
                      FormatNumber(total),
                  diagnostics);
  }
  return true;
}

bool ReadAssignment(const YamlNode& root, bool allow_missing_hidden, Assignment& assignment,
                    std::optional<lab::Error>& scenario_error, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"title",   "points",  "scenarios", "goal",
                                               "rubric",  "mixable", "message",   "search",
                                               "hidden_feedback_submissions"};
  if (root.is_null()) return diagnostics.Fail(0, 0, "the assignment is empty; it needs 'title', 'scenarios' and 'rubric'");
  if (!root.is_map()) return diagnostics.Fail(root.line, root.column, "the top level must be a map of keys (title, scenarios, rubric, ...)");
  if (!CheckKeys(root, "", kKeys, diagnostics) || !RequireKey(root, "", "title", diagnostics) ||
      !RequireKey(root, "", "scenarios", diagnostics) || !RequireKey(root, "", "rubric", diagnostics) ||
      !ReadString(*root.Find("title"), "title", assignment.title, diagnostics) ||
      !ReadNumberAt(root, "", "points", NumberRange{0, kMaxPoints, true}, assignment.points, diagnostics)) {
    return false;
  }
  if (assignment.title.empty()) return FailAt(*root.Find("title"), "title", "must not be empty", diagnostics);
  int64_t feedback = 0;
  if (!lab::scenario::ReadIntegerAt(root, "", "hidden_feedback_submissions", 0, 100000, feedback, diagnostics)) {
    return false;
  }
  assignment.hidden_feedback_submissions = static_cast<int>(feedback);
  if (const YamlNode* mixable = root.Find("mixable")) {
    if (!mixable->is_scalar() || mixable->quoted || (mixable->scalar != "true" && mixable->scalar != "false")) {
      return FailAt(*mixable, "mixable", "expected true or false", diagnostics);
    }
    assignment.mixable = mixable->scalar == "true";
  }
  if (const YamlNode* message = root.Find("message")) {
    lab::message::MessageFormat format;
    if (!lab::scenario::ReadMessageFormat(*message, "message", format, diagnostics)) return false;
    assignment.message = std::move(format);
  } else if (assignment.mixable) {
    return FailAt(*root.Find("mixable"), "mixable",
                  "a mixable assignment must declare its robots' message format: add 'message: none' or "
                  "'message: { length: ..., fields: [...] }'",
                  diagnostics);
  }
  Context context;
  context.folder = assignment.folder;
  context.goal = root.Find("goal");
  if (assignment.message) context.message = &*assignment.message;
  const YamlNode& sets = *root.Find("scenarios");
  static constexpr std::string_view kSets[] = {"public", "hidden"};
  if (!ExpectMap(sets, "scenarios", diagnostics) || !CheckKeys(sets, "scenarios", kSets, diagnostics) ||
      !RequireKey(sets, "scenarios", "public", diagnostics) ||
      !ReadSet(*sets.Find("public"), "scenarios.public", context, assignment.public_runs, scenario_error,
               diagnostics)) {
    return false;
  }
  if (const YamlNode* hidden = sets.Find("hidden")) {
    context.skip_missing = allow_missing_hidden;
    if (!ReadSet(*hidden, "scenarios.hidden", context, assignment.hidden_runs, scenario_error, diagnostics)) {
      return false;
    }
    if (context.missing) {
      assignment.hidden_runs.clear();
      assignment.hidden_missing = true;
    }
  }
  context.skip_missing = false;
  if (const YamlNode* search = root.Find("search")) {
    if (!ReadSearchTests(*search, assignment.points, allow_missing_hidden, context, assignment.search_tests,
                         scenario_error, diagnostics)) {
      return false;
    }
  }
  if (!ReadRubric(*root.Find("rubric"), "rubric", assignment.points, assignment.rubric, diagnostics)) return false;
  if (assignment.rubric.goal && context.goal == nullptr) {
    // A student's library has no built-in goal checker: every scenario must
    // say what its goal is.
    for (const auto* runs : {&assignment.public_runs, &assignment.hidden_runs}) {
      for (const ScenarioRun& run : *runs) {
        if (run.scenario_has_goal) continue;
        return FailAt(*root.Find("rubric")->Find("goal"), "rubric.goal",
                      "scenario '" + run.file + "' declares no 'goal:' and the assignment has none, so a student's "
                      "app could not be judged; add 'goal:' to the assignment or to the scenario",
                      diagnostics);
      }
    }
  }
  return true;
}

}  // namespace

double RunPoints(const Assignment& assignment, bool with_hidden) {
  double points = assignment.points;
  for (const SearchTestSpec& test : assignment.search_tests) {
    if (with_hidden || test.visibility == Visibility::kPublic) points -= test.points;
  }
  return points;
}

LoadResult LoadAssignmentFile(const std::string& path, const LoadOptions& options) {
  std::string file = path;
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) file = (std::filesystem::path(path) / "assignment.yaml").string();
  Diagnostics diagnostics(file);
  LoadResult result;
  lab::scenario::YamlNode root;
  Assignment assignment;
  assignment.folder = std::filesystem::path(file).parent_path().string();
  assignment.name = std::filesystem::absolute(std::filesystem::path(file)).parent_path().filename().string();
  std::optional<lab::Error> scenario_error;
  if (!lab::scenario::ReadYamlFile(file, root, diagnostics) ||
      !ReadAssignment(root, options.allow_missing_hidden, assignment, scenario_error, diagnostics)) {
    result.error = scenario_error ? scenario_error : diagnostics.error();
    return result;
  }
  result.assignment = std::move(assignment);
  return result;
}

}  // namespace syrof::grader::assignment
