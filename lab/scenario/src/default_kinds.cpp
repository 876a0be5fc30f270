#include "syrof/lab/scenario/default_kinds.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

#include "syrof/lab/world/arena.h"
#include "syrof/motion/robot_kind.h"

namespace syrof::lab::scenario {

std::optional<ScenarioError> CheckDefaultKindLimits(const Scenario& scenario) {
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
      return ScenarioError{.where = scenario.source.empty() ? scenario.name : scenario.source,
                           .message = "kinds." + std::string(world::ToString(kind)) + "." + name + values +
                                      " compiled in (the default kinds, docs/scenarios.md) and would drive its "
                                      "robots with other limits"};
    }
  }
  return std::nullopt;
}

}  // namespace syrof::lab::scenario
