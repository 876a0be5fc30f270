#include "view_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "exit_status.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/view/verdict.h"
#include "syrof/lab/view/view.h"

namespace syrof::cli {
namespace {

// An error in words alone.
lab::Error PageError(std::string message) { return lab::Error{.where = "", .message = std::move(message)}; }

// Writes `page` to `path`; what went wrong, if anything.
std::optional<lab::Error> WriteHtml(const lab::view::Page& page, const std::string& path) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return PageError(fmt::format("cannot write {}", path));
  file << page.html;
  file.flush();
  if (!file) return PageError(fmt::format("writing {} failed", path));
  return std::nullopt;
}

}  // namespace

std::string DefaultPagePath(const std::string& replay_path) { return replay_path + ".html"; }

CLI::App* SetupViewCommand(CLI::App& app, ViewOptions& options) {
  CLI::App* command = app.add_subcommand(
      "view", "Write a replay's page: one self-contained HTML file (arena, events, inspector, plots)");
  command->add_option("REPLAY", options.file, "Replay file written by `syrof run`")->required();
  command->add_option("-o,--output", options.output, "The page to write (default: REPLAY.html)");
  command->add_option("--metrics", options.metrics,
                      "The run's metrics.json, for the verdict (default: metrics.json beside REPLAY, if there)");
  command->add_option("--scenario", options.scenario, "The run's scenario file, to draw the goal's target");
  return command;
}

int RunViewCommand(const ViewOptions& options, std::ostream& out, std::ostream& err) {
  std::error_code error;
  if (std::filesystem::is_directory(options.file, error)) {
    fmt::print(err, "syrof view: '{}' is a folder, not a replay file\n", options.file);
    return kBadInput;
  }
  std::ifstream in(options.file, std::ios::binary);
  if (!in) {
    fmt::print(err, "syrof view: cannot open '{}': {}\n", options.file, std::strerror(errno));
    return kBadInput;
  }
  lab::view::PageOptions page_options;
  // The verdict's metrics: the run's metrics.json, named or beside the
  // replay. Untrusted like the replay: a bad one is reported and left out.
  const std::filesystem::path metrics_path = options.metrics.empty()
                                                 ? std::filesystem::path(options.file).parent_path() / "metrics.json"
                                                 : std::filesystem::path(options.metrics);
  if (!options.metrics.empty() || std::filesystem::is_regular_file(metrics_path, error)) {
    std::ifstream metrics_file(metrics_path, std::ios::binary);
    lab::Error metrics_error;
    if (!metrics_file) {
      fmt::print(err, "syrof view: cannot open '{}': {}\n", metrics_path.string(), std::strerror(errno));
      return kBadInput;
    }
    page_options.metrics = lab::view::ReadVerdictMetrics(metrics_file, metrics_path.string(), metrics_error);
    if (!page_options.metrics && !options.metrics.empty()) {
      fmt::print(err, "syrof view: {}\n", metrics_error.ToString());
      return kBadInput;
    }
    if (!page_options.metrics) {  // found beside the replay, not asked for: the page goes on without it
      fmt::print(err, "syrof view: warning: {}; the verdict is the replay's alone\n", metrics_error.ToString());
    }
  }
  std::optional<lab::scenario::Scenario> scenario;
  if (!options.scenario.empty()) {
    const lab::scenario::LoadResult loaded = lab::scenario::LoadScenarioFile(options.scenario);
    if (!loaded.ok()) {
      fmt::print(err, "syrof view: {}\n", loaded.error->ToString());
      return kBadInput;
    }
    scenario = *loaded.scenario;
    page_options.scenario = &*scenario;
  }
  const lab::view::Page page = lab::view::BuildPage(in, options.file, page_options);
  const std::string path = options.output.empty() ? DefaultPagePath(options.file) : options.output;
  if (const std::optional<lab::Error> problem = WriteHtml(page, path)) {
    fmt::print(err, "syrof view: {}\n", problem->ToString());
    return kInternalError;
  }
  if (!page.complete) {
    fmt::print(err, "syrof view: {}\n", page.error ? page.error->ToString() : options.file);
    fmt::print(err, "syrof view: wrote {}, which shows this message{}\n", path,
               page.rounds > 0 ? fmt::format(" and the {} rounds read before it", page.rounds) : "");
    return kBadInput;
  }
  fmt::print(out, "syrof view: wrote {} ({} rounds, {} events{}; {:.1f} KiB); open it in a browser\n", path,
             page.rounds, page.events,
             page.frame_stride > 1 ? fmt::format(", frames drawn every {} rounds", page.frame_stride) : "",
             static_cast<double>(page.html.size()) / 1024.0);
  return kOk;
}

std::optional<lab::Error> WritePage(const std::string& replay_path, const std::string& page_path,
                                    const lab::view::PageOptions& options) {
  std::ifstream in(replay_path, std::ios::binary);
  if (!in) return PageError(fmt::format("cannot open {}", replay_path));
  const lab::view::Page page = lab::view::BuildPage(in, replay_path, options);
  if (std::optional<lab::Error> problem = WriteHtml(page, page_path)) return problem;
  if (!page.complete) return page.error ? *page.error : PageError("the replay is incomplete");
  return std::nullopt;
}

}  // namespace syrof::cli
