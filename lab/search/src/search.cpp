#include "syrof/lab/search/search.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
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
};

Window WindowOf(const std::string& replay_bytes, int64_t run_rounds, int epochs) {
  std::istringstream in(replay_bytes);
  replay::Reader reader(in);
  replay::Header header;
  Window window{run_rounds, 0};
  if (!reader.ReadHeader(header)) return window;
  replay::EpochTableBuilder builder(header, reader.version());
  replay::Round round;
  while (reader.Next(round)) builder.Add(round);
  const replay::EpochTable table = std::move(builder).Finish();
  window.epochs = static_cast<int64_t>(table.epochs.size());
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
  std::vector<LostBeacon> lost;
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

// Losses of `run` in rounds before `round`.
int LossesBefore(const PatternRun& run, int64_t round) {
  int count = 0;
  while (count < static_cast<int>(run.lost.size()) && run.lost[static_cast<size_t>(count)].round < round) ++count;
  return count;
}

// Whether a run with `losses` losses so far (fingerprinted `prefix`) in
// `state` goes on as a pattern of no more losses already does.
const Representative* Dominated(const StateTable& table, const Digest& state, int losses, const Digest& prefix) {
  const auto found = table.find(state);
  if (found == table.end()) return nullptr;
  const Representative& first = found->second;
  return first.prefix != prefix && first.losses <= losses ? &first : nullptr;
}

void RunPattern(const scenario::Scenario& scenario, const SearchOptions& options, PatternRun& run,
                bool goal_declared, const std::vector<StateTable>* tables, bool end_state) {
  sim::SimulationOptions sim_options;
  sim_options.app_factory = options.app_factory;
  sim_options.app_source = options.app_source;
  sim_options.app_sandbox = options.app_sandbox;
  sim_options.state_digests = tables != nullptr || end_state;
  sim::Simulation simulation(WithLosses(scenario, run.lost), sim_options);
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
void RunBatch(const scenario::Scenario& scenario, const SearchOptions& options, std::vector<PatternRun*>& batch,
              bool goal_declared, const std::vector<StateTable>* tables) {
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < batch.size(); i = next++) {
      RunPattern(scenario, options, *batch[i], goal_declared, tables, false);
    }
  };
  const int threads = std::min<int>(options.jobs, static_cast<int>(batch.size()));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
}

// The scenario file again, its channel scripted to lose `lost` (its cuts,
// partitions and links kept), with the command line's overrides written in
// and a library's path made absolute, so the file runs from any folder.
// Comments are not kept.
std::string CounterexampleText(const scenario::Scenario& resolved, const CounterexampleSource& source,
                               const std::vector<LostBeacon>& lost) {
  YAML::Node root = YAML::LoadFile(source.scenario_path);
  YAML::Node channel(YAML::NodeType::Map);
  channel["model"] = "scripted";
  if (YAML::Node old = root["channel"]; old && old.IsMap()) {
    for (const char* key : {"links", "partitions", "cuts"}) {
      if (old[key]) channel[key] = old[key];
    }
  }
  YAML::Node list(YAML::NodeType::Sequence);
  for (const LostBeacon& beacon : lost) {
    YAML::Node entry(YAML::NodeType::Sequence);
    entry.SetStyle(YAML::EmitterStyle::Flow);
    entry.push_back(beacon.round);
    entry.push_back(beacon.from);
    entry.push_back(beacon.to);
    list.push_back(entry);
  }
  channel["lost"] = list;
  root["channel"] = channel;
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
  return fmt::format("# syrof search: {} with {} lost beacon{} (channel.lost: [round, sender, receiver])\n{}\n",
                     source.scenario_path, lost.size(), lost.size() == 1 ? "" : "s", emitter.c_str());
}

}  // namespace

std::string WriteCounterexample(const std::string& dir, const scenario::Scenario& resolved,
                                const CounterexampleSource& source, const Counterexample& found,
                                const SearchOptions& options) {
  const std::filesystem::path folder(dir);
  const std::string yaml_path = (folder / "counterexample.yaml").string();
  std::string text;
  try {
    text = CounterexampleText(resolved, source, found.lost);
  } catch (const std::exception& error) {
    return fmt::format("cannot write {}: reading {} again failed: {}", yaml_path, source.scenario_path, error.what());
  }
  {
    std::ofstream file(yaml_path, std::ios::binary | std::ios::trunc);
    file << text;
    if (!file) return fmt::format("cannot write {}", yaml_path);
  }
  const scenario::LoadResult again = scenario::LoadScenarioFile(yaml_path);
  if (!again.ok()) return fmt::format("internal error: {} does not load: {}", yaml_path, again.error->ToString());
  std::ofstream replay_file(folder / "replay", std::ios::binary | std::ios::trunc);
  sim::SimulationOptions sim_options;
  sim_options.replay = &replay_file;
  sim_options.app_factory = options.app_factory;
  sim_options.app_source = options.app_source;
  sim_options.app_sandbox = options.app_sandbox;
  const sim::RunReport rerun = sim::Run(*again.scenario, sim_options, 0);
  replay_file.close();
  std::ofstream metrics_file(folder / "metrics.json", std::ios::binary | std::ios::trunc);
  metrics_file << rerun.metrics_json;
  if (!replay_file || !metrics_file) return fmt::format("cannot write the replay and metrics.json in {}", dir);
  if (rerun.metrics_json != metrics::ToJson(found.metrics)) {
    return fmt::format("internal error: {} ran differently from the pattern it was written for", yaml_path);
  }
  return {};
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

SearchResult Search(const scenario::Scenario& scenario, const SearchOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  auto elapsed_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); };
  const bool goal_declared = !scenario.goal.empty();
  SearchResult result;
  // The search chooses every loss itself; a link that loses some beacons at
  // random would make a pattern's outcome the seed's as much as the search's.
  for (const world::LinkLossSpec& link : scenario.channel.links) {
    if (link.loss > 0 && link.loss < 1) {
      result.error = fmt::format(
          "channel link {} -> {} loses {} of its beacons at random; a search decides every loss itself: give the "
          "link loss 0 or 1 (a dead link), or leave it out",
          link.from, link.to, link.loss);
      return result;
    }
  }

  // The loss-free run: the first pattern, and the epochs that set the window.
  std::ostringstream replay_bytes;
  sim::SimulationOptions sim_options;
  sim_options.app_factory = options.app_factory;
  sim_options.app_source = options.app_source;
  sim_options.app_sandbox = options.app_sandbox;
  sim_options.replay = &replay_bytes;
  const scenario::Scenario loss_free = WithLosses(scenario, {});
  sim::RunReport baseline = sim::Run(loss_free, sim_options, 0);
  result.runs = 1;
  std::vector<Violation> violations = ViolationsOf(baseline.metrics, goal_declared);
  if (!violations.empty()) {
    result.counterexample = Counterexample{{}, std::move(violations), std::move(baseline.metrics)};
    result.seconds = elapsed_s();
    return result;
  }
  result.complete_losses = 0;
  const Window window = WindowOf(replay_bytes.str(), baseline.metrics.radio_rounds, options.epochs);
  result.window_rounds = window.rounds;
  result.epochs_in_window = window.epochs;
  const auto robots = static_cast<int64_t>(scenario.robots.size());
  if (const int64_t most = robots * (robots - 1) * window.rounds; most > kMaxSearchSlots) {
    result.error = fmt::format(
        "the first {} epoch{} hold up to {} beacon slots ({} robots, {} radio rounds), more than a search can try "
        "(at most {}): search a smaller swarm or fewer epochs",
        window.epochs, window.epochs == 1 ? "" : "s", most, robots, window.rounds, kMaxSearchSlots);
    result.seconds = elapsed_s();
    return result;
  }
  const std::vector<LostBeacon> slots = SlotsOf(scenario, window.rounds);
  result.slots = static_cast<int64_t>(slots.size());

  // Pruning (search.h): a table per round start of the states seen there,
  // and, for patterns shorter than the longest, the round at which each was
  // pruned (0: it ran to its end), so that the patterns that extend it with
  // later losses are skipped.
  const bool prune = options.prune && !scenario.clocks.enabled && window.rounds > 0;
  std::vector<StateTable> tables(prune ? static_cast<size_t>(window.rounds) + 1 : 0);
  struct Pruned {
    int64_t round = 0;
    int32_t prefix_index = -1;
  };
  std::map<std::vector<int64_t>, Pruned> memo;
  std::vector<std::vector<int64_t>> representative_prefixes;  // check_pruning
  struct Check {
    std::vector<int64_t> indices;
    Pruned pruned;
  };
  std::vector<Check> checks;
  int64_t stored_states = 0;

  auto make_run = [&](std::vector<int64_t> indices) {
    PatternRun run;
    run.indices = std::move(indices);
    for (int64_t index : run.indices) run.lost.push_back(slots[static_cast<size_t>(index)]);
    for (size_t c = 0; c <= run.indices.size(); ++c) {
      run.prefixes.push_back(PrefixDigest(std::span<const int64_t>(run.indices.data(), c)));
    }
    return run;
  };
  // The states of `run`, in order, against the tables as they are now;
  // where it was pruned, or {0} if it was not (its new states added).
  auto merge = [&](const PatternRun& run) {
    for (size_t k = 0; k < run.states.size(); ++k) {
      const auto round = static_cast<int64_t>(k) + 1;
      const int losses = LossesBefore(run, round);
      const Digest& prefix = run.prefixes[static_cast<size_t>(losses)];
      StateTable& table = tables[static_cast<size_t>(round)];
      if (const Representative* first = Dominated(table, run.states[k], losses, prefix)) {
        return Pruned{round, first->prefix_index};
      }
      if (stored_states < kMaxStoredStates && !table.contains(run.states[k])) {
        Representative representative{losses, prefix, -1};
        if (options.check_pruning) {
          representative.prefix_index = static_cast<int32_t>(representative_prefixes.size());
          representative_prefixes.emplace_back(run.indices.begin(), run.indices.begin() + losses);
        }
        table.emplace(run.states[k], representative);
        ++stored_states;
      }
    }
    return Pruned{};
  };
  // Whether a shorter pattern that `indices` extends with later losses only
  // was pruned before those losses.
  auto skipped_by_prefix = [&](const std::vector<int64_t>& indices, Pruned& why) {
    for (size_t m = 1; m < indices.size(); ++m) {
      const auto found = memo.find(std::vector<int64_t>(indices.begin(), indices.begin() + static_cast<ptrdiff_t>(m)));
      if (found == memo.end() || found->second.round == 0) continue;
      if (slots[static_cast<size_t>(indices[m])].round >= found->second.round) {
        why = found->second;
        return true;
      }
    }
    return false;
  };

  if (prune) {
    // The loss-free run's states come first: every masked loss meets them.
    PatternRun loss_free_run = make_run({});
    RunPattern(scenario, options, loss_free_run, goal_declared, &tables, false);
    merge(loss_free_run);
    result.round_starts += static_cast<int64_t>(loss_free_run.states.size());
  }

  const size_t batch_size = static_cast<size_t>(options.jobs) * 8;
  std::unordered_set<size_t> outcome_hashes{std::hash<std::string>{}(baseline.metrics_json)};
  result.distinct_outcomes = 1;
  for (int losses = 1; losses <= options.max_losses; ++losses) {
    const bool remember = prune && losses < options.max_losses;
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
        Pruned why;
        const bool skip = prune && skipped_by_prefix(patterns.current(), why);
        batch.push_back(make_run(patterns.current()));
        skipped.push_back(skip ? why : Pruned{});
        if (!skip) ++to_run;
      }
      std::vector<PatternRun*> running;
      for (size_t i = 0; i < batch.size(); ++i) {
        if (skipped[i].round == 0) running.push_back(&batch[i]);
      }
      RunBatch(scenario, options, running, goal_declared, prune ? &tables : nullptr);
      for (size_t i = 0; i < batch.size(); ++i) {
        // Counted in search order, up to the first pattern that broke the
        // run, whatever else the batch ran: the same figures for any --jobs.
        PatternRun& run = batch[i];
        ++result.runs;
        Pruned pruned = skipped[i];
        if (pruned.round > 0) {
          ++result.skipped;
        } else if (prune) {
          result.round_starts += static_cast<int64_t>(run.states.size());
          pruned = merge(run);
          if (pruned.round > 0) ++result.stopped_early;
        }
        if (remember) memo.emplace(run.indices, pruned);
        if (pruned.round > 0) {
          if (options.check_pruning) checks.push_back({run.indices, pruned});
          continue;
        }
        SYROF_CHECK(!run.stopped);  // the tables only grew since the batch began
        outcome_hashes.insert(run.outcome.metrics_hash);
        result.distinct_outcomes = static_cast<int64_t>(outcome_hashes.size());
        if (run.outcome.violations.empty()) continue;
        result.counterexample = Counterexample{std::move(run.lost), std::move(run.outcome.violations),
                                               std::move(run.outcome.metrics)};
        break;
      }
      if (result.counterexample) break;
      if (options.progress) options.progress(result.runs, losses);
    }
    if (result.counterexample || result.stopped_by_time) break;
    result.complete_losses = losses;
  }
  result.distinct_states = stored_states;

  // The self-test: each pruned pattern, run to its end, against the pattern
  // it stood for (the representative's losses before the round it was
  // pruned at, then its own from that round on).
  for (const Check& check : checks) {
    std::vector<int64_t> standing_for = representative_prefixes.at(static_cast<size_t>(check.pruned.prefix_index));
    for (int64_t index : check.indices) {
      if (slots[static_cast<size_t>(index)].round >= check.pruned.round) standing_for.push_back(index);
    }
    PatternRun pruned_run = make_run(check.indices);
    PatternRun other_run = make_run(standing_for);
    RunPattern(scenario, options, pruned_run, goal_declared, nullptr, true);
    RunPattern(scenario, options, other_run, goal_declared, nullptr, true);
    ++result.pruning_checked;
    auto properties = [](const Outcome& outcome) {
      std::string text;
      for (const Violation& violation : outcome.violations) text += violation.property + ": " + violation.detail + "; ";
      return text;
    };
    if (pruned_run.outcome.end_state == other_run.outcome.end_state &&
        properties(pruned_run.outcome) == properties(other_run.outcome)) {
      continue;
    }
    if (result.pruning_mismatches++ == 0) {
      auto describe = [&](const std::vector<LostBeacon>& lost) {
        std::string text;
        for (const LostBeacon& beacon : lost) text += fmt::format("[{}, {}, {}] ", beacon.round, beacon.from, beacon.to);
        return text;
      };
      result.first_mismatch = fmt::format("{}pruned at round {} as {}: they end {} ({} / {})", describe(pruned_run.lost),
                                          check.pruned.round, describe(other_run.lost),
                                          pruned_run.outcome.end_state == other_run.outcome.end_state
                                              ? "in the same state but break other properties"
                                              : "in different states",
                                          properties(pruned_run.outcome), properties(other_run.outcome));
    }
  }
  result.seconds = elapsed_s();
  return result;
}

}  // namespace syrof::lab::search
