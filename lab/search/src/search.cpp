#include "syrof/lab/search/search.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <thread>
#include <unordered_set>

#include "syrof/base/check.h"
#include "syrof/base/state_digest.h"
#include "syrof/lab/replay/epoch_table.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::search {
namespace {

using world::LostBeacon;

// The loss-free run's replay, read into its epoch table; the rounds the
// losses fall in: up to the first start of the `epochs`-th epoch after the
// first (0-based row `epochs`), or the whole run when it has no such row.
struct Window {
  int64_t rounds = 0;
  int64_t epochs = 0;
  std::vector<WindowEpoch> rows;  // the window's epochs (the activation search's slots)
};

// An epoch row as an activation search's window holds it: the earliest
// start, and the members of every robot's map that started it.
WindowEpoch WindowEpochOf(const replay::EpochRow& row, const std::vector<uint16_t>& robot_ids) {
  WindowEpoch epoch;
  epoch.epoch = row.wire_epoch();
  epoch.round = -1;
  for (size_t i = 0; i < row.robots.size(); ++i) {
    const replay::EpochStart& start = row.robots[i];
    if (!start.started()) continue;
    if (epoch.round < 0 || start.round < epoch.round) epoch.round = start.round;
    if (start.members) {
      epoch.members.insert(epoch.members.end(), start.members->begin(), start.members->end());
    } else {
      epoch.members.push_back(robot_ids[i]);
    }
  }
  std::sort(epoch.members.begin(), epoch.members.end());
  epoch.members.erase(std::unique(epoch.members.begin(), epoch.members.end()), epoch.members.end());
  return epoch;
}

Window WindowOf(const std::string& replay_bytes, int64_t run_rounds, int epochs) {
  std::istringstream in(replay_bytes);
  replay::Reader reader(in);
  replay::Header header;
  Window window{run_rounds, 0, {}};
  if (!reader.ReadHeader(header)) return window;
  replay::EpochTableBuilder builder(header, reader.version());
  replay::Round round;
  while (reader.Next(round)) builder.Add(round);
  const replay::EpochTable table = std::move(builder).Finish();
  window.epochs = static_cast<int64_t>(table.epochs.size());
  for (size_t row = 0; row < table.epochs.size() && row < static_cast<size_t>(epochs); ++row) {
    window.rows.push_back(WindowEpochOf(table.epochs[row], table.robot_ids));
  }
  if (table.epochs.size() <= static_cast<size_t>(epochs)) return window;
  window.epochs = epochs;
  int64_t first_start = run_rounds;
  for (const replay::EpochStart& start : table.epochs[static_cast<size_t>(epochs)].robots) {
    if (start.started()) first_start = std::min<int64_t>(first_start, start.round);
  }
  window.rounds = first_start;
  return window;
}

// Whether robot `id` runs (and sends, or hears, as `sending` says) at
// `time_s` by the scenario's faults. A loss of a beacon never sent or never
// heard repeats a shorter pattern.
bool Active(const scenario::Scenario& scenario, uint16_t id, double time_s, bool sending) {
  bool running = scenario.robots[id].present_at_start;
  for (const scenario::FaultSpec& fault : scenario.faults) {
    if (fault.robot != id) continue;
    switch (fault.kind) {
      case scenario::FaultKind::kJoin:
        if (time_s >= fault.at_s) running = true;
        break;
      case scenario::FaultKind::kCrash:
        if (time_s >= fault.at_s) return false;
        break;
      case scenario::FaultKind::kPause:
        if (time_s >= fault.at_s && time_s < fault.until_s) return false;
        break;
      case scenario::FaultKind::kDeaf:
        if (!sending && time_s >= fault.at_s && time_s < fault.until_s) return false;
        break;
      case scenario::FaultKind::kMute:
        if (sending && time_s >= fault.at_s && time_s < fault.until_s) return false;
        break;
    }
  }
  return running;
}

std::vector<LostBeacon> SlotsOf(const scenario::Scenario& scenario, int64_t window_rounds) {
  const auto robots = static_cast<uint16_t>(scenario.robots.size());
  world::Channel channel(WithLosses(scenario, {}).channel, robots, scenario.seed);
  std::vector<LostBeacon> slots;
  for (int64_t round = 0; round < window_rounds; ++round) {
    const double time_s = static_cast<double>(round) * scenario.timing.radio_round_s;
    for (uint16_t from = 0; from < robots; ++from) {
      if (!Active(scenario, from, time_s, /*sending=*/true)) continue;
      for (uint16_t to = 0; to < robots; ++to) {
        if (to == from || !Active(scenario, to, time_s, /*sending=*/false)) continue;
        if (!channel.Delivers(from, to, round, time_s)) continue;
        slots.push_back({round, from, to});
      }
    }
  }
  return slots;
}

// Combinations of `k` of `n` slots in lexicographic order of their indices.
class Patterns {
 public:
  Patterns(int64_t n, int k) : n_(n), indices_(static_cast<size_t>(k)) {
    for (int i = 0; i < k; ++i) indices_[static_cast<size_t>(i)] = i;
    done_ = k > n;
  }
  bool done() const { return done_; }
  const std::vector<int64_t>& current() const { return indices_; }
  void Advance() {
    const int k = static_cast<int>(indices_.size());
    int i = k - 1;
    while (i >= 0 && indices_[static_cast<size_t>(i)] == n_ - k + i) --i;
    if (i < 0) {
      done_ = true;
      return;
    }
    ++indices_[static_cast<size_t>(i)];
    for (int j = i + 1; j < k; ++j) indices_[static_cast<size_t>(j)] = indices_[static_cast<size_t>(j - 1)] + 1;
  }

 private:
  int64_t n_;
  std::vector<int64_t> indices_;
  bool done_ = false;
};

// What a search's patterns choose from: beacons to lose, or members of the
// window's epochs to leave out (search.h). Slots are in round order.
struct SearchSpace {
  bool activations = false;
  std::vector<LostBeacon> beacons;
  std::vector<Inactivation> inactivations;
  std::vector<size_t> epoch_of;  // per inactivation slot: its index in `epochs`
  std::vector<WindowEpoch> epochs;
  int fair_within = 0;
  // ASYNC: the patterns are cycle timings (AsyncSchedules), under these bounds.
  bool async = false;
  int max_delay_epochs = 0;
  double min_move_m = 0;

  int64_t size() const { return static_cast<int64_t>(activations ? inactivations.size() : beacons.size()); }
  int64_t RoundOf(int64_t slot) const {
    const auto i = static_cast<size_t>(slot);
    return activations ? inactivations[i].round : beacons[i].round;
  }
};

std::vector<Inactivation> InactivationSlots(const std::vector<WindowEpoch>& epochs, std::vector<size_t>& epoch_of) {
  std::vector<Inactivation> slots;
  for (size_t e = 0; e < epochs.size(); ++e) {
    for (const uint16_t robot : epochs[e].members) {
      slots.push_back({epochs[e].round, epochs[e].epoch, robot});
      epoch_of.push_back(e);
    }
  }
  return slots;
}

// Whether no robot is left out of `fair_within` of the window's epochs in
// a row (a robot that is not a member of an epoch ends its run).
bool IsFair(const SearchSpace& space, std::span<const int64_t> indices) {
  std::vector<int> runs;  // per robot id: inactive epochs in a row so far
  for (const WindowEpoch& epoch : space.epochs) {
    if (!epoch.members.empty()) runs.resize(std::max<size_t>(runs.size(), epoch.members.back() + 1u), 0);
  }
  for (size_t e = 0; e < space.epochs.size(); ++e) {
    std::vector<int> after(runs.size(), 0);
    for (const uint16_t robot : space.epochs[e].members) {
      const bool left_out = std::any_of(indices.begin(), indices.end(), [&](int64_t index) {
        const auto slot = static_cast<size_t>(index);
        return space.epoch_of[slot] == e && space.inactivations[slot].robot == robot;
      });
      after[robot] = left_out ? runs[robot] + 1 : 0;
      if (after[robot] >= space.fair_within) return false;
    }
    runs = std::move(after);
  }
  return true;
}

// Whether an activation pattern is a schedule: every epoch keeps an active
// member, and no robot is inactive in fair_within epochs in a row.
bool IsSchedule(const SearchSpace& space, std::span<const int64_t> indices) {
  size_t i = 0;
  while (i < indices.size()) {
    const size_t epoch = space.epoch_of[static_cast<size_t>(indices[i])];
    size_t left_out = 0;
    for (; i < indices.size() && space.epoch_of[static_cast<size_t>(indices[i])] == epoch; ++i) ++left_out;
    if (left_out >= space.epochs[epoch].members.size()) return false;
  }
  return space.fair_within <= 0 || IsFair(space, indices);
}

// The schedules of up to `most` inactive robot-epochs (no fairness bound):
// the product over epochs of sum_j C(m, j), j < m, truncated at `most`.
int64_t ScheduleCount(const std::vector<WindowEpoch>& epochs, int most) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  auto add = [&](int64_t a, int64_t b) { return a > kMax - b ? kMax : a + b; };
  auto times = [&](int64_t a, int64_t b) {
    if (a == 0 || b == 0) return int64_t{0};
    return a > kMax / b ? kMax : a * b;
  };
  std::vector<int64_t> ways(static_cast<size_t>(most) + 1, 0);  // [k]: schedules with k left out
  ways[0] = 1;
  for (const WindowEpoch& epoch : epochs) {
    const auto m = static_cast<int>(epoch.members.size());
    std::vector<int64_t> next(ways.size(), 0);
    int64_t choose = 1;  // C(m, j)
    for (int j = 0; j < m && j <= most; ++j) {
      if (j > 0) choose = times(choose, m - j + 1) == kMax ? kMax : choose * (m - j + 1) / j;
      for (int k = 0; k + j <= most; ++k) {
        next[static_cast<size_t>(k + j)] = add(next[static_cast<size_t>(k + j)], times(ways[static_cast<size_t>(k)], choose));
      }
    }
    ways = std::move(next);
  }
  int64_t total = 0;
  for (const int64_t count : ways) total = add(total, count);
  return total;
}

// ASYNC: the schedules of exactly k deviating cycles in the window, in
// search order (search.h). A robot looks at each epoch start of the window
// it makes (a member of the epoch's row) unless its cycle still holds it;
// the walk goes look by look in (epoch, robot) order, trying each
// deviating choice before FSYNC's one-epoch cycle, so the patterns come
// earliest deviation first. Each robot's looks follow its own cycles only.
class AsyncSchedules {
 public:
  using Visit = std::function<bool(const std::vector<sync::ScriptedCycle>&)>;
  AsyncSchedules(const std::vector<WindowEpoch>& epochs, std::vector<sync::AsyncCycle> choices)
      : epochs_(epochs), choices_(std::move(choices)) {
    uint16_t most = 0;
    for (const WindowEpoch& epoch : epochs_) {
      if (!epoch.members.empty()) most = std::max(most, epoch.members.back());
    }
    busy_.assign(static_cast<size_t>(most) + 1, 0);
  }
  // Calls `visit` with each schedule of exactly `k` deviating cycles (sorted
  // by epoch, then robot); false when `visit` asked to stop.
  bool ForEach(int k, const Visit& visit) {
    visit_ = &visit;
    cycles_.clear();
    std::fill(busy_.begin(), busy_.end(), 0);
    return Walk(0, 0, k);
  }

 private:
  bool Walk(size_t epoch, size_t member, int left) {
    if (left == 0) return (*visit_)(cycles_);  // every later look: FSYNC's cycle
    while (epoch < epochs_.size() && member >= epochs_[epoch].members.size()) {
      ++epoch;
      member = 0;
    }
    if (epoch == epochs_.size()) return true;  // the window ended with deviations left to place
    const uint16_t robot = epochs_[epoch].members[member];
    int& busy = busy_[robot];
    if (busy > 0) {  // inside a cycle: no look
      --busy;
      const bool go = Walk(epoch, member + 1, left);
      ++busy;
      return go;
    }
    for (const sync::AsyncCycle& choice : choices_) {
      cycles_.push_back({epochs_[epoch].epoch, robot, choice.start_delay, choice.move_epochs, choice.cut});
      busy = choice.start_delay + choice.move_epochs - 1;  // the epoch starts it holds after the look's
      const bool go = Walk(epoch, member + 1, left - 1);
      busy = 0;
      cycles_.pop_back();
      if (!go) return false;
    }
    return Walk(epoch, member + 1, left);  // FSYNC's cycle: the next epoch start looks again
  }

  const std::vector<WindowEpoch>& epochs_;
  std::vector<sync::AsyncCycle> choices_;
  std::vector<int> busy_;  // per robot id
  std::vector<sync::ScriptedCycle> cycles_;
  const Visit* visit_ = nullptr;
};

struct Outcome {
  std::vector<Violation> violations;
  metrics::Metrics metrics;
  size_t metrics_hash = 0;  // of metrics.json: equal for runs the metrics cannot tell apart
  std::optional<base::StateDigest::Value> end_state;  // check_pruning only
};

using Digest = base::StateDigest::Value;
struct DigestHash {
  size_t operator()(const Digest& digest) const { return static_cast<size_t>(digest.low ^ (digest.high * 31)); }
};

// The pattern that first reached a state at a round's start: its losses
// before that round (how many, and which, as a fingerprint).
struct Representative {
  int losses = 0;
  Digest prefix;
  int32_t prefix_index = -1;  // into Pruning::prefixes (check_pruning only)
};
using StateTable = std::unordered_map<Digest, Representative, DigestHash>;

// Most states the tables keep; past it none is added (the search stays
// sound, it only prunes less). About 70 bytes each with the hash table's
// own, so at most about 70 MB: a grader runs several searches side by side.
// (Every pair of losses in 6 epochs of 3 robots keeps 4,349.)
constexpr int64_t kMaxStoredStates = 1'000'000;

// One pattern of a batch, and what its run saw.
struct PatternRun {
  std::vector<int64_t> indices;   // slot indices, increasing (so by round)
  std::vector<int64_t> rounds;    // the slots' rounds
  std::vector<LostBeacon> lost;
  std::vector<Inactivation> inactive;
  std::vector<sync::ScriptedCycle> cycles;  // ASYNC
  std::vector<Digest> prefixes;   // [c]: the fingerprint of its first c losses
  // Its state at the start of rounds 1, 2, ... while it had broken nothing;
  // it ends early when the run stopped at a state seen before.
  std::vector<Digest> states;
  bool stopped = false;  // by the tables as they were when the batch began
  Outcome outcome;       // when it ran to its end
};

Digest PrefixDigest(std::span<const int64_t> indices) {
  base::StateDigest digest;
  digest.AddRange(indices);
  return digest.value();
}

// Losses (inactive robot-epochs) of `run` in rounds before `round`.
int LossesBefore(const PatternRun& run, int64_t round) {
  int count = 0;
  while (count < static_cast<int>(run.rounds.size()) && run.rounds[static_cast<size_t>(count)] < round) ++count;
  return count;
}

// The scenario a pattern stands for.
scenario::Scenario PatternScenario(const scenario::Scenario& scenario, const SearchSpace& space, const PatternRun& run) {
  if (space.async) return WithCycles(scenario, run.cycles, space.max_delay_epochs, space.min_move_m);
  if (space.activations) return WithInactivations(scenario, space.epochs, run.inactive);
  return WithLosses(scenario, run.lost);
}

// Whether a run with `losses` losses so far (fingerprinted `prefix`) in
// `state` goes on as a pattern of no more losses already does.
const Representative* Dominated(const StateTable& table, const Digest& state, int losses, const Digest& prefix) {
  const auto found = table.find(state);
  if (found == table.end()) return nullptr;
  const Representative& first = found->second;
  return first.prefix != prefix && first.losses <= losses ? &first : nullptr;
}

void RunPattern(const scenario::Scenario& scenario, const SearchSpace& space, const SearchOptions& options,
                PatternRun& run, bool goal_declared, const std::vector<StateTable>* tables, bool end_state) {
  sim::SimulationOptions sim_options;
  sim_options.apps = options.apps;
  sim_options.state_digests = tables != nullptr || end_state;
  sim::Simulation simulation(PatternScenario(scenario, space, run), sim_options);
  if (tables != nullptr) {
    for (int64_t round = 1; round < static_cast<int64_t>(tables->size()); ++round) {
      simulation.RunThroughRoundStart(round);
      if (simulation.PropertyBreaks() > 0) break;
      const std::optional<Digest> state = simulation.StateDigest();
      if (!state) break;
      run.states.push_back(*state);
      const int losses = LossesBefore(run, round);
      if (Dominated((*tables)[static_cast<size_t>(round)], *state, losses, run.prefixes[static_cast<size_t>(losses)])) {
        run.stopped = true;
        return;
      }
    }
  }
  simulation.RunUntil(scenario.timing.duration_s);
  if (end_state) run.outcome.end_state = simulation.StateDigest();
  sim::RunReport report = simulation.Finish(0);
  run.outcome.violations = ViolationsOf(report.metrics, goal_declared);
  run.outcome.metrics = std::move(report.metrics);
  run.outcome.metrics_hash = std::hash<std::string>{}(report.metrics_json);
}

// Runs `batch` on `jobs` threads, reading `tables` (null: no pruning).
void RunBatch(const scenario::Scenario& scenario, const SearchSpace& space, const SearchOptions& options,
              std::vector<PatternRun*>& batch, bool goal_declared, const std::vector<StateTable>* tables) {
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < batch.size(); i = next++) {
      RunPattern(scenario, space, options, *batch[i], goal_declared, tables, false);
    }
  };
  const int threads = std::min<int>(options.jobs, static_cast<int>(batch.size()));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
}

// ASYNC: the patterns of 1 .. `most` deviating cycles in search order,
// `jobs` at a time, up to the first that breaks the run (into `result`).
void SearchCycles(const scenario::Scenario& scenario, const SearchSpace& space, const SearchOptions& options,
                  int most, bool goal_declared, const std::function<double()>& elapsed_s,
                  std::unordered_set<size_t>& outcome_hashes, SearchResult& result) {
  AsyncSchedules schedules(space.epochs, AsyncChoices(space.max_delay_epochs, space.min_move_m > 0));
  const size_t batch_size = static_cast<size_t>(options.jobs) * 8;
  for (int deviations = 1; deviations <= most; ++deviations) {
    std::vector<PatternRun> batch;
    // Runs the batch; false once a run broke (counted in search order, as
    // the loss search counts, so the figures do not depend on --jobs).
    auto flush = [&] {
      std::vector<PatternRun*> running;
      for (PatternRun& run : batch) running.push_back(&run);
      RunBatch(scenario, space, options, running, goal_declared, nullptr);
      for (PatternRun& run : batch) {
        ++result.runs;
        outcome_hashes.insert(run.outcome.metrics_hash);
        result.distinct_outcomes = static_cast<int64_t>(outcome_hashes.size());
        if (run.outcome.violations.empty()) continue;
        Counterexample found;
        found.cycles = std::move(run.cycles);
        found.window_epochs = space.epochs;
        found.max_delay_epochs = space.max_delay_epochs;
        found.min_move_m = space.min_move_m;
        found.violations = std::move(run.outcome.violations);
        found.metrics = std::move(run.outcome.metrics);
        result.counterexample = std::move(found);
        return false;
      }
      batch.clear();
      if (options.progress) options.progress(result.runs, deviations);
      return true;
    };
    bool go = schedules.ForEach(deviations, [&](const std::vector<sync::ScriptedCycle>& cycles) {
      if (batch.empty() && options.time_limit_s > 0 && elapsed_s() >= options.time_limit_s) {
        result.stopped_by_time = true;
        return false;
      }
      PatternRun run;
      run.cycles = cycles;
      batch.push_back(std::move(run));
      return batch.size() < batch_size || flush();
    });
    if (go && !batch.empty()) go = flush();
    if (!go) return;
    result.complete_losses = deviations;
  }
}

// The scenario file again, its channel scripted to lose `lost` (its cuts,
// partitions and links kept), with the command line's overrides written in
// and a library's path made absolute, so the file runs from any folder.
// Comments are not kept.
// The `activation:` section of an activation search's counterexample: the
// script WithInactivations gives, or FSYNC when nobody is left out.
YAML::Node ActivationNode(const Counterexample& found) {
  YAML::Node activation(YAML::NodeType::Map);
  activation.SetStyle(YAML::EmitterStyle::Block);
  if (found.inactive.empty() && found.cycles.empty()) {
    activation["model"] = "fsync";
    return activation;
  }
  if (!found.cycles.empty()) {  // the scenario WithCycles gives
    const scenario::ActivationSpec spec =
        WithCycles({}, found.cycles, found.max_delay_epochs, found.min_move_m).activation;
    activation["model"] = "async";
    activation["schedule"] = "scripted";
    activation["max_delay_epochs"] = static_cast<int>(spec.max_delay_epochs);
    // The shortest text that reads back as the same double.
    if (spec.min_move_m > 0) activation["min_move_m"] = fmt::format("{}", spec.min_move_m);
    YAML::Node list(YAML::NodeType::Sequence);
    for (const sync::ScriptedCycle& cycle : spec.cycles) {
      YAML::Node row(YAML::NodeType::Sequence);
      row.SetStyle(YAML::EmitterStyle::Flow);
      row.push_back(cycle.epoch);
      row.push_back(cycle.robot);
      row.push_back(static_cast<int>(cycle.start_delay));
      row.push_back(static_cast<int>(cycle.move_epochs));
      if (cycle.cut) row.push_back(1);
      list.push_back(row);
    }
    activation["cycles"] = list;
    return activation;
  }
  activation["model"] = "ssync";
  activation["schedule"] = "scripted";
  YAML::Node list(YAML::NodeType::Sequence);
  std::optional<uint16_t> epoch;
  for (const sync::ScriptedActivation& entry : WithInactivations({}, found.window_epochs, found.inactive).activation.script) {
    if (!epoch || *epoch != entry.epoch) {
      YAML::Node row(YAML::NodeType::Sequence);
      row.SetStyle(YAML::EmitterStyle::Flow);
      row.push_back(entry.epoch);
      row.push_back(YAML::Node(YAML::NodeType::Sequence));
      list.push_back(row);
      epoch = entry.epoch;
    }
    YAML::Node ids = list[list.size() - 1][1];
    ids.push_back(entry.robot);
  }
  activation["active"] = list;
  return activation;
}

std::string CounterexampleText(const scenario::Scenario& resolved, const CounterexampleSource& source,
                               const Counterexample& found, bool activations) {
  YAML::Node root = YAML::LoadFile(source.scenario_path);
  YAML::Node channel(YAML::NodeType::Map);
  channel["model"] = "scripted";
  if (YAML::Node old = root["channel"]; old && old.IsMap()) {
    for (const char* key : {"links", "partitions", "cuts"}) {
      if (old[key]) channel[key] = old[key];
    }
  }
  YAML::Node list(YAML::NodeType::Sequence);
  for (const LostBeacon& beacon : found.lost) {
    YAML::Node entry(YAML::NodeType::Sequence);
    entry.SetStyle(YAML::EmitterStyle::Flow);
    entry.push_back(beacon.round);
    entry.push_back(beacon.from);
    entry.push_back(beacon.to);
    list.push_back(entry);
  }
  channel["lost"] = list;
  if (activations) {
    root["activation"] = ActivationNode(found);  // the scenario's channel stays
  } else {
    root["channel"] = channel;
  }
  root["name"] = resolved.name;  // else the name would be the new file's stem
  root["seed"] = resolved.seed;
  if (source.duration_s) root["timing"]["duration_s"] = *source.duration_s;
  if (resolved.app.is_library()) {
    const std::string absolute = std::filesystem::absolute(resolved.app.library).lexically_normal().string();
    if (root["app"] && root["app"].IsMap() && !source.app) {
      root["app"]["library"] = absolute;
    } else {
      root["app"] = absolute;
    }
  } else if (source.app) {
    root["app"] = *source.app;
  }
  YAML::Emitter emitter;
  emitter << root;
  if (activations && !found.cycles.empty()) {
    return fmt::format(
        "# syrof search --activations async: {} with {} deviating cycle{} (activation.cycles: [look epoch, robot, "
        "start_delay, move_epochs(, cut)]; a look not listed: a one-epoch uncut move)\n{}\n",
        source.scenario_path, found.cycles.size(), found.cycles.size() == 1 ? "" : "s", emitter.c_str());
  }
  if (activations) {
    return fmt::format(
        "# syrof search --activations: {} with {} inactive robot-epoch{} (activation.active: [epoch, [the robots "
        "active in it]]; epochs not listed: every member)\n{}\n",
        source.scenario_path, found.inactive.size(), found.inactive.size() == 1 ? "" : "s", emitter.c_str());
  }
  return fmt::format("# syrof search: {} with {} lost beacon{} (channel.lost: [round, sender, receiver])\n{}\n",
                     source.scenario_path, found.lost.size(), found.lost.size() == 1 ? "" : "s", emitter.c_str());
}

}  // namespace

std::optional<Error> WriteCounterexample(const std::string& dir, const scenario::Scenario& resolved,
                                         const CounterexampleSource& source, const Counterexample& found,
                                         const SearchOptions& options) {
  const std::filesystem::path folder(dir);
  const std::string yaml_path = (folder / "counterexample.yaml").string();
  auto failed = [&](std::string where, std::string message) {
    return Error{.where = std::move(where), .message = std::move(message)};
  };
  std::string text;
  try {
    text = CounterexampleText(resolved, source, found, options.activations);
  } catch (const std::exception& error) {
    return failed(yaml_path, fmt::format("not written: reading {} again failed: {}", source.scenario_path, error.what()));
  }
  {
    std::ofstream file(yaml_path, std::ios::binary | std::ios::trunc);
    file << text;
    if (!file) return failed(yaml_path, "cannot be written");
  }
  const scenario::LoadResult again = scenario::LoadScenarioFile(yaml_path);
  if (!again.ok()) return failed(yaml_path, "internal error: it does not load: " + again.error->ToString());
  std::ofstream replay_file(folder / "replay", std::ios::binary | std::ios::trunc);
  sim::SimulationOptions sim_options;
  sim_options.replay = &replay_file;
  sim_options.apps = options.apps;
  const sim::RunReport rerun = sim::Run(*again.scenario, sim_options, 0);
  replay_file.close();
  std::ofstream metrics_file(folder / "metrics.json", std::ios::binary | std::ios::trunc);
  metrics_file << rerun.metrics_json;
  if (!replay_file || !metrics_file) return failed(dir, "cannot write the replay and metrics.json here");
  if (rerun.metrics_json != metrics::ToJson(found.metrics)) {
    return failed(yaml_path, "internal error: it ran differently from the pattern it was written for");
  }
  return std::nullopt;
}

std::vector<Violation> ViolationsOf(const metrics::Metrics& m, bool goal_declared) {
  std::vector<Violation> found;
  const metrics::CommonKnowledgeMetrics& ck = m.common_knowledge;
  if (ck.violations > 0) {
    std::string detail = fmt::format("{} P3 violation{}", ck.violations, ck.violations == 1 ? "" : "s");
    if (!ck.first_violations.empty()) {
      const metrics::Violation& first = ck.first_violations.front();
      detail += fmt::format(": first robot {} in epoch {}", first.robot, first.epoch);
    }
    found.push_back({"common knowledge", detail});
  }
  if (m.agreement && m.agreement->disagreeing_calls > 0) {
    std::string detail = fmt::format("the app's global state differed in {} call{}", m.agreement->disagreeing_calls,
                                     m.agreement->disagreeing_calls == 1 ? "" : "s");
    if (const auto& first = m.agreement->first_disagreement) {
      detail += fmt::format(": first robot {} in epoch {} ({}), state {} where robot {} had {}", first->robot,
                            first->epoch, first->callback, first->state, first->reference_robot,
                            first->reference_state);
    }
    found.push_back({"agreement", detail});
  }
  if (m.collisions.count > 0) {
    std::string detail = fmt::format("{} collision{}", m.collisions.count, m.collisions.count == 1 ? "" : "s");
    if (!m.collisions.pairs.empty()) {
      const metrics::CollisionEvent& first = m.collisions.pairs.front();
      detail += fmt::format(": first robots {} and {} at {:.2f} s", first.a, first.b,
                            static_cast<double>(first.time_ns) / 1e9);
    }
    found.push_back({"collision", detail});
  }
  if (!m.app.faults.empty()) {
    const metrics::AppFault& first = m.app.faults.front();
    found.push_back({"app fault", fmt::format("robot {}, {} of epoch {}: {}", first.robot, first.callback,
                                              first.epoch, first.verdict)});
  } else if (m.app.invalid_commands.count > 0) {
    found.push_back({"app fault", fmt::format("{} invalid commands", m.app.invalid_commands.count)});
  } else if (m.app.payload_refused.count > 0) {
    found.push_back({"app fault", fmt::format("{} payloads refused", m.app.payload_refused.count)});
  }
  if (goal_declared && !m.goal.reached) found.push_back({"goal", m.goal.detail});
  return found;
}

scenario::Scenario WithLosses(const scenario::Scenario& base, std::span<const LostBeacon> lost) {
  scenario::Scenario result = base;
  world::ChannelSpec& channel = result.channel;
  const world::ChannelSpec defaults;
  channel.model = world::ChannelModel::kScripted;
  channel.loss = defaults.loss;
  channel.good_to_bad = defaults.good_to_bad;
  channel.bad_to_good = defaults.bad_to_good;
  channel.loss_good = defaults.loss_good;
  channel.loss_bad = defaults.loss_bad;
  channel.lost.assign(lost.begin(), lost.end());
  std::sort(channel.lost.begin(), channel.lost.end());
  channel.lost.erase(std::unique(channel.lost.begin(), channel.lost.end()), channel.lost.end());
  return result;
}

scenario::Scenario WithInactivations(const scenario::Scenario& base, std::span<const WindowEpoch> epochs,
                                     std::span<const Inactivation> inactive) {
  scenario::Scenario result = base;
  result.activation = scenario::ActivationSpec{};
  if (inactive.empty()) return result;  // FSYNC: every member, every epoch
  result.activation.model = sync::ActivationModel::kSsync;
  result.activation.schedule = sync::ActivationSchedule::kScripted;
  for (const WindowEpoch& epoch : epochs) {
    const bool listed = std::any_of(inactive.begin(), inactive.end(),
                                    [&](const Inactivation& out) { return out.epoch == epoch.epoch; });
    if (!listed) continue;
    for (const uint16_t robot : epoch.members) {
      const bool left_out = std::any_of(inactive.begin(), inactive.end(), [&](const Inactivation& out) {
        return out.epoch == epoch.epoch && out.robot == robot;
      });
      if (!left_out) result.activation.script.push_back({epoch.epoch, robot});
    }
  }
  return result;
}

scenario::Scenario WithCycles(const scenario::Scenario& base, std::span<const sync::ScriptedCycle> cycles,
                              int max_delay_epochs, double min_move_m) {
  scenario::Scenario result = base;
  result.activation = scenario::ActivationSpec{};
  if (cycles.empty()) return result;  // FSYNC: every look a one-epoch move
  result.activation.model = sync::ActivationModel::kAsync;
  result.activation.schedule = sync::ActivationSchedule::kScripted;
  result.activation.max_delay_epochs = static_cast<uint8_t>(max_delay_epochs);
  result.activation.min_move_m = min_move_m;
  result.activation.cycles.assign(cycles.begin(), cycles.end());
  std::sort(result.activation.cycles.begin(), result.activation.cycles.end(),
            [](const sync::ScriptedCycle& a, const sync::ScriptedCycle& b) {
              return a.epoch != b.epoch ? a.epoch < b.epoch : a.robot < b.robot;
            });
  return result;
}

std::vector<sync::AsyncCycle> AsyncChoices(int max_delay_epochs, bool cuts) {
  std::vector<sync::AsyncCycle> choices;
  for (int length = 1; length <= 2 * max_delay_epochs + 1; ++length) {
    for (int delay = 0; delay <= max_delay_epochs; ++delay) {
      const int move = length - delay;
      if (move < 1 || move > max_delay_epochs + 1) continue;
      for (const bool cut : {false, true}) {
        if (cut && !cuts) continue;
        if (delay == 0 && move == 1 && !cut) continue;  // FSYNC's cycle
        choices.push_back({static_cast<uint8_t>(delay), static_cast<uint8_t>(move), cut});
      }
    }
  }
  return choices;
}

int64_t AsyncScheduleCount(const std::vector<WindowEpoch>& epochs, int max_delay_epochs, bool cuts, int most) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  auto add = [&](int64_t a, int64_t b) { return a > kMax - b ? kMax : a + b; };
  auto times = [&](int64_t a, int64_t b) {
    if (a == 0 || b == 0) return int64_t{0};
    return a > kMax / b ? kMax : a * b;
  };
  const std::vector<sync::AsyncCycle> choices = AsyncChoices(max_delay_epochs, cuts);
  using Polynomial = std::vector<int64_t>;  // [k]: schedules with k deviating cycles
  auto multiply = [&](const Polynomial& a, const Polynomial& b) {
    Polynomial product(static_cast<size_t>(most) + 1, 0);
    for (size_t i = 0; i < a.size(); ++i) {
      for (size_t j = 0; i + j < product.size(); ++j) product[i + j] = add(product[i + j], times(a[i], b[j]));
    }
    return product;
  };
  std::map<uint16_t, int64_t> starts;  // per robot: the window's epoch starts it makes
  for (const WindowEpoch& epoch : epochs) {
    for (const uint16_t robot : epoch.members) ++starts[robot];
  }
  Polynomial total(static_cast<size_t>(most) + 1, 0);
  total[0] = 1;
  for (const auto& [robot, count] : starts) {
    // after[i]: the schedules of the robot's starts from its i-th on, when
    // it looks at the i-th (1 once past the window).
    std::vector<Polynomial> after(static_cast<size_t>(count) + 1, Polynomial(total.size(), 0));
    after[static_cast<size_t>(count)][0] = 1;
    for (int64_t i = count - 1; i >= 0; --i) {
      Polynomial& here = after[static_cast<size_t>(i)];
      here = after[static_cast<size_t>(i) + 1];
      for (const sync::AsyncCycle& choice : choices) {
        const int64_t next = std::min<int64_t>(count, i + choice.start_delay + choice.move_epochs);
        const Polynomial& rest = after[static_cast<size_t>(next)];
        for (size_t k = 0; k + 1 < here.size(); ++k) here[k + 1] = add(here[k + 1], rest[k]);
      }
    }
    total = multiply(total, after[0]);
  }
  int64_t sum = 0;
  for (const int64_t count : total) sum = add(sum, count);
  return sum;
}

int64_t PatternCount(int64_t slots, int losses) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  int64_t total = 0;
  int64_t choose = 1;  // C(slots, k)
  for (int k = 0; k <= losses; ++k) {
    if (k > 0) {
      if (slots - k + 1 <= 0) break;
      // C(n, k) = C(n, k-1) * (n - k + 1) / k, exact; in long double
      // only to see that it fits (at most kMaxSearchLosses steps).
      const int64_t factor = slots - k + 1;
      if (static_cast<long double>(choose) * static_cast<long double>(factor) > static_cast<long double>(kMax)) {
        return kMax;
      }
      choose = choose * factor / k;
    }
    if (total > kMax - choose) return kMax;
    total += choose;
  }
  return total;
}

namespace {

// Why `options` cannot search `scenario`, before anything runs (so that a
// search too large costs nothing); nothing when it can. `async`: an ASYNC
// search with the delay bound `max_delay_epochs`.
std::optional<std::string> RefusedBeforeRunning(const scenario::Scenario& scenario, const SearchOptions& options,
                                                bool async, int max_delay_epochs) {
  if (async && (max_delay_epochs < 1 || max_delay_epochs > sync::kMaxAsyncDelayEpochs)) {
    return fmt::format(
        "an ASYNC search needs a delay bound of 1 .. {} epochs (the scenario's activation.max_delay_epochs under "
        "model async, or --max-delay), got {}",
        sync::kMaxAsyncDelayEpochs, max_delay_epochs);
  }
  // The window's looks, at most every robot in every epoch.
  if (const int64_t most = static_cast<int64_t>(scenario.robots.size()) * options.epochs;
      async && most > kMaxAsyncSearchLooks) {
    return fmt::format(
        "the first {} epochs of {} robots hold up to {} robot-epochs, more looks than an ASYNC search walks (at most "
        "{}): search fewer epochs (--epochs) or a smaller swarm",
        options.epochs, scenario.robots.size(), most, kMaxAsyncSearchLooks);
  }
  // The search chooses every loss itself; a link that loses some beacons at
  // random would make a pattern's outcome the seed's as much as the search's.
  for (const world::LinkLossSpec& link : scenario.channel.links) {
    if (link.loss > 0 && link.loss < 1) {
      return fmt::format(
          "channel link {} -> {} loses {} of its beacons at random; a search decides every loss itself: give the "
          "link loss 0 or 1 (a dead link), or leave it out",
          link.from, link.to, link.loss);
    }
  }
  return std::nullopt;
}

// Pattern `indices` of `space` ready to run: its slots' rounds, its lost
// beacons or inactive robot-epochs, and the fingerprints of its prefixes.
PatternRun MakeRun(const SearchSpace& space, std::vector<int64_t> indices) {
  PatternRun run;
  run.indices = std::move(indices);
  for (int64_t index : run.indices) {
    run.rounds.push_back(space.RoundOf(index));
    if (space.activations) {
      run.inactive.push_back(space.inactivations[static_cast<size_t>(index)]);
    } else {
      run.lost.push_back(space.beacons[static_cast<size_t>(index)]);
    }
  }
  for (size_t c = 0; c <= run.indices.size(); ++c) {
    run.prefixes.push_back(PrefixDigest(std::span<const int64_t>(run.indices.data(), c)));
  }
  return run;
}

// Where a pattern was pruned: the round, and the representative it met
// (check_pruning); round 0: it was not.
struct Pruned {
  int64_t round = 0;
  int32_t prefix_index = -1;
};

// Pruning (search.h): a table per round start of the states seen there,
// and, for patterns shorter than the longest, the round at which each was
// pruned (0: it ran to its end), so that the patterns that extend it with
// later losses are skipped. No two schedules meet in a state: the state
// holds each app's call history (search.h), and schedules differ in who was
// called when.
class Pruning {
 public:
  // Off: no tables, nothing pruned. `check`: keep what the self-test needs.
  Pruning(bool on, int64_t window_rounds, bool check)
      : tables_(on ? static_cast<size_t>(window_rounds) + 1 : 0), check_(check) {}

  bool on() const { return !tables_.empty(); }
  // What a run reads to stop early; null when off.
  const std::vector<StateTable>* tables() const { return on() ? &tables_ : nullptr; }
  int64_t stored_states() const { return stored_states_; }

  // The states of `run`, in order, against the tables as they are now;
  // where it was pruned, or {0} if it was not (its new states added).
  Pruned Merge(const PatternRun& run) {
    for (size_t k = 0; k < run.states.size(); ++k) {
      const auto round = static_cast<int64_t>(k) + 1;
      const int losses = LossesBefore(run, round);
      const Digest& prefix = run.prefixes[static_cast<size_t>(losses)];
      StateTable& table = tables_[static_cast<size_t>(round)];
      if (const Representative* first = Dominated(table, run.states[k], losses, prefix)) {
        return Pruned{round, first->prefix_index};
      }
      if (stored_states_ < kMaxStoredStates && !table.contains(run.states[k])) {
        Representative representative{losses, prefix, -1};
        if (check_) {
          representative.prefix_index = static_cast<int32_t>(representative_prefixes_.size());
          representative_prefixes_.emplace_back(run.indices.begin(), run.indices.begin() + losses);
        }
        table.emplace(run.states[k], representative);
        ++stored_states_;
      }
    }
    return Pruned{};
  }

  // Whether a shorter pattern that `indices` extends with later losses only
  // was pruned before those losses (into `why`).
  bool SkippedByPrefix(const SearchSpace& space, const std::vector<int64_t>& indices, Pruned& why) const {
    for (size_t m = 1; m < indices.size(); ++m) {
      const auto found =
          memo_.find(std::vector<int64_t>(indices.begin(), indices.begin() + static_cast<ptrdiff_t>(m)));
      if (found == memo_.end() || found->second.round == 0) continue;
      if (space.RoundOf(indices[m]) >= found->second.round) {
        why = found->second;
        return true;
      }
    }
    return false;
  }

  // Where a pattern that longer ones may extend was pruned.
  void Remember(const std::vector<int64_t>& indices, const Pruned& pruned) { memo_.emplace(indices, pruned); }
  // A pruned pattern for the self-test (check_pruning).
  void NoteForCheck(const std::vector<int64_t>& indices, const Pruned& pruned) {
    if (check_) checks_.push_back({indices, pruned});
  }

  // The self-test: each pruned pattern, run to its end, against the
  // pattern it stood for (the representative's losses before the round it
  // was pruned at, then its own from that round on); into `result`.
  void Check(const scenario::Scenario& scenario, const SearchSpace& space, const SearchOptions& options,
             bool goal_declared, SearchResult& result) const {
    for (const PrunedPattern& check : checks_) {
      std::vector<int64_t> standing_for =
          representative_prefixes_.at(static_cast<size_t>(check.pruned.prefix_index));
      for (int64_t index : check.indices) {
        if (space.RoundOf(index) >= check.pruned.round) standing_for.push_back(index);
      }
      PatternRun pruned_run = MakeRun(space, check.indices);
      PatternRun other_run = MakeRun(space, standing_for);
      RunPattern(scenario, space, options, pruned_run, goal_declared, nullptr, true);
      RunPattern(scenario, space, options, other_run, goal_declared, nullptr, true);
      ++result.pruning_checked;
      const bool same_state = pruned_run.outcome.end_state == other_run.outcome.end_state;
      if (same_state && Properties(pruned_run.outcome) == Properties(other_run.outcome)) continue;
      if (result.pruning_mismatches++ == 0) {
        result.first_mismatch =
            fmt::format("{}pruned at round {} as {}: they end {} ({} / {})", Described(pruned_run), check.pruned.round,
                        Described(other_run),
                        same_state ? "in the same state but break other properties" : "in different states",
                        Properties(pruned_run.outcome), Properties(other_run.outcome));
      }
    }
  }

 private:
  struct PrunedPattern {
    std::vector<int64_t> indices;
    Pruned pruned;
  };

  static std::string Properties(const Outcome& outcome) {
    std::string text;
    for (const Violation& violation : outcome.violations) text += violation.property + ": " + violation.detail + "; ";
    return text;
  }
  static std::string Described(const PatternRun& run) {
    std::string text;
    for (const LostBeacon& beacon : run.lost) text += fmt::format("[{}, {}, {}] ", beacon.round, beacon.from, beacon.to);
    for (const Inactivation& out : run.inactive) text += fmt::format("[epoch {}: {}] ", out.epoch, out.robot);
    return text;
  }

  std::vector<StateTable> tables_;
  bool check_ = false;
  std::map<std::vector<int64_t>, Pruned> memo_;
  std::vector<std::vector<int64_t>> representative_prefixes_;
  std::vector<PrunedPattern> checks_;
  int64_t stored_states_ = 0;
};

// The loss (or inactivation) patterns of 1 .. `most` in search order,
// `jobs` * 8 at a time, up to the first that breaks the run (into `result`).
void SearchPatterns(const scenario::Scenario& scenario, const SearchSpace& space, const SearchOptions& options,
                    int most, bool goal_declared, const std::function<double()>& elapsed_s, Pruning& pruning,
                    std::unordered_set<size_t>& outcome_hashes, SearchResult& result) {
  const size_t batch_size = static_cast<size_t>(options.jobs) * 8;
  for (int losses = 1; losses <= most; ++losses) {
    const bool remember = pruning.on() && losses < most;
    Patterns patterns(result.slots, losses);
    while (!patterns.done()) {
      if (options.time_limit_s > 0 && elapsed_s() >= options.time_limit_s) {
        result.stopped_by_time = true;
        break;
      }
      // The batch, in search order: patterns skipped at once, and those to run.
      std::vector<PatternRun> batch;
      std::vector<Pruned> skipped;  // per batch entry; round 0: to run
      size_t to_run = 0;
      for (; !patterns.done() && to_run < batch_size; patterns.Advance()) {
        if (space.activations && !IsSchedule(space, patterns.current())) {
          ++result.not_schedules;
          continue;
        }
        Pruned why;
        const bool skip = pruning.on() && pruning.SkippedByPrefix(space, patterns.current(), why);
        batch.push_back(MakeRun(space, patterns.current()));
        skipped.push_back(skip ? why : Pruned{});
        if (!skip) ++to_run;
      }
      std::vector<PatternRun*> running;
      for (size_t i = 0; i < batch.size(); ++i) {
        if (skipped[i].round == 0) running.push_back(&batch[i]);
      }
      RunBatch(scenario, space, options, running, goal_declared, pruning.tables());
      for (size_t i = 0; i < batch.size(); ++i) {
        // Counted in search order, up to the first pattern that broke the
        // run, whatever else the batch ran: the same figures for any --jobs.
        PatternRun& run = batch[i];
        ++result.runs;
        Pruned pruned = skipped[i];
        if (pruned.round > 0) {
          ++result.skipped;
        } else if (pruning.on()) {
          result.round_starts += static_cast<int64_t>(run.states.size());
          pruned = pruning.Merge(run);
          if (pruned.round > 0) ++result.stopped_early;
        }
        if (remember) pruning.Remember(run.indices, pruned);
        if (pruned.round > 0) {
          pruning.NoteForCheck(run.indices, pruned);
          continue;
        }
        SYROF_CHECK(!run.stopped);  // the tables only grew since the batch began
        outcome_hashes.insert(run.outcome.metrics_hash);
        result.distinct_outcomes = static_cast<int64_t>(outcome_hashes.size());
        if (run.outcome.violations.empty()) continue;
        result.counterexample = Counterexample{std::move(run.lost), std::move(run.inactive), space.epochs,
                                               std::move(run.outcome.violations), std::move(run.outcome.metrics)};
        return;
      }
      if (options.progress) options.progress(result.runs, losses);
    }
    if (result.stopped_by_time) return;
    result.complete_losses = losses;
  }
}

}  // namespace

SearchResult Search(const scenario::Scenario& scenario, const SearchOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  auto elapsed_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); };
  const bool goal_declared = !scenario.goal.empty();
  SearchResult result;
  // ASYNC: the bounds a cycle is chosen under, the command's or the scenario's.
  const bool async = options.activations && options.activation_model == sync::ActivationModel::kAsync;
  const bool scenario_async = scenario.activation.model == sync::ActivationModel::kAsync;
  int max_delay_epochs = options.max_delay_epochs;
  if (max_delay_epochs == 0 && scenario_async) max_delay_epochs = scenario.activation.max_delay_epochs;
  const double min_move_m = options.min_move_m.value_or(scenario_async ? scenario.activation.min_move_m : 0.0);
  if (std::optional<std::string> refused = RefusedBeforeRunning(scenario, options, async, max_delay_epochs)) {
    result.error = std::move(*refused);
    return result;
  }

  // The loss-free run: the first pattern, and the epochs that set the window.
  std::ostringstream replay_bytes;
  sim::SimulationOptions sim_options;
  sim_options.apps = options.apps;
  sim_options.replay = &replay_bytes;
  // With every robot active (FSYNC), for the activation search.
  const scenario::Scenario loss_free =
      options.activations ? WithInactivations(scenario, {}, {}) : WithLosses(scenario, {});
  sim::RunReport baseline = sim::Run(loss_free, sim_options, 0);
  result.runs = 1;
  result.distinct_outcomes = 1;
  std::vector<Violation> violations = ViolationsOf(baseline.metrics, goal_declared);
  if (!violations.empty()) {
    result.counterexample = Counterexample{{}, {}, {}, std::move(violations), std::move(baseline.metrics)};
    result.seconds = elapsed_s();
    return result;
  }
  result.complete_losses = 0;
  const Window window = WindowOf(replay_bytes.str(), baseline.metrics.radio_rounds, options.epochs);
  result.window_rounds = window.rounds;
  result.epochs_in_window = window.epochs;
  const auto robots = static_cast<int64_t>(scenario.robots.size());
  SearchSpace space;
  space.activations = options.activations;
  space.fair_within = options.fair_within;
  int most_in_pattern = options.max_losses;
  if (async) {
    space.epochs = window.rows;
    space.async = true;
    space.max_delay_epochs = max_delay_epochs;
    space.min_move_m = min_move_m;
    int64_t looks = 0;  // the robot-epochs of the window: the most looks a schedule makes
    for (const WindowEpoch& epoch : space.epochs) looks += static_cast<int64_t>(epoch.members.size());
    most_in_pattern = static_cast<int>(std::min<int64_t>(options.max_deviations, looks));
    result.patterns_in_all = AsyncScheduleCount(space.epochs, max_delay_epochs, min_move_m > 0, most_in_pattern);
    result.slots = looks;
  } else if (options.activations) {
    space.epochs = window.rows;
    space.inactivations = InactivationSlots(space.epochs, space.epoch_of);
    // Each epoch keeps one member active.
    most_in_pattern = static_cast<int>(std::min<int64_t>(
        options.max_inactive, space.size() - static_cast<int64_t>(space.epochs.size())));
    result.patterns_in_all = ScheduleCount(space.epochs, std::max(most_in_pattern, 0));
  } else if (const int64_t most = robots * (robots - 1) * window.rounds; most > kMaxSearchSlots) {
    result.error = fmt::format(
        "the first {} epoch{} hold up to {} beacon slots ({} robots, {} radio rounds), more than a search can try "
        "(at most {}): search a smaller swarm or fewer epochs",
        window.epochs, window.epochs == 1 ? "" : "s", most, robots, window.rounds, kMaxSearchSlots);
    result.seconds = elapsed_s();
    return result;
  }
  if (!options.activations) space.beacons = SlotsOf(scenario, window.rounds);
  if (!async) result.slots = space.size();

  Pruning pruning(options.prune && !options.activations && !scenario.clocks.enabled && window.rounds > 0,
                  window.rounds, options.check_pruning);
  if (pruning.on()) {
    // The loss-free run's states come first: every masked loss meets them.
    PatternRun loss_free_run = MakeRun(space, {});
    RunPattern(scenario, space, options, loss_free_run, goal_declared, pruning.tables(), false);
    pruning.Merge(loss_free_run);
    result.round_starts += static_cast<int64_t>(loss_free_run.states.size());
  }
  std::unordered_set<size_t> outcome_hashes{std::hash<std::string>{}(baseline.metrics_json)};
  result.distinct_outcomes = 1;
  if (async) {
    SearchCycles(scenario, space, options, most_in_pattern, goal_declared, elapsed_s, outcome_hashes, result);
  } else {
    SearchPatterns(scenario, space, options, most_in_pattern, goal_declared, elapsed_s, pruning, outcome_hashes,
                   result);
  }
  result.distinct_states = pruning.stored_states();
  pruning.Check(scenario, space, options, goal_declared, result);
  result.seconds = elapsed_s();
  return result;
}

}  // namespace syrof::lab::search
