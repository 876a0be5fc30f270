// The app: a built-in one and its parameters, checked against the catalog,
// or a student's shared library, checked to be a file (the app host checks
// its entry symbol and ABI before a run).
#include <algorithm>
#include <filesystem>
#include <limits>
#include <string_view>
#include <system_error>
#include <vector>

#include "nearest_name.h"
#include "syrof/app.h"
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

bool CheckAppValueName(const YamlNode& key, const std::string& path, const char* what, Diagnostics& diagnostics) {
  const std::string& name = key.scalar;
  if (name.size() > SYROF_APP_MAX_PARAMETER_NAME_LENGTH) {
    return FailAt(key, path,
                  std::string(what) + " name '" + name.substr(0, 24) + "...' is " + std::to_string(name.size()) +
                      " characters long; at most " + std::to_string(SYROF_APP_MAX_PARAMETER_NAME_LENGTH),
                  diagnostics);
  }
  const auto is_letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  const bool well_formed =
      !name.empty() && is_letter(name[0]) &&
      std::all_of(name.begin(), name.end(), [&](char c) { return is_letter(c) || (c >= '0' && c <= '9'); });
  if (!well_formed) {
    return FailAt(key, path,
                  std::string(what) + " name '" + name +
                      "' must start with a letter or '_' and hold only letters, digits and '_' (as radius_m)",
                  diagnostics);
  }
  return true;
}

namespace {

// A library's params: any names the app asks for with syrofAppParameter
// (the platform cannot know which), so only their form, count and length are
// checked; any finite number.
bool ReadLibraryParams(const YamlNode& node, const std::string& path, std::map<std::string, double>& params,
                       Diagnostics& diagnostics) {
  if (!ExpectMap(node, path, diagnostics)) return false;
  if (node.keys.size() > SYROF_APP_MAX_PARAMETERS) {
    return FailAt(node.keys[SYROF_APP_MAX_PARAMETERS], path,
                  "too many parameters: " + std::to_string(node.keys.size()) + ", a library app takes at most " +
                      std::to_string(SYROF_APP_MAX_PARAMETERS),
                  diagnostics);
  }
  for (size_t i = 0; i < node.keys.size(); ++i) {
    const std::string& name = node.keys[i].scalar;
    if (!CheckAppValueName(node.keys[i], path, "parameter", diagnostics)) return false;
    double value = 0;
    const NumberRange any{std::numeric_limits<double>::lowest(), std::numeric_limits<double>::max()};
    if (!ReadNumber(node.values[i], JoinPath(path, name), any, value, diagnostics)) return false;
    params[name] = value;
  }
  return true;
}

// Where a library named `text` in a file under `base_dir` is: `text` itself
// when absolute or when `base_dir` is empty, else base_dir/text.
std::string ResolveLibrary(const std::string& text, const std::string& base_dir) {
  const std::filesystem::path path(text);
  if (path.is_absolute() || base_dir.empty()) return text;
  return (std::filesystem::path(base_dir) / path).string();
}

// Why `resolved` (written as `text`) cannot be a library; empty when it is
// a file. Only existence is checked here: whether it loads is the app
// host's question.
std::string LibraryFileProblem(const std::string& text, const std::string& resolved) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(resolved, error);
  const std::string looked = resolved == text ? "" : " (looked for " + resolved + ")";
  if (status.type() == std::filesystem::file_type::not_found) {
    return "no such library file '" + text + "'" + looked + "; build the app first (docs/apps.md, \"Your first app\")";
  }
  if (error) return "cannot read library file '" + text + "'" + looked + ": " + error.message();
  if (std::filesystem::is_directory(status)) return "'" + text + "'" + looked + " is a folder, not a library file";
  return {};
}

// A library path at `node` (the scalar form of `app:` or `app.library`).
bool ReadLibrary(const YamlNode& node, const std::string& path, const std::string& base_dir, AppSpec& app,
                 Diagnostics& diagnostics) {
  std::string text;
  if (!ReadString(node, path, text, diagnostics)) return false;
  if (text.empty()) return FailAt(node, path, "expected the path of a shared library, got an empty string", diagnostics);
  const std::string resolved = ResolveLibrary(text, base_dir);
  if (const std::string problem = LibraryFileProblem(text, resolved); !problem.empty()) {
    return FailAt(node, path, problem, diagnostics);
  }
  app.name = text;
  app.library = resolved;
  app.params.clear();
  return true;
}

bool ReadBuiltinName(const YamlNode& node, const std::string& path, std::span<const apps::BuiltinAppInfo> catalog,
                     const apps::BuiltinAppInfo*& info, AppSpec& app, Diagnostics& diagnostics) {
  std::string problem;
  info = FindApp(node.scalar, catalog, problem);
  if (info == nullptr) return FailAt(node, path, problem, diagnostics);
  app.name = node.scalar;
  app.library.clear();
  app.params.clear();
  return true;
}

// cpu_budget_ms and wall_cap_ms of a library app.
bool ReadLibraryLimits(const YamlNode& node, AppSpec& app, Diagnostics& diagnostics) {
  int64_t cpu = 0;
  int64_t wall = 0;
  if (node.Find("cpu_budget_ms") != nullptr) {
    if (!ReadIntegerAt(node, "app", "cpu_budget_ms", 1, kMaxCpuBudgetMs, cpu, diagnostics)) return false;
    app.cpu_budget_ms = static_cast<uint32_t>(cpu);
  }
  if (node.Find("wall_cap_ms") != nullptr) {
    if (!ReadIntegerAt(node, "app", "wall_cap_ms", 1, kMaxWallCapMs, wall, diagnostics)) return false;
    if (app.cpu_budget_ms && wall < cpu) {
      return FailAt(*node.Find("wall_cap_ms"), "app.wall_cap_ms",
                    "must be at least cpu_budget_ms (" + std::to_string(cpu) + "), got " + std::to_string(wall),
                    diagnostics);
    }
    app.wall_cap_ms = static_cast<uint32_t>(wall);
  }
  return true;
}

}  // namespace

bool IsLibraryPath(std::string_view name) {
  return name.find('/') != std::string_view::npos || name.ends_with(".so");
}

bool ReadApp(const YamlNode& node, std::span<const apps::BuiltinAppInfo> catalog, const std::string& base_dir,
             AppSpec& app, Diagnostics& diagnostics) {
  static constexpr std::string_view kKeys[] = {"name", "library", "params", "cpu_budget_ms", "wall_cap_ms"};
  const std::string path = "app";
  app = AppSpec{};
  if (node.is_scalar()) {
    if (IsLibraryPath(node.scalar)) return ReadLibrary(node, path, base_dir, app, diagnostics);
    const apps::BuiltinAppInfo* info = nullptr;
    return ReadBuiltinName(node, path, catalog, info, app, diagnostics);
  }
  if (!node.is_map()) {
    return FailAt(node, path,
                  "expected an app such as 'builtin:idle' or 'build/libmyapp.so', or a map with 'name' (a built-in "
                  "app) or 'library' (a shared library)",
                  diagnostics);
  }
  if (!CheckKeys(node, path, kKeys, diagnostics)) return false;
  const YamlNode* name = node.Find("name");
  const YamlNode* library = node.Find("library");
  const YamlNode* params = node.Find("params");
  if (name != nullptr && library != nullptr) {
    return FailAt(KeyNode(node, "library"), path,
                  "give either 'name' (a built-in app) or 'library' (a shared library), not both", diagnostics);
  }
  if (library != nullptr) {
    if (!ReadLibrary(*library, "app.library", base_dir, app, diagnostics)) return false;
    if (params != nullptr && !ReadLibraryParams(*params, "app.params", app.params, diagnostics)) return false;
    return ReadLibraryLimits(node, app, diagnostics);
  }
  if (name == nullptr) {
    return FailAt(node, path, "missing required key 'app.name' (a built-in app) or 'app.library' (a shared library)",
                  diagnostics);
  }
  for (std::string_view key : {std::string_view("cpu_budget_ms"), std::string_view("wall_cap_ms")}) {
    if (node.Find(key) != nullptr) {
      return FailAt(KeyNode(node, key), path,
                    "'" + std::string(key) + "' is for a library app; built-in apps run inside the simulator",
                    diagnostics);
    }
  }
  if (!name->is_scalar()) {
    return FailAt(*name, "app.name", "expected a built-in app's name such as 'builtin:idle'", diagnostics);
  }
  if (IsLibraryPath(name->scalar)) {
    return FailAt(*name, "app.name",
                  "'" + name->scalar + "' is a library's path; write it as 'library: " + name->scalar + "'",
                  diagnostics);
  }
  const apps::BuiltinAppInfo* info = nullptr;
  if (!ReadBuiltinName(*name, "app.name", catalog, info, app, diagnostics)) return false;
  return params == nullptr || ReadParams(*params, "app.params", *info, app.params, diagnostics);
}

bool OverrideApp(const std::string& name, std::span<const apps::BuiltinAppInfo> catalog, AppSpec& app,
                 Diagnostics& diagnostics) {
  if (IsLibraryPath(name)) {
    if (const std::string problem = LibraryFileProblem(name, name); !problem.empty()) {
      return diagnostics.Fail(0, 0, "app override: " + problem);
    }
    // A library's limits and params in the file stay when one library
    // replaces another (`--app build/libmyapp.so` on the file's scenario).
    if (!app.is_library()) {
      app.cpu_budget_ms.reset();
      app.wall_cap_ms.reset();
      app.params.clear();
    }
    app.name = name;
    app.library = name;
    return true;
  }
  std::string problem;
  if (FindApp(name, catalog, problem) == nullptr) return diagnostics.Fail(0, 0, "app override: " + problem);
  if (name != app.name) app.params.clear();
  app.name = name;
  app.library.clear();
  app.cpu_budget_ms.reset();
  app.wall_cap_ms.reset();
  return true;
}

}  // namespace syrof::lab::scenario
