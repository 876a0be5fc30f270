#include "run_summary.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

namespace syrof::cli {

namespace metrics = lab::metrics;

namespace {

// A measured value with `decimals`; "-" when it is undefined (no samples,
// or not finite).
std::string Number(double value, int decimals) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, decimals) : std::string("-");
}

std::string Number(const std::optional<double>& value, int decimals) {
  return value ? Number(*value, decimals) : std::string("-");
}

// "first robot 2, epoch 3: what" for an incident's first occurrence.
std::string FirstIncident(const metrics::AppIncidents& incidents) {
  if (!incidents.first) return "first unknown";
  return fmt::format("first robot {}, epoch {}: {}", incidents.first->robot, incidents.first->epoch,
                     incidents.first->what);
}

// The app's lines: one when it behaved, a warning and the first occurrence
// of each kind of misbehaviour otherwise.
void PrintAppLines(std::ostream& out, const metrics::Metrics& m) {
  if (!AppMisbehaved(m)) {
    fmt::print(out, "  {:<17} {}: no faults, no invalid commands, no refused payloads\n", "app", m.app.name);
    return;
  }
  fmt::print(out, "  {:<17} {}: WARNING: the app misbehaved (see app in metrics.json; --strict exits 3)\n", "app",
             m.app.name);
  if (!m.app.faults.empty()) {
    const metrics::AppFault& first = m.app.faults.front();
    fmt::print(out, "    {:<17} {} in all; first robot {}, {} of epoch {} at {:.3f} s: {}{}\n", "faults",
               m.app.faults.size(), first.robot, first.callback, first.epoch, static_cast<double>(first.time_ns) / 1e9,
               first.verdict, first.detail.empty() ? "" : " (" + first.detail + ")");
  }
  if (const int64_t count = m.app.invalid_commands.count; count > 0) {
    fmt::print(out, "    {:<17} {} in all, each replaced by STOP; {}\n", "invalid commands", count,
               FirstIncident(m.app.invalid_commands));
  }
  if (const int64_t count = m.app.payload_refused.count; count > 0) {
    fmt::print(out, "    {:<17} {} in all (over 9 bytes); {}\n", "refused payloads", count,
               FirstIncident(m.app.payload_refused));
  }
}

void PrintAgreementLine(std::ostream& out, const metrics::Metrics& m) {
  if (!m.agreement) {
    fmt::print(out, "  {:<17} not measured (the {} runtime does not see the app's returns)\n", "agreement", m.runtime);
    return;
  }
  const metrics::AgreementMetrics& agreement = *m.agreement;
  fmt::print(out, "  {:<17} the app's global state agreed in {} of {} COOPERATIVE epochs{}\n", "agreement",
             agreement.agreed_epochs, agreement.cooperative_epochs,
             agreement.first_disagreement ? fmt::format(" (first disagreement: epoch {}, robot {})",
                                                        agreement.first_disagreement->epoch,
                                                        agreement.first_disagreement->robot)
                                          : std::string());
}

// Real clocks (docs/clocks.md): how long until every pair of members stayed
// within the threshold, and the phase error left after that.
void PrintRoundPhaseLine(std::ostream& out, const metrics::RoundPhaseMetrics& phase) {
  fmt::print(out, "  {:<17} {}, phase error after that p99 {} ms, max {} ms\n", "round phase",
             phase.converged_s ? fmt::format("aligned within {} ms after {:.2f} s", Number(phase.threshold_ms, 1),
                                             *phase.converged_s)
                               : "never aligned within " + Number(phase.threshold_ms, 1) + " ms",
             Number(phase.residual.p99_ms, 3), Number(phase.residual.max_ms, 3));
}

}  // namespace

bool AppMisbehaved(const metrics::Metrics& m) {
  return !m.app.faults.empty() || m.app.invalid_commands.count > 0 || m.app.payload_refused.count > 0;
}

void PrintSummary(std::ostream& out, const metrics::Metrics& m, const std::filesystem::path& dir, bool replay,
                  bool library, bool html, bool clocks, std::string_view title) {
  fmt::print(out, "\n{}: {} ({}), {} robots, seed {}\n", title, m.scenario, m.app.source, m.robots, m.seed);
  if (m.wall_seconds > 0) {
    fmt::print(out, "  {:<17} {:.1f} s ({} radio rounds) in {:.2f} s wall, {:.0f}x real time\n", "simulated",
               m.sim_seconds, m.radio_rounds, m.wall_seconds, m.sim_seconds / m.wall_seconds);
  } else {
    fmt::print(out, "  {:<17} {:.1f} s ({} radio rounds)\n", "simulated", m.sim_seconds, m.radio_rounds);
  }
  fmt::print(out, "  {:<17} {} epochs, start skew max {} rounds ({} ms)\n", "synchrony", m.epochs_started,
             m.synchrony.max_start_skew_rounds, Number(m.synchrony.max_start_skew_ms, 1));
  if (m.activation) {
    const metrics::ActivationMetrics& activation = *m.activation;
    if (activation.async) {
      // A look starts a cycle; the move may start and end epochs later.
      const metrics::AsyncActivationMetrics& async = *activation.async;
      fmt::print(out,
                 "  {:<17} async {} (delays up to {} epochs{}): {} of {} robot-epoch starts looked, every robot within "
                 "{} epochs; {} robot-epochs moving, {} on a stale look, {} moves cut\n",
                 "activation", activation.schedule, async.max_delay_epochs,
                 async.min_move_m > 0 ? fmt::format(", non-rigid {} m", Number(async.min_move_m, 3)) : std::string(),
                 activation.active_starts, activation.active_starts + activation.inactive_starts,
                 activation.fair_within_achieved, async.move_epochs, async.stale_move_epochs, async.moves_cut);
    } else {
      fmt::print(out, "  {:<17} {} {}{}: {} of {} robot-epoch starts active, fair within {} epochs\n", "activation",
                 activation.model, activation.schedule,
                 activation.fair_within ? fmt::format(" (bound {})", *activation.fair_within) : std::string(),
                 activation.active_starts, activation.active_starts + activation.inactive_starts,
                 activation.fair_within_achieved);
    }
  }
  const std::optional<double>& fraction = m.common_knowledge.cooperative_fraction;
  fmt::print(out, "  {:<17} {} P3 violations, {} COOPERATIVE starts, mode disagreement max {} rounds\n",
             "common knowledge", m.common_knowledge.violations,
             fraction ? fmt::format("{:.1f}%", 100.0 * *fraction) : std::string("-"),
             m.common_knowledge.max_mode_disagreement_rounds);
  fmt::print(out, "  {:<17} {} (min separation {} m), wall contacts {}\n", "collisions", m.collisions.count,
             Number(m.collisions.min_separation_m, 3), m.walls.contacts);
  if (!m.safety.enabled) {
    fmt::print(out, "  {:<17} off (safety: off in the scenario)\n", "safety");
  } else {
    fmt::print(out, "  {:<17} {} interventions on {} robots, {} precautions, {} join waits\n", "safety",
               m.safety.interventions, m.safety.robots_involved, m.safety.precautions, m.safety.join_waits);
  }
  // A joiner that never joined is otherwise only a count above and a goal
  // reason about where it is not.
  for (const std::string& line : metrics::UnjoinedJoiners(m)) fmt::print(out, "    {}\n", line);
  PrintAgreementLine(out, m);
  fmt::print(out, "  {:<17} position RMSE {} m, max {} m\n", "estimation", Number(m.estimation.position_rmse_m, 3),
             Number(m.estimation.max_error_m, 3));
  // Joins are robots that became members; each observer's notice of one is
  // a join notice (one joiner seen by 12 robots: 1 join, 12 notices).
  fmt::print(out, "  {:<17} {} removals, {} join{} ({} join notices)\n", "membership", m.membership.removals,
             m.membership.completed_joins, m.membership.completed_joins == 1 ? "" : "s", m.membership.joins);
  if (clocks) PrintRoundPhaseLine(out, m.round_phase);
  if (library && m.goal.source != "scenario") {
    fmt::print(out, "  {:<17} none: declare checks under goal: in the scenario (docs/scenarios.md)\n", "goal");
  } else {
    fmt::print(out, "  {:<17} {} ({})\n", "goal", m.goal.reached ? "reached" : "NOT reached", m.goal.detail);
  }
  PrintAppLines(out, m);
  fmt::print(out, "  {:<17} {}{}{}{}\n", "outputs", (dir / "metrics.json").string(),
             replay ? ", " + (dir / "replay").string() : std::string(),
             library ? ", " + (dir / "robots").string() + "/<id>.log" : std::string(),
             html ? ", " + (dir / "replay.html").string() : std::string());
}

}  // namespace syrof::cli
