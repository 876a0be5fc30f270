// The estimator's consistency where the safety filter relies on it
// (docs/safety.md, "What the estimate says of itself"; docs/estimation.md,
// "In the lab"): scenario files run over seeds in the lab, and at the end
// of every radio round, for every robot that is driving (its body active,
// its estimate initialized), the true position error against
//   - the EKF's own covariance: position NEES e^T P^-1 e (expected 2, the
//     dimension) and pose NEES over x, y and heading (expected 3);
//   - the margin the safety filter used for it: OwnErrorAllowanceM of the
//     estimate the robot's tasks published (motion::SafetyConfig of the
//     robot), and the share of robot-rounds whose error exceeds it; also for
//     the robot-rounds within 0.3 m of another body (where a wrong estimate
//     can turn into a contact);
//   - the multiple of the estimate's own sigma that the true error reached
//     in 99.9% of robot-rounds (what own_sigmas would have to be for the
//     margin to cover it there, ignoring the floor of half the margin).
// Per kind (omni, rover), with each run's collisions, interventions, precautions and the
// time from which the goal held to the end (judged every radio round on the
// true poses, as the run's metrics judge the final ones). Deterministic: the
// runs are seeded; the table regenerates exactly.
//
// Usage: bench_lab_margin_coverage [--seeds N] [--first S] [--duration S] [--jobs J] [--own-sigmas K] [--list] FILE...
//   --seeds N      seeds S .. S+N-1 (default 20, first 1)
//   --duration S   cap every run at S simulated seconds (default: the file's)
//   --jobs J       runs side by side on J threads (default 1)
//   --own-sigmas K every robot's SafetyConfig::own_sigmas (default: the lab's),
//                  to compare margin rules on the same runs
//   --list         one line per run (collisions with their time and pair)
#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "syrof/estimation/state.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/run_parts.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/motion/safety_filter.h"

namespace {

using namespace syrof;
using namespace syrof::lab;

constexpr double kNearGapM = 0.3;  // surface gap to the nearest other body
constexpr int kKinds = 3;          // world::RobotKind's values: omni, rover, drone
const char* const kKindNames[kKinds] = {"omni", "rover", "drone"};

struct KindStats {
  int64_t robot_rounds = 0;
  double nees_position_sum = 0;
  double nees_pose_sum = 0;
  int64_t beyond_allowance = 0;
  int64_t near_rounds = 0;
  int64_t near_beyond_allowance = 0;
  double max_error_m = 0;
  double squared_error_sum_m2 = 0;      // for the position RMSE
  std::vector<float> error_over_sigma;  // |e| / max(sigma_x, sigma_y)

  void Add(const KindStats& other) {
    robot_rounds += other.robot_rounds;
    nees_position_sum += other.nees_position_sum;
    nees_pose_sum += other.nees_pose_sum;
    beyond_allowance += other.beyond_allowance;
    near_rounds += other.near_rounds;
    near_beyond_allowance += other.near_beyond_allowance;
    max_error_m = std::max(max_error_m, other.max_error_m);
    squared_error_sum_m2 += other.squared_error_sum_m2;
    error_over_sigma.insert(error_over_sigma.end(), other.error_over_sigma.begin(), other.error_over_sigma.end());
  }
};

struct RunResult {
  std::string file;
  uint64_t seed = 0;
  std::array<KindStats, kKinds> kinds;
  int64_t collisions = 0;
  std::vector<metrics::CollisionEvent> pairs;
  int64_t interventions = 0;
  int64_t precautions = 0;
  bool goal_reached = false;
  double goal_since_s = 0;  // the goal held from this time to the end (when reached)
};

double WrapAngle(double angle) {
  while (angle > M_PI) angle -= 2 * M_PI;
  while (angle < -M_PI) angle += 2 * M_PI;
  return angle;
}

// One robot-round: the true pose against the robot's estimator.
void Sample(const sim::Simulation& simulation, uint16_t id, KindStats& stats) {
  const runtime::Robot& robot = simulation.robot(id);
  const world::World& world = simulation.world();
  if (world.presence(id) != world::BodyPresence::kActive || !robot.estimate_valid()) return;
  const world::BodyState& truth = world.state(id);
  // What the safety filter used: the published estimate and its sigmas.
  const estimation::StateEstimate& estimate = robot.estimate();
  const double ex = truth.x_m - estimate.x_m;
  const double ey = truth.y_m - estimate.y_m;
  const double error_m = std::hypot(ex, ey);
  const double allowance_m = motion::OwnErrorAllowanceM(robot.config().safety, estimate);
  const double sigma_m = std::max(estimate.sigma_x_m, estimate.sigma_y_m);
  // NEES from the filter's own state and covariance (the newest).
  const auto& filter = robot.estimator().filter();
  const auto& state = filter.state();
  const auto& covariance = filter.covariance();
  Eigen::Vector3d e(truth.x_m - state(estimation::kStateX), truth.y_m - state(estimation::kStateY),
                    WrapAngle(truth.heading_rad - state(estimation::kStateHeading)));
  Eigen::Matrix3d p;
  const int index[3] = {estimation::kStateX, estimation::kStateY, estimation::kStateHeading};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) p(r, c) = covariance(index[r], index[c]);
  }
  const Eigen::Vector2d e2 = e.head<2>();
  const double nees_position = e2.dot(p.topLeftCorner<2, 2>().ldlt().solve(e2));
  const double nees_pose = e.dot(p.ldlt().solve(e));

  double nearest_gap_m = 1e9;
  for (uint16_t other = 0; other < world.size(); ++other) {
    if (other == id || world.presence(other) == world::BodyPresence::kAbsent) continue;
    const world::BodyState& body = world.state(other);
    nearest_gap_m = std::min(nearest_gap_m, std::hypot(body.x_m - truth.x_m, body.y_m - truth.y_m) -
                                                world.body_radius_m(id) - world.body_radius_m(other));
  }
  ++stats.robot_rounds;
  stats.nees_position_sum += nees_position;
  stats.nees_pose_sum += nees_pose;
  const bool beyond = error_m > allowance_m;
  stats.beyond_allowance += beyond ? 1 : 0;
  if (nearest_gap_m < kNearGapM) {
    ++stats.near_rounds;
    stats.near_beyond_allowance += beyond ? 1 : 0;
  }
  stats.max_error_m = std::max(stats.max_error_m, error_m);
  stats.squared_error_sum_m2 += error_m * error_m;
  if (sigma_m > 0) stats.error_over_sigma.push_back(static_cast<float>(error_m / sigma_m));
}

RunResult RunOne(const std::string& file, uint64_t seed, double duration_s, float own_sigmas) {
  scenario::Overrides overrides;
  overrides.seed = seed;
  if (duration_s > 0) overrides.duration_s = duration_s;
  const scenario::LoadResult loaded = scenario::LoadScenarioFile(file, overrides);
  if (!loaded.ok()) {
    fmt::print(stderr, "{}\n", loaded.error->ToString());
    std::exit(2);
  }
  const scenario::Scenario& scenario = *loaded.scenario;
  RunResult result;
  result.file = file;
  result.seed = seed;
  sim::SimulationOptions options;
  if (own_sigmas > 0) {
    options.configure_robot = [own_sigmas](runtime::RobotConfig& config) { config.safety.own_sigmas = own_sigmas; };
  }
  sim::Simulation simulation(scenario, options);
  const bool builtin_goal = scenario.goal.empty();
  const double round_s = scenario.timing.radio_round_s;
  const auto rounds = static_cast<int64_t>(std::floor(scenario.timing.duration_s / round_s + 1e-9));
  bool held = false;
  for (int64_t round = 1; round <= rounds; ++round) {
    const double now_s = static_cast<double>(round) * round_s;
    simulation.RunUntil(now_s);
    for (uint16_t id = 0; id < simulation.robot_count(); ++id) {
      const int kind = static_cast<int>(scenario.robots[id].kind);
      Sample(simulation, id, result.kinds[kind]);
    }
    if (builtin_goal) {
      std::vector<apps::GoalPose> poses;
      const world::World& world = simulation.world();
      for (uint16_t id = 0; id < world.size(); ++id) {
        const world::BodyState& body = world.state(id);
        poses.push_back(apps::GoalPose{id, body.x_m, body.y_m, body.heading_rad,
                                       world.presence(id) == world::BodyPresence::kActive, world.body_radius_m(id)});
      }
      const bool reached = sim::BuiltinGoal(scenario, poses).reached;
      if (reached && !held) result.goal_since_s = now_s;
      held = reached;
    }
  }
  const sim::RunReport report = simulation.Finish(0.0);
  result.collisions = report.metrics.collisions.count;
  result.pairs = report.metrics.collisions.pairs;
  result.interventions = report.metrics.safety.interventions;
  result.precautions = report.metrics.safety.precautions;
  result.goal_reached = report.metrics.goal.reached;
  if (!builtin_goal || !held) result.goal_since_s = report.metrics.goal.reached ? scenario.timing.duration_s : 0;
  return result;
}

// The multiple of sigma that the error stayed within in `share` of the samples.
double Quantile(std::vector<float> values, double share) {
  if (values.empty()) return 0;
  const auto at = static_cast<size_t>(std::min<double>(values.size() - 1, std::ceil(share * values.size()) - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at), values.end());
  return values[at];
}

std::string Percent(int64_t part, int64_t whole) {
  return whole == 0 ? "-" : fmt::format("{:.3f} %", 100.0 * static_cast<double>(part) / static_cast<double>(whole));
}

std::string BaseName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t dot = name.rfind('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 20;
  uint64_t first = 1;
  double duration_s = 0;
  int jobs = 1;
  bool list = false;
  float own_sigmas = 0;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        fmt::print(stderr, "{} needs a value\n", arg);
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--seeds") {
      seeds = std::atoi(value().c_str());
    } else if (arg == "--first") {
      first = std::strtoull(value().c_str(), nullptr, 10);
    } else if (arg == "--duration") {
      duration_s = std::atof(value().c_str());
    } else if (arg == "--jobs") {
      jobs = std::max(1, std::atoi(value().c_str()));
    } else if (arg == "--own-sigmas") {
      own_sigmas = static_cast<float>(std::atof(value().c_str()));
    } else if (arg == "--list") {
      list = true;
    } else if (!arg.empty() && arg[0] == '-') {
      fmt::print(stderr, "unknown option {}\n", arg);
      return 2;
    } else {
      files.push_back(arg);
    }
  }
  if (files.empty() || seeds < 1) {
    fmt::print(stderr,
               "usage: bench_lab_margin_coverage [--seeds N] [--first S] [--duration S] [--jobs J] [--own-sigmas K] [--list] FILE...\n");
    return 2;
  }

  struct Job {
    size_t file;
    uint64_t seed;
  };
  std::vector<Job> work;
  for (size_t f = 0; f < files.size(); ++f) {
    for (int s = 0; s < seeds; ++s) work.push_back(Job{f, first + static_cast<uint64_t>(s)});
  }
  std::vector<RunResult> results(work.size());
  std::atomic<size_t> next{0};
  const auto worker = [&]() {
    for (size_t i = next++; i < work.size(); i = next++) results[i] = RunOne(files[work[i].file], work[i].seed, duration_s, own_sigmas);
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < jobs; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& thread : threads) thread.join();

  if (list) {
    for (const RunResult& r : results) {
      std::string pairs;
      for (const metrics::CollisionEvent& c : r.pairs) {
        pairs += fmt::format(" {}-{}@{:.2f}s", c.a, c.b, static_cast<double>(c.time_ns) * 1e-9);
      }
      fmt::print("{} seed {}: collisions {}{}, interventions {}, precautions {}, goal {}\n", BaseName(r.file), r.seed,
                 r.collisions, pairs, r.interventions, r.precautions,
                 r.goal_reached ? fmt::format("from {:.2f} s", r.goal_since_s) : "missed");
    }
    fmt::print("\n");
  }

  if (own_sigmas > 0) fmt::print("own_sigmas {}\n", own_sigmas);
  fmt::print("seeds {} .. {}{}; robot-rounds of driving robots with an initialized estimate\n\n", first,
             first + static_cast<uint64_t>(seeds) - 1,
             duration_s > 0 ? fmt::format(", runs capped at {} s", duration_s) : "");
  fmt::print(
      "| scenario | kind | robot-rounds | NEES x,y (2) | NEES x,y,heading (3) | error > allowance | near: error > "
      "allowance | 99.9 % of error / sigma | max error (m) | collisions | goal (runs) | goal from (s, mean) | "
      "interventions | precautions |\n");
  fmt::print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  std::array<KindStats, kKinds> total;
  int64_t total_collisions = 0;
  for (size_t f = 0; f < files.size(); ++f) {
    std::array<KindStats, kKinds> kinds;
    int64_t collisions = 0, interventions = 0, precautions = 0, goals = 0;
    double goal_sum_s = 0;
    for (size_t i = 0; i < work.size(); ++i) {
      if (work[i].file != f) continue;
      const RunResult& r = results[i];
      for (int k = 0; k < kKinds; ++k) kinds[k].Add(r.kinds[k]);
      collisions += r.collisions;
      interventions += r.interventions;
      precautions += r.precautions;
      if (r.goal_reached) {
        ++goals;
        goal_sum_s += r.goal_since_s;
      }
    }
    total_collisions += collisions;
    bool first_row = true;
    for (int k = 0; k < kKinds; ++k) {
      const KindStats& s = kinds[k];
      if (s.robot_rounds == 0) continue;
      total[k].Add(s);
      const double n = static_cast<double>(s.robot_rounds);
      const std::string run_columns =
          first_row ? fmt::format("{} | {} / {} | {} | {} | {}", collisions, goals, seeds,
                                  goals == 0 ? std::string("-") : fmt::format("{:.2f}", goal_sum_s / goals), interventions,
                                  precautions)
                    : " | | | |";
      fmt::print("| {} | {} | {} | {:.2f} | {:.2f} | {} | {} of {} | {:.2f} | {:.3f} | {} |\n", BaseName(files[f]),
                 kKindNames[k], s.robot_rounds, s.nees_position_sum / n, s.nees_pose_sum / n,
                 Percent(s.beyond_allowance, s.robot_rounds), Percent(s.near_beyond_allowance, s.near_rounds),
                 s.near_rounds, Quantile(s.error_over_sigma, 0.999), s.max_error_m, run_columns);
      first_row = false;
    }
  }
  // The position RMSE of the published estimate, per kind, over every file.
  for (int k = 0; k < kKinds; ++k) {
    const KindStats& s = total[k];
    if (s.robot_rounds == 0) continue;
    fmt::print("position RMSE, {}: {:.4f} m over {} robot-rounds (max {:.3f} m)\n", kKindNames[k],
               std::sqrt(s.squared_error_sum_m2 / static_cast<double>(s.robot_rounds)), s.robot_rounds, s.max_error_m);
  }
  if (files.size() > 1) {
    for (int k = 0; k < kKinds; ++k) {
      const KindStats& s = total[k];
      if (s.robot_rounds == 0) continue;
      const double n = static_cast<double>(s.robot_rounds);
      fmt::print("| all | {} | {} | {:.2f} | {:.2f} | {} | {} of {} | {:.2f} | {:.3f} | {} | | | |\n", kKindNames[k],
                 s.robot_rounds, s.nees_position_sum / n, s.nees_pose_sum / n,
                 Percent(s.beyond_allowance, s.robot_rounds), Percent(s.near_beyond_allowance, s.near_rounds),
                 s.near_rounds, Quantile(s.error_over_sigma, 0.999), s.max_error_m, k == 0 ? total_collisions : 0);
    }
  }
  return 0;
}
