#include "syrof/lab/apps/catalog.h"

#include <array>

#include "builtin_apps.h"

namespace syrof::lab::apps {
namespace {

// The margin every moving app adds to two body radii: it must cover two
// robots' position errors (about 0.03-0.05 m RMS each in the simulated lab)
// plus the controller's tolerance. Below 0.1 m (gather's default gap) so a
// robot can enter a packing slot next to an occupied one.
constexpr ParamInfo kMarginParam{"margin_m", 0.08, 0.0, 0.5,
                                 "metres added to two body radii in the safety rule (estimation and control error)"};

constexpr std::array<ParamInfo, 3> kGatherParams{{
    {"gap_m", 0.1, 0.0, 2.0, "metres of free space between neighbouring bodies in the packing"},
    {"tolerance_m", 0.1, 0.001, 2.0, "metres the swarm's radius may exceed the packing's (goal)"},
    kMarginParam,
}};

constexpr std::array<ParamInfo, 5> kCircleParams{{
    {"radius_m", 1.2, 0.05, 30.0, "metres, circle radius (raised if the robots do not fit, lowered to fit the arena)"},
    {"centre_x_m", -1.0, -1.0, 30.0, "metres, circle centre x; negative: the arena's centre"},
    {"centre_y_m", -1.0, -1.0, 30.0, "metres, circle centre y; negative: the arena's centre"},
    {"tolerance_m", 0.1, 0.001, 2.0, "metres a robot may be from its point (goal)"},
    kMarginParam,
}};

constexpr std::array<ParamInfo, 5> kLeaderFollowParams{{
    {"speed_mps", 0.15, 0.0, 2.0, "metres per second, the leader's speed along its path (an upper bound)"},
    {"spacing_m", 0.4, 0.05, 5.0, "metres between consecutive robots of the line"},
    {"path_radius_m", 1.2, 0.1, 30.0, "metres, radius of the leader's circular path around the arena centre"},
    {"tolerance_m", 0.1, 0.001, 2.0, "metres a robot may be from its slot (goal)"},
    kMarginParam,
}};

}  // namespace

std::span<const BuiltinAppInfo> BuiltinApps() {
  static const std::array<BuiltinAppInfo, 4> kApps{{
      {"idle", "hold still", {}},
      {"gather", "pack around the centre of the first smallest enclosing circle", kGatherParams},
      {"circle", "spread evenly on a circle", kCircleParams},
      {"leader_follow", "a line trailing the leader around a circular path", kLeaderFollowParams},
  }};
  return kApps;
}

const BuiltinAppInfo* FindBuiltinApp(std::string_view name) {
  for (const BuiltinAppInfo& app : BuiltinApps()) {
    if (name == app.name) return &app;
  }
  return nullptr;
}

double ParamValue(const BuiltinAppInfo& app, const std::map<std::string, double>& params, std::string_view name) {
  if (const auto found = params.find(std::string(name)); found != params.end()) return found->second;
  for (const ParamInfo& param : app.params) {
    if (name == param.name) return param.default_value;
  }
  return 0.0;
}

std::unique_ptr<app::App> MakeBuiltinApp(std::string_view name, const std::map<std::string, double>& params) {
  if (name == "idle") return MakeIdleApp();
  if (name == "gather") return MakeGatherApp(ReadGatherParams(params));
  if (name == "circle") return MakeCircleApp(ReadCircleParams(params));
  if (name == "leader_follow") return MakeLeaderFollowApp(ReadLeaderFollowParams(params));
  return nullptr;
}

}  // namespace syrof::lab::apps
