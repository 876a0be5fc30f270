#include "syrof/lab/scenario/fits_the_image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "syrof/estimation/arena.h"
#include "syrof/estimation/estimator_config.h"
#include "syrof/lab/world/arena.h"
#include "syrof/motion/robot_kind.h"
#include "syrof/registry/tasks.h"
#include "syrof/runtime/robot.h"
#include "syrof/sync/config.h"
#include "syrof/wire/beacon_layout.h"

namespace syrof::lab::scenario {

namespace {

// What differs from the image, or nothing. The radio round the image's
// tasks run on (robot_image.cpp).
std::optional<std::string> RadioRoundDiffers(const Scenario& scenario) {
  if (std::llround(scenario.timing.radio_round_s * 1e9) == registry::kDefaultRadioRoundNs) return std::nullopt;
  return "timing.radio_round_s must be 0.05 (the robot image's radio round)";
}

// The synchronizer's timing the image runs: runtime::RobotConfig's default
// PROGRESS and sync::SyncConfig::ForSwarm's K and F (robot_image.cpp sets
// none of them and no boot word or block field carries them). Compared once
// the radio round is the image's, so app_round_s counts in its rounds.
std::optional<std::string> SyncTimingDiffers(const Scenario& scenario) {
  const TimingSpec& timing = scenario.timing;
  const sync::SyncConfig image = sync::SyncConfig::ForSwarm(1, 0);
  const int64_t image_maneuver_rounds = runtime::RobotConfig{}.maneuver_rounds;
  const double image_app_round_s =
      static_cast<double>(image_maneuver_rounds * registry::kDefaultRadioRoundNs) / 1e9;
  const struct {
    const char* name;
    double given;
    double image;
    bool differs;
  } fields[] = {
      {"app_round_s", timing.app_round_s, image_app_round_s,
       std::llround(timing.app_round_s / timing.radio_round_s) != image_maneuver_rounds},
      {"vote_rounds", static_cast<double>(timing.vote_rounds), static_cast<double>(image.vote_rounds),
       timing.vote_rounds != image.vote_rounds},
      {"silence_rounds", static_cast<double>(timing.silence_rounds), static_cast<double>(image.silence_rounds),
       timing.silence_rounds != image.silence_rounds}};
  for (const auto& field : fields) {
    if (!field.differs) continue;
    char values[96];
    std::snprintf(values, sizeof values, " is %g; the robot image has %g", field.given, field.image);
    return "timing." + std::string(field.name) + values +
           " compiled in (its synchronizer's timing, docs/scenarios.md) and would run its epochs on other timing";
  }
  return std::nullopt;
}

// The image's estimator ranges against the default arena's anchors; the
// world measures against the scenario's.
std::optional<std::string> ArenaDiffers(const Scenario& scenario) {
  const estimation::Arena<double>& arena = scenario.sensors.arena;
  const estimation::Arena<double> image = estimation::DefaultArena<double>();
  const auto near = [](double a, double b) { return std::fabs(a - b) <= 1e-9; };
  const auto metres = [](double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g m", value);
    return std::string(text);
  };
  std::string differs;
  if (!near(arena.width_m, image.width_m) || !near(arena.depth_m, image.depth_m)) {
    differs = "the arena is " + metres(arena.width_m) + " x " + metres(arena.depth_m);
  } else if (!near(arena.tag_height_m, image.tag_height_m)) {
    differs = "arena.tag_height_m is " + metres(arena.tag_height_m);
  } else if (arena.anchor_count != image.anchor_count) {
    differs = "arena.anchors lists " + std::to_string(arena.anchor_count) + " anchors";
  } else {
    for (int i = 0; i < arena.anchor_count && differs.empty(); ++i) {
      if ((arena.anchors[i] - image.anchors[i]).norm() > 1e-9) {
        differs = "arena.anchors[" + std::to_string(i) + "] is elsewhere";
      }
    }
  }
  if (differs.empty()) return std::nullopt;
  return differs +
         "; the robot image has the default arena compiled in (4 m x 4 m, tag_height_m 0.10, the four default "
         "anchors; docs/scenarios.md) and its estimates would be off";
}

// The kinds' limits the image's controllers and safety filter drive with.
std::optional<std::string> KindLimitsDiffer(const Scenario& scenario) {
  const std::pair<const char*, double motion::KindLimits::*> fields[] = {
      {"body_radius_m", &motion::KindLimits::body_radius_m},
      {"max_speed_mps", &motion::KindLimits::max_speed_mps},
      {"max_accel_mps2", &motion::KindLimits::max_accel_mps2},
      {"max_turn_rate_radps", &motion::KindLimits::max_turn_rate_radps},
      {"wheel_base_m", &motion::KindLimits::wheel_base_m},
      {"tilt_time_constant_s", &motion::KindLimits::tilt_time_constant_s},
      {"flight_height_m", &motion::KindLimits::flight_height_m}};
  for (size_t i = 0; i < motion::kRobotKindCount; ++i) {
    const auto kind = static_cast<world::RobotKind>(i);
    const bool present = std::any_of(scenario.robots.begin(), scenario.robots.end(),
                                     [kind](const RobotSpec& robot) { return robot.kind == kind; });
    if (!present) continue;
    const motion::KindLimits given = world::LimitsOf(scenario.kind_spec(kind));
    const motion::KindLimits image = motion::DefaultKindLimits(kind);
    for (const auto& [name, field] : fields) {
      if (given.*field == image.*field) continue;
      char values[96];
      std::snprintf(values, sizeof values, " is %g; the robot image has %g", given.*field, image.*field);
      return "kinds." + std::string(world::ToString(kind)) + "." + name + values +
             " compiled in (the default kinds, docs/scenarios.md) and would drive its robots with other limits";
    }
  }
  return std::nullopt;
}

// The noise the image's estimator weighs its readings with: the lab's
// robot takes the scenario's sensors' (lab/sim robot_config.cpp, above a
// floor), the image its compiled-in defaults, which the default sensors
// match.
std::optional<std::string> SensorNoiseDiffers(const Scenario& scenario) {
  const estimation::EstimatorConfig<float> image{};
  const std::pair<const char*, std::pair<double, float>> fields[] = {
      {"sensors.uwb.sigma_m", {scenario.sensors.uwb.sigma_m, image.range_sigma_m}},
      {"sensors.flow.sigma_px", {scenario.sensors.flow.sigma_px, image.flow_sigma_px}}};
  for (const auto& [name, values] : fields) {
    if (static_cast<float>(values.first) == values.second) continue;
    char text[96];
    std::snprintf(text, sizeof text, " is %g; the robot image's estimator has %g", values.first,
                  static_cast<double>(values.second));
    return std::string(name) + text +
           " compiled in (the default sensors, docs/scenarios.md) and would weigh its readings otherwise than the "
           "lab's robots";
  }
  return std::nullopt;
}

// The image's safety filter is always on.
std::optional<std::string> SafetyDiffers(const Scenario& scenario) {
  if (scenario.safety) return std::nullopt;
  return "safety is off; the robot image runs its safety filter always (docs/safety.md) and would drive otherwise "
         "than the lab's robots";
}

// The robots' radio carries a beacon of one BLE advertisement.
std::optional<std::string> SwarmTooLargeForTheRadio(const Scenario& scenario) {
  const size_t robots = scenario.robots.size();
  if (robots <= wire::LargestRadioSwarm()) return std::nullopt;
  return std::to_string(robots) + " robots; their beacon would be " +
         std::to_string(wire::EncodedSize(static_cast<uint16_t>(std::min<size_t>(robots, wire::kMaxSwarmSize)))) +
         " bytes, more than the robots' radio carries (" + std::to_string(wire::kMaxRadioBeaconBytes) +
         ", one BLE advertisement): the robot image runs swarms of at most " +
         std::to_string(wire::LargestRadioSwarm()) + " robots (docs/beacon.md)";
}

}  // namespace

std::optional<ScenarioError> CheckScenarioFitsTheImage(const Scenario& scenario) {
  for (std::optional<std::string> (*differs)(const Scenario&) :
       {SwarmTooLargeForTheRadio, RadioRoundDiffers, SyncTimingDiffers, ArenaDiffers, KindLimitsDiffer,
        SensorNoiseDiffers, SafetyDiffers}) {
    std::optional<std::string> message = differs(scenario);
    if (!message) continue;
    return ScenarioError{.where = scenario.source.empty() ? scenario.name : scenario.source,
                         .message = std::move(*message)};
  }
  return std::nullopt;
}

}  // namespace syrof::lab::scenario
