#include "view_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "exit_status.h"
#include "syrof/lab/view/view.h"

namespace syrof::cli {
namespace {

// Writes `page` to `path`; "" or what went wrong.
std::string WriteHtml(const lab::view::Page& page, const std::string& path) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return fmt::format("cannot write {}", path);
  file << page.html;
  file.flush();
  if (!file) return fmt::format("writing {} failed", path);
  return {};
}

}  // namespace

std::string DefaultPagePath(const std::string& replay_path) { return replay_path + ".html"; }

CLI::App* SetupViewCommand(CLI::App& app, ViewOptions& options) {
  CLI::App* command = app.add_subcommand(
      "view", "Write a replay's page: one self-contained HTML file (arena, events, inspector, plots)");
  command->add_option("REPLAY", options.file, "Replay file written by `syrof run`")->required();
  command->add_option("-o,--output", options.output, "The page to write (default: REPLAY.html)");
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
  const lab::view::Page page = lab::view::BuildPage(in, options.file);
  const std::string path = options.output.empty() ? DefaultPagePath(options.file) : options.output;
  if (std::string problem = WriteHtml(page, path); !problem.empty()) {
    fmt::print(err, "syrof view: {}\n", problem);
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

std::string WritePage(const std::string& replay_path, const std::string& page_path) {
  std::ifstream in(replay_path, std::ios::binary);
  if (!in) return fmt::format("cannot open {}", replay_path);
  const lab::view::Page page = lab::view::BuildPage(in, replay_path);
  if (std::string problem = WriteHtml(page, page_path); !problem.empty()) return problem;
  if (!page.complete) return page.error ? page.error->ToString() : "the replay is incomplete";
  return {};
}

}  // namespace syrof::cli
