// SwarmHost's end of a run (swarm_host.h): the qemu instances reaped, the
// faults judged, the checks, the output files (metrics.json, the replay read
// back, beacons.csv, firmware-swarm.json) and the summary.
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "syrof/firmware/swarm/swarm_host.h"
#include "syrof/lab/replay/reader.h"

namespace syrof::firmware::swarm {

namespace metrics = lab::metrics;
namespace replay = lab::replay;

int SwarmHost::Finish() {
  RunResult result;
  EndStress();
  result.ok = ReapRobots();
  std::vector<lab::sim::Lifecycle> final_presence;
  for (uint16_t i = 0; i < robots_; ++i) final_presence.push_back(loop_.player().lifecycle(i));
  result.report.faults = fault_outcomes_.Finish(final_presence);
  for (const swarm::FaultOutcome& outcome : result.report.faults) {
    if (options_.expect_faults && !outcome.ok) result.ok = false;
  }
  launcher_.RemoveSockets();
  channel_.CloseBaseStation();
  result.report.wall_seconds = static_cast<double>(HostNs() - start_ns_) * 1e-9;
  result.metrics = CollectMetrics(result.report.wall_seconds);
  ReadReplayBack(result);
  CheckEstimation(result);
  WriteMetrics(result);
  WriteBeacons(result);
  if (options_.expect_cooperative && !all_cooperative_s_) result.ok = false;
  if (result.metrics.common_knowledge.violations != 0) result.ok = false;
  if (activation_check_.figures().against_schedule != 0) result.ok = false;
  FillReport(result);
  WriteReport(result);
  PrintSummary(result);
  if (!result.ok && options_.stress.on()) {
    std::fprintf(stderr, "syrof-firmware-swarm: failed under stress seed %llu: rerun with  %s\n",
                 static_cast<unsigned long long>(options_.stress.seed), options_.command_line.c_str());
  }
  return result.ok ? 0 : 1;
}

// Waits for every qemu (killing one still running at the deadline) and
// keeps its exit status; false when one never started, ran past the
// deadline, exited badly or never reported, or printed a bad line.
bool SwarmHost::ReapRobots() {
  bool ok = true;
  for (uint16_t i = 0; i < robots_; ++i) {
    Robot& robot = swarm_[i];
    if (!robot.qemu.started()) continue;  // never launched: LaunchRobots failed
    // A crashed robot was killed (exit 137), perhaps before it reported or
    // even before it was switched on (a crash while waiting to join).
    const bool crashed = loop_.player().lifecycle(i) == lab::sim::Lifecycle::kCrashed;
    if (robot.console >= 0 || robot.radio >= 0) {  // the deadline passed
      robot.qemu.Kill();
      ok = false;
      std::fprintf(stderr, "robot %u: still running at the deadline\n", static_cast<unsigned>(i));
    }
    if (!robot.switched_on && !crashed) {  // a joiner whose time never came: killed at the end
      ok = false;
      std::fprintf(stderr, "robot %u: never switched on\n", static_cast<unsigned>(i));
    }
    const process::ExitStatus status = robot.qemu.Reap();
    robot.exit_status = status.exited() ? status.code : status.signaled() ? 128 + status.signal : -1;
    if (robot.switched_on && !crashed && (robot.exit_status != 0 || !robot.latest)) ok = false;
    if (robot.bad_lines > 0) ok = false;
  }
  return ok;
}

metrics::Metrics SwarmHost::CollectMetrics(double wall_s) {
  // The goal over the robots running at the end, as in every runtime (a
  // crashed or never-started robot used to count, and kept the goal from
  // being met).
  const lab::sim::RunEnd end{static_cast<double>(round_) * static_cast<double>(period_ns_) * 1e-9, wall_s, round_};
  lab::metrics::RunFacts facts = loop_.recorder().Facts(end, loop_.player(), loop_.world());
  // The image runs its compiled-in app, whatever the scenario's `app:` says:
  // its own name, as its held lines said it (NameImageApp), from the image.
  facts.app_name = image_app_;
  facts.app_source = options_.image;
  metrics::Metrics result = loop_.Finish(facts);
  // The robots' consoles do not carry the app's returns, so agreement stays
  // unset: metrics.json says null, not a measurement of nothing.
  result.runtime = "firmware";
  return result;
}

// The replay, then read back as the viewer reads it.
void SwarmHost::ReadReplayBack(RunResult& result) {
  loop_.recorder().FinishReplay();
  replay_file_.close();
  {
    std::ifstream in(options_.out + "/replay", std::ios::binary);
    replay::Reader reader(in);
    replay::Header header;
    replay::Round replay_round;
    if (reader.ReadHeader(header)) {
      while (reader.Next(replay_round)) ++result.report.replay_rounds;
    }
    if (!reader.complete()) result.replay_problem = reader.error().ToString();
  }
  if (!result.replay_problem.empty() || result.report.replay_rounds != round_) {
    std::fprintf(stderr, "syrof-firmware-swarm: %s/replay does not read back (%lld of %lld rounds): %s\n",
                 options_.out.c_str(), static_cast<long long>(result.report.replay_rounds), static_cast<long long>(round_),
                 result.replay_problem.c_str());
    result.ok = false;
  }
}

void SwarmHost::CheckEstimation(RunResult& result) const {
  const std::optional<double> max_error_m = result.metrics.estimation.max_error_m;
  if (options_.max_estimation_error_m &&
      (!max_error_m || result.metrics.estimation.samples == 0 || *max_error_m > *options_.max_estimation_error_m)) {
    std::fprintf(stderr, "syrof-firmware-swarm: largest estimation error %s m over %lld samples, above --max-estimation-error %g\n",
                 max_error_m ? std::to_string(*max_error_m).c_str() : "(none)",
                 static_cast<long long>(result.metrics.estimation.samples), *options_.max_estimation_error_m);
    result.ok = false;
  }
}

void SwarmHost::WriteMetrics(RunResult& result) const {
  std::ofstream metrics_file(options_.out + "/metrics.json");
  metrics_file << metrics::ToJson(result.metrics);
  if (!metrics_file.flush()) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot write %s/metrics.json\n", options_.out.c_str());
    result.ok = false;
  }
}

// beacons.csv: every beacon's arrival at the host.
void SwarmHost::WriteBeacons(RunResult& result) const {
  std::ofstream beacons_csv(options_.out + "/beacons.csv");
  beacons_csv << "robot,host_ms\n";
  for (uint16_t i = 0; i < robots_; ++i) {
    for (const int64_t t : swarm_[i].beacon_ns) beacons_csv << i << ',' << static_cast<double>(t - all_started_ns_) * 1e-6 << '\n';
  }
  if (!beacons_csv.flush()) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot write %s/beacons.csv\n", options_.out.c_str());
    result.ok = false;
  }
}

// The firmware's own figures of the run, as measured, beside those the
// earlier steps put in (wall time, faults, replay rounds).
void SwarmHost::FillReport(RunResult& result) const {
  swarm::FirmwareMetrics& report = result.report;
  const metrics::Metrics& run = result.metrics;
  report.robots = robots_;
  report.seconds = options_.seconds;
  report.loss = options_.loss;
  report.seed = options_.seed;
  report.align = *options_.align;
  report.latency_ms = options_.latency_ms;
  report.timing = timing_;
  report.all_cooperative_s = all_cooperative_s_;
  report.p3_violations = run.common_knowledge.violations;
  report.cooperative_starts = run.common_knowledge.cooperative_starts;
  report.activation = activation_check_.figures();
  report.beacons = channel_.counts();
  for (const Robot& robot : swarm_) {
    report.sensor_link.imu += robot.feed.counters().imu;
    report.sensor_link.flow += robot.feed.counters().flow;
    report.sensor_link.uwb += robot.feed.counters().uwb;
    report.sensor_link.not_encoded += robot.feed.counters().not_encoded;
    report.sensor_link.drives += robot.feed.counters().drives;
    report.sensor_link.rejected_from_robots += robot.feed.link_counters().rejected;
    report.exit_statuses.push_back(robot.exit_status);
  }
  report.scenario = scenario_.name;
  report.estimation = swarm::EstimationFigures{run.estimation.samples, run.estimation.position_rmse_m,
                                               run.estimation.max_error_m};
  report.partitioned_beacons = channel_.partitioned_beacons();
  if (options_.stress.on()) {
    report.stress = swarm::StressFigures{options_.stress.seed,          options_.stress.stalls_per_second,
                                         stress_.robot_stalls(),        stress_.world_stalls(),
                                         options_.stress.delayed_fraction, channel_.stress_late_beacons(),
                                         options_.stress.cpu_quota_permille};
  }
}

void SwarmHost::WriteReport(RunResult& result) const {
  std::ofstream file(options_.out + "/firmware-swarm.json");
  file << swarm::ToJson(result.report);
  if (!file.flush()) {
    std::fprintf(stderr, "syrof-firmware-swarm: cannot write %s/firmware-swarm.json\n", options_.out.c_str());
    result.ok = false;
  }
}

void SwarmHost::PrintSummary(const RunResult& result) const {
  const metrics::Metrics& run = result.metrics;
  const lab::metrics::SkewStats skew = run.round_start_skew.value_or(lab::metrics::SkewStats{});
  const swarm::SensorLinkCounts& sensor_totals = result.report.sensor_link;
  const swarm::BeaconCounts& beacons = result.report.beacons;
  const std::optional<double> max_error_m = run.estimation.max_error_m;
  const bool cooperative = all_cooperative_s_.has_value();
  std::printf("firmware swarm: %u robots, %d s, loss %.2f, seed %llu, timing %s, wall %.1f s\n",
              static_cast<unsigned>(robots_), options_.seconds, options_.loss,
              static_cast<unsigned long long>(options_.seed), timing_.c_str(), result.report.wall_seconds);
  std::printf("  all robots COOPERATIVE in one epoch: %s; COOPERATIVE starts %lld; P3 violations %lld\n",
              cooperative ? ("at " + std::to_string(*all_cooperative_s_) + " s").c_str() : "never",
              static_cast<long long>(run.common_knowledge.cooperative_starts),
              static_cast<long long>(run.common_knowledge.violations));
  std::printf("  round-start skew (spread of a round's beacon arrivals): p50 %.0f us, p99 %.0f us, max %.0f us "
              "over %lld rounds\n",
              skew.p50_us, skew.p99_us, skew.max_us, static_cast<long long>(skew.samples));
  std::printf("  beacons offered %lld, delivered %lld; radio-link errors %lld; %lld beacons reached the host past "
              "their delivery instant, %lld past their round\n",
              static_cast<long long>(beacons.offered), static_cast<long long>(beacons.delivered),
              static_cast<long long>(beacons.link_errors), static_cast<long long>(beacons.late),
              static_cast<long long>(beacons.past_their_round));
  std::printf("  scenario %s, app %s (the image's); sensor link: %lld IMU, %lld flow, %lld UWB frames sent, %lld drive "
              "commands back\n",
              scenario_.name.c_str(), image_app_.c_str(), static_cast<long long>(sensor_totals.imu),
              static_cast<long long>(sensor_totals.flow), static_cast<long long>(sensor_totals.uwb),
              static_cast<long long>(sensor_totals.drives));
  std::printf("  estimation error over %lld samples: RMSE %s m, max %s m; collisions %lld; goal %s (%s)\n",
              static_cast<long long>(run.estimation.samples),
              run.estimation.position_rmse_m ? std::to_string(*run.estimation.position_rmse_m).c_str() : "-",
              max_error_m ? std::to_string(*max_error_m).c_str() : "-",
              static_cast<long long>(run.collisions.count), run.goal.reached ? "reached" : "not reached",
              run.goal.detail.c_str());
  std::printf("  %s/replay: %lld rounds%s\n", options_.out.c_str(), static_cast<long long>(result.report.replay_rounds),
              result.replay_problem.empty() ? "" : (", " + result.replay_problem).c_str());
  if (options_.stress.on()) {
    std::printf("  stress seed %llu: %lld qemu stalls, %lld host stalls, %lld beacons late%s (rerun: --stress %llu)\n",
                static_cast<unsigned long long>(options_.stress.seed), static_cast<long long>(stress_.robot_stalls()),
                static_cast<long long>(stress_.world_stalls()), static_cast<long long>(channel_.stress_late_beacons()),
                launcher_.cpu_quota() ? (", qemu at " + std::to_string(options_.stress.cpu_quota_permille) + " per mille of a core").c_str() : "",
                static_cast<unsigned long long>(options_.stress.seed));
  }
  const swarm::ActivationFigures& activation = result.report.activation;
  if (activation.model != "fsync" || activation.against_schedule != 0) {
    std::printf("  activation %s: the robots looked at %lld of %lld epoch starts; %s\n", activation.model.c_str(),
                static_cast<long long>(activation.looked), static_cast<long long>(activation.starts),
                activation.against_schedule == 0
                    ? "each as its schedule says"
                    : ("FAILED: " + std::to_string(activation.against_schedule) + " against the schedule, first: " +
                       activation.first_difference)
                          .c_str());
  }
  for (uint16_t i = 0; i < robots_; ++i) {
    std::printf("  robot %u: exit %d, %s\n", static_cast<unsigned>(i), swarm_[i].exit_status,
                swarm_[i].last_status.c_str());
  }
  for (const swarm::FaultOutcome& outcome : result.report.faults) {
    std::printf("  fault: %s: %s\n", outcome.ok ? "ok" : (options_.expect_faults ? "FAILED" : "not seen"),
                outcome.detail.c_str());
  }
  std::printf("  %s/metrics.json, %s/firmware-swarm.json: %s\n", options_.out.c_str(), options_.out.c_str(),
              result.ok ? "ok" : "FAILED");
}

}  // namespace syrof::firmware::swarm
