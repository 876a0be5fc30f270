#include "run_summary.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cstdint>
#include <string>

namespace syrof::cli {

std::string Number(const nlohmann::json& value, int decimals) {
  if (value.is_null()) return "-";
  if (value.is_number_integer()) return std::to_string(value.get<int64_t>());
  return fmt::format("{:.{}f}", value.get<double>(), decimals);
}

namespace {

const nlohmann::json& Field(const nlohmann::json& json, const char* object, const char* key) {
  static const nlohmann::json kNull;
  if (!json.contains(object) || !json[object].contains(key)) return kNull;
  return json[object][key];
}

// `json[key]`, or null when `json` is no object or has no such key.
const nlohmann::json& Member(const nlohmann::json& json, const char* key) {
  static const nlohmann::json kNull;
  if (!json.is_object() || !json.contains(key)) return kNull;
  return json[key];
}

std::string Text(const nlohmann::json& json, const char* key) {
  const nlohmann::json& value = Member(json, key);
  return value.is_string() ? value.get<std::string>() : std::string();
}

// How many incidents of one kind metrics.json's app object counts.
int64_t IncidentCount(const nlohmann::json& m, const char* kind) {
  const nlohmann::json& count = Member(Field(m, "app", kind), "count");
  return count.is_number_integer() ? count.get<int64_t>() : 0;
}

// Whether metrics.json's app object reports any misbehaviour.
bool AppMisbehavedIn(const nlohmann::json& m) {
  const nlohmann::json& faults = Field(m, "app", "faults");
  return (faults.is_array() && !faults.empty()) || IncidentCount(m, "invalid_commands") > 0 ||
         IncidentCount(m, "payload_refused") > 0;
}

// "first robot 2, epoch 3: what" for an incident's first occurrence.
std::string FirstIncident(const nlohmann::json& incidents) {
  const nlohmann::json& first = Member(incidents, "first");
  if (!first.is_object()) return "first unknown";
  return fmt::format("first robot {}, epoch {}: {}", Number(Member(first, "robot"), 0),
                     Number(Member(first, "epoch"), 0), Text(first, "what"));
}

// The app's lines: one when it behaved, a warning and the first occurrence
// of each kind of misbehaviour otherwise.
void PrintAppLines(std::ostream& out, const nlohmann::json& m) {
  const std::string name = Text(Member(m, "app"), "name");
  if (!AppMisbehaved(m)) {
    fmt::print(out, "  {:<17} {}: no faults, no invalid commands, no refused payloads\n", "app", name);
    return;
  }
  fmt::print(out, "  {:<17} {}: WARNING: the app misbehaved (see app in metrics.json; --strict exits 3)\n", "app",
             name);
  const nlohmann::json& faults = Field(m, "app", "faults");
  if (faults.is_array() && !faults.empty()) {
    const nlohmann::json& first = faults[0];
    const std::string detail = Text(first, "detail");
    fmt::print(out, "    {:<17} {} in all; first robot {}, {} of epoch {} at {} s: {}{}\n", "faults", faults.size(),
               Number(Member(first, "robot"), 0), Text(first, "callback"), Number(Member(first, "epoch"), 0),
               Number(Member(first, "time_s"), 3), Text(first, "verdict"), detail.empty() ? "" : " (" + detail + ")");
  }
  if (const int64_t count = IncidentCount(m, "invalid_commands"); count > 0) {
    fmt::print(out, "    {:<17} {} in all, each replaced by STOP; {}\n", "invalid commands", count,
               FirstIncident(Field(m, "app", "invalid_commands")));
  }
  if (const int64_t count = IncidentCount(m, "payload_refused"); count > 0) {
    fmt::print(out, "    {:<17} {} in all (over 9 bytes); {}\n", "refused payloads", count,
               FirstIncident(Field(m, "app", "payload_refused")));
  }
}

}  // namespace

bool AppMisbehaved(const nlohmann::json& m) { return AppMisbehavedIn(m); }

void PrintSummary(std::ostream& out, const nlohmann::json& m, const std::filesystem::path& dir, bool replay,
                  bool library, bool html, bool clocks, std::string_view title) {
  const double sim = m.value("sim_seconds", 0.0);
  const double wall = m.value("wall_seconds", 0.0);
  fmt::print(out, "\n{}: {} ({}), {} robots, seed {}\n", title, m.value("scenario", std::string()),
             Field(m, "app", "source").is_string() ? Field(m, "app", "source").get<std::string>() : std::string(),
             m.value("robots", 0), m.value("seed", uint64_t{0}));
  if (wall > 0) {
    fmt::print(out, "  {:<17} {:.1f} s ({} radio rounds) in {:.2f} s wall, {:.0f}x real time\n", "simulated", sim,
               m.value("radio_rounds", int64_t{0}), wall, sim / wall);
  } else {
    fmt::print(out, "  {:<17} {:.1f} s ({} radio rounds)\n", "simulated", sim, m.value("radio_rounds", int64_t{0}));
  }
  fmt::print(out, "  {:<17} {} epochs, start skew max {} rounds ({} ms)\n", "synchrony", Number(m["epochs_started"], 0),
             Number(Field(m, "synchrony", "max_start_skew_rounds"), 0),
             Number(Field(m, "synchrony", "max_start_skew_ms"), 1));
  const nlohmann::json& fraction = Field(m, "common_knowledge", "cooperative_fraction");
  fmt::print(out, "  {:<17} {} P3 violations, {} COOPERATIVE starts, mode disagreement max {} rounds\n",
             "common knowledge", Number(Field(m, "common_knowledge", "violations"), 0),
             fraction.is_null() ? std::string("-") : fmt::format("{:.1f}%", 100.0 * fraction.get<double>()),
             Number(Field(m, "common_knowledge", "max_mode_disagreement_rounds"), 0));
  fmt::print(out, "  {:<17} {} (min separation {} m), wall contacts {}\n", "collisions",
             Number(Field(m, "collisions", "count"), 0), Number(Field(m, "collisions", "min_separation_m"), 3),
             Number(Field(m, "walls", "contacts"), 0));
  const nlohmann::json& safety = Field(m, "safety", "enabled");
  if (safety.is_boolean() && !safety.get<bool>()) {
    fmt::print(out, "  {:<17} off (safety: off in the scenario)\n", "safety");
  } else if (safety.is_boolean()) {
    fmt::print(out, "  {:<17} {} interventions on {} robots, {} join waits\n", "safety",
               Number(Field(m, "safety", "interventions"), 0), Number(Field(m, "safety", "robots_involved"), 0),
               Number(Field(m, "safety", "join_waits"), 0));
  }
  const nlohmann::json& agreed = Field(m, "agreement", "agreed_epochs");
  if (agreed.is_number()) {
    const nlohmann::json& first = Field(m, "agreement", "first_disagreement");
    fmt::print(out, "  {:<17} the app's global state agreed in {} of {} COOPERATIVE epochs{}\n", "agreement",
               Number(agreed, 0), Number(Field(m, "agreement", "cooperative_epochs"), 0),
               first.is_object() ? fmt::format(" (first disagreement: epoch {}, robot {})", Number(first["epoch"], 0),
                                               Number(first["robot"], 0))
                                 : std::string());
  }
  fmt::print(out, "  {:<17} position RMSE {} m, max {} m\n", "estimation",
             Number(Field(m, "estimation", "position_rmse_m"), 3), Number(Field(m, "estimation", "max_error_m"), 3));
  fmt::print(out, "  {:<17} {} removals, {} joins\n", "membership", Number(Field(m, "membership", "removals"), 0),
             Number(Field(m, "membership", "joins"), 0));
  if (const nlohmann::json& phase = m.contains("round_phase") ? m["round_phase"] : nlohmann::json();
      clocks && phase.is_object() && phase.contains("residual") && phase["residual"].is_object()) {
    // Real clocks (docs/clocks.md): how long until every pair of members
    // stayed within the threshold, and the phase error left after that.
    const nlohmann::json& converged = phase.contains("converged_s") ? phase["converged_s"] : nlohmann::json();
    fmt::print(out, "  {:<17} {}, phase error after that p99 {} ms, max {} ms\n", "round phase",
               converged.is_number() ? fmt::format("aligned within {} ms after {:.2f} s", Number(phase["threshold_ms"], 1),
                                                   converged.get<double>())
                                     : std::string("never aligned within ") + Number(phase["threshold_ms"], 1) + " ms",
               Number(phase["residual"]["p99_ms"], 3), Number(phase["residual"]["max_ms"], 3));
  }
  const bool declared_goal = m.contains("goal") && m["goal"].is_object() && m["goal"].value("source", "") == "scenario";
  if (library && !declared_goal) {
    fmt::print(out, "  {:<17} none: declare checks under goal: in the scenario (docs/scenarios.md)\n", "goal");
  } else if (m.contains("goal")) {
    const nlohmann::json& goal = m["goal"];
    fmt::print(out, "  {:<17} {} ({})\n", "goal", goal.value("reached", false) ? "reached" : "NOT reached",
               goal.value("detail", std::string()));
  }
  PrintAppLines(out, m);
  fmt::print(out, "  {:<17} {}{}{}{}\n", "outputs", (dir / "metrics.json").string(),
             replay ? ", " + (dir / "replay").string() : std::string(),
             library ? ", " + (dir / "robots").string() + "/<id>.log" : std::string(),
             html ? ", " + (dir / "replay.html").string() : std::string());
}

}  // namespace syrof::cli
