// The app and its parameters, checked against the catalog of built-in apps.
#include <string_view>
#include <vector>

#include "nearest_name.h"
#include "schema.h"
#include "value_reader.h"

namespace syrof::lab::scenario {
namespace {

using apps::kBuiltinPrefix;

std::vector<std::string> QualifiedNames(std::span<const apps::BuiltinAppInfo> catalog) {
  std::vector<std::string> names;
  for (const apps::BuiltinAppInfo& app : catalog) names.push_back(std::string(kBuiltinPrefix) + app.name);
  return names;
}

// The catalog entry for "builtin:NAME", or an error message naming the
// nearest app and listing them all.
const apps::BuiltinAppInfo* FindApp(const std::string& name, std::span<const apps::BuiltinAppInfo> catalog,
                                    std::string& problem) {
  if (name.starts_with(kBuiltinPrefix)) {
    const std::string_view bare = apps::BareAppName(name);
    for (const apps::BuiltinAppInfo& app : catalog) {
      if (bare == app.name) return &app;
    }
  }
  const std::vector<std::string> names = QualifiedNames(catalog);
  const std::vector<std::string_view> views(names.begin(), names.end());
  std::string nearest = NearestName(name, views);
  if (nearest.empty()) nearest = NearestName(std::string(kBuiltinPrefix) + name, views);
  problem = "unknown app '" + name + "'" + (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
            "; built-in apps: " + JoinNames(views);
  return nullptr;
}

bool ReadParams(const YamlNode& node, const std::string& path, const apps::BuiltinAppInfo& app,
                std::map<std::string, double>& params, Diagnostics& diagnostics) {
  if (!ExpectMap(node, path, diagnostics)) return false;
  std::vector<std::string_view> names;
  for (const apps::ParamInfo& param : app.params) names.push_back(param.name);
  for (size_t i = 0; i < node.keys.size(); ++i) {
    const YamlNode& key = node.keys[i];
    const apps::ParamInfo* info = nullptr;
    for (const apps::ParamInfo& param : app.params) {
      if (key.scalar == param.name) info = &param;
    }
    if (info == nullptr) {
      const std::string nearest = NearestName(key.scalar, names);
      const std::string hint = !nearest.empty()  ? " (did you mean '" + nearest + "'?)"
                               : names.empty()   ? " (builtin:" + std::string(app.name) + " takes no parameters)"
                                                 : " (parameters: " + JoinNames(names) + ")";
      return FailAt(key, path, "unknown parameter '" + key.scalar + "' for builtin:" + app.name + hint, diagnostics);
    }
    double value = info->default_value;
    if (!ReadNumber(node.values[i], JoinPath(path, key.scalar), NumberRange{info->min_value, info->max_value}, value,
                    diagnostics)) {
      return false;
    }
    params[key.scalar] = value;
  }
  return true;
}

}  // namespace

bool ReadApp(const YamlNode& node, std::span<const apps::BuiltinAppInfo> catalog, AppSpec& app,
             Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"name", "params"};
  const std::string path = "app";
  const YamlNode* name_node = &node;
  std::string name_path = path;
  if (node.is_map()) {
    if (!CheckKeys(node, path, kKeys, diagnostics) || !RequireKey(node, path, "name", diagnostics)) return false;
    name_node = node.Find("name");
    name_path = "app.name";
  }
  if (!name_node->is_scalar()) {
    return FailAt(*name_node, name_path, "expected an app name such as 'builtin:idle' or a map with 'name' and 'params'",
                  diagnostics);
  }
  std::string problem;
  const apps::BuiltinAppInfo* info = FindApp(name_node->scalar, catalog, problem);
  if (info == nullptr) return FailAt(*name_node, name_path, problem, diagnostics);
  app.name = name_node->scalar;
  app.params.clear();
  const YamlNode* params = node.is_map() ? node.Find("params") : nullptr;
  return params == nullptr || ReadParams(*params, "app.params", *info, app.params, diagnostics);
}

bool OverrideApp(const std::string& name, std::span<const apps::BuiltinAppInfo> catalog, AppSpec& app,
                 Diagnostics& diagnostics) {
  std::string problem;
  if (FindApp(name, catalog, problem) == nullptr) return diagnostics.Fail(0, 0, "app override: " + problem);
  if (name != app.name) app.params.clear();
  app.name = name;
  return true;
}

}  // namespace syrof::lab::scenario
