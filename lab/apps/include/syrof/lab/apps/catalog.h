// The apps built into the tree, by name: what `app: builtin:NAME` in a
// scenario and `syrof run --app builtin:NAME` can choose, the numeric
// parameters each accepts, and a factory for one instance per robot.
#pragma once

#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "syrof/app/app.h"

namespace syrof::lab::apps {

/// One numeric parameter of a built-in app (scenario key app.params.NAME).
struct ParamInfo {
  const char* name;       ///< e.g. "radius_m"
  double default_value;
  double min_value;       ///< inclusive bounds the scenario loader enforces
  double max_value;
  const char* doc;        ///< one line, with the unit
};

struct BuiltinAppInfo {
  const char* name;      ///< without the "builtin:" prefix, e.g. "circle"
  const char* summary;   ///< one line
  std::span<const ParamInfo> params;
};

/// How scenarios and the command line name a built-in app: "builtin:NAME".
inline constexpr std::string_view kBuiltinPrefix = "builtin:";

/// NAME for "builtin:NAME"; `qualified` unchanged when it has no prefix.
constexpr std::string_view BareAppName(std::string_view qualified) {
  return qualified.starts_with(kBuiltinPrefix) ? qualified.substr(kBuiltinPrefix.size()) : qualified;
}

/// Every built-in app, in a fixed order.
std::span<const BuiltinAppInfo> BuiltinApps();

/// The app called `name` (without "builtin:"), or nullptr.
const BuiltinAppInfo* FindBuiltinApp(std::string_view name);

/// The value of the parameter `name` of `app`: params[name] when present,
/// else the parameter's default; 0 for a name `app` does not list and
/// `params` does not hold.
double ParamValue(const BuiltinAppInfo& app, const std::map<std::string, double>& params, std::string_view name);

/// A new instance of the app `name` for one robot. `params` holds values the
/// scenario loader already checked against ParamInfo; missing ones take
/// their defaults. Returns nullptr for an unknown name.
std::unique_ptr<app::App> MakeBuiltinApp(std::string_view name, const std::map<std::string, double>& params);

}  // namespace syrof::lab::apps
