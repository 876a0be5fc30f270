#include "replay_command.h"

#include <fmt/format.h>

#include <array>
#include <exception>
#include <fstream>

#include "syrof/lab/replay/reader.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/wire/beacon.h"

namespace syrof::cli {
namespace {

namespace replay = lab::replay;

using replay::Event;
using replay::EventKind;
using replay::Header;
using replay::Reader;
using replay::RobotFrame;
using replay::Round;

constexpr int kOk = 0;
constexpr int kInternalError = 1;
constexpr int kBadInput = 2;

// Seconds with all nine digits of the nanoseconds: exact, and the same text
// on every host.
std::string FormatTime(int64_t time_ns) {
  const bool negative = time_ns < 0;
  const uint64_t magnitude = negative ? 0 - static_cast<uint64_t>(time_ns) : static_cast<uint64_t>(time_ns);
  return fmt::format("{}{}.{:09}s", negative ? "-" : "", magnitude / 1000000000u, magnitude % 1000000000u);
}

// Mirrors world::RobotKind's names; lab_replay stores the kind as a plain
// number so it does not depend on the world module.
std::string KindName(uint8_t kind) {
  if (kind == 0) return "omni";
  if (kind == 1) return "rover";
  return fmt::format("kind {}", kind);
}

std::string RobotName(uint16_t robot) { return robot == replay::kNoRobot ? "-" : fmt::format("{}", robot); }

const char* PhaseName(uint8_t phase) { return wire::ToString(static_cast<wire::Phase>(phase)); }
const char* ModeName(uint8_t mode) { return wire::ToString(static_cast<wire::Mode>(mode)); }

void PrintHeader(const Header& header, uint16_t version, std::ostream& out) {
  out << fmt::format("SyROF replay, format version {}\n", version)
      << fmt::format("scenario: {}\n", header.scenario_name)
      << fmt::format("app: {}\n", header.app_name)
      << fmt::format("seed: {}\n", header.seed)
      << fmt::format("radio round: {} ns\n", header.radio_round_ns)
      << fmt::format("arena: {} x {} m\n", header.arena_width_m, header.arena_height_m)
      << fmt::format("robots: {}\n", header.robots.size());
  for (const replay::RobotInfo& robot : header.robots) {
    out << fmt::format("  robot {}: {}, body radius {} m\n", robot.id, KindName(robot.kind),
                       robot.body_radius_m);
  }
}

// Says once what the columns of the frame lines are.
void PrintLegend(std::ostream& out) {
  out << "frames: time robot ID PRESENCE member|joining PHASE MODE epoch E "
         "true (x m, y m, heading rad) est (x m, y m, heading rad)\n";
}

void PrintFrame(const RobotFrame& frame, int64_t time_ns, std::ostream& out) {
  out << fmt::format(
      "  {} robot {} {} {} {} {} epoch {} true ({:.3f}, {:.3f}, {:.3f}) est ({:.3f}, {:.3f}, {:.3f})\n",
      FormatTime(time_ns), frame.id, replay::ToString(frame.presence),
      frame.status == 0 ? "member" : "joining", PhaseName(frame.phase), ModeName(frame.mode),
      frame.epoch, frame.true_x_m, frame.true_y_m, frame.true_heading_rad, frame.est_x_m,
      frame.est_y_m, frame.est_heading_rad);
}

void PrintEvent(const Event& event, std::ostream& out) {
  if (replay::IsPartitionEvent(event.kind)) {
    out << fmt::format("  {} event {} partition {}\n", FormatTime(event.time_ns), replay::ToString(event.kind),
                       event.partition);
    return;
  }
  std::string other;
  if (event.other != replay::kNoRobot) other = fmt::format(" other {}", event.other);
  out << fmt::format("  {} event {} robot {}{} epoch {} mode {}\n", FormatTime(event.time_ns),
                     replay::ToString(event.kind), RobotName(event.robot), other, event.epoch,
                     ModeName(event.mode));
}

// One line per map: who started which epoch with which members; the
// snapshots are in the csv and jsonl exports.
void PrintMap(const replay::RobotMap& entry, int64_t time_ns, std::ostream& out) {
  std::string members;
  for (const replay::MapMember& member : entry.map->members) members += fmt::format(" {}", member.id);
  out << fmt::format("  {} map robot {} epoch {} {} members{}\n", FormatTime(time_ns), entry.robot,
                     entry.map->epoch, ModeName(entry.map->mode), members);
}

bool Selected(const Event& event, const ReplayOptions& options) {
  return !options.robot || event.robot == *options.robot || event.other == *options.robot;
}

void PrintRound(const Round& round, const ReplayOptions& options, std::ostream& out) {
  size_t events = 0;
  for (const Event& event : round.events) events += Selected(event, options) ? 1 : 0;
  if (options.events_only && events == 0) return;
  out << fmt::format("round {} t={}\n", round.index, FormatTime(round.time_ns));
  if (!options.events_only) {
    for (const RobotFrame& frame : round.robots) {
      if (!options.robot || frame.id == *options.robot) PrintFrame(frame, round.time_ns, out);
    }
  }
  for (const Event& event : round.events) {
    if (Selected(event, options)) PrintEvent(event, out);
  }
  if (!options.events_only) {
    for (const replay::RobotMap& entry : round.maps) {
      if (!options.robot || entry.robot == *options.robot) PrintMap(entry, round.time_ns, out);
    }
  }
}

// How a file ended, for the summary and the exit code.
std::string Ending(const Reader& reader) {
  if (reader.complete()) return "complete";
  return fmt::format("{} ({})", reader.truncated() ? "truncated" : "invalid", reader.error().ToString());
}

int Summarize(Reader& reader, std::ostream& out) {
  Round round;
  uint32_t rounds = 0;
  uint64_t frames = 0;
  std::array<uint64_t, static_cast<size_t>(replay::kLastEventKind) + 1> by_kind{};
  uint64_t events = 0;
  uint32_t first_index = 0;
  uint32_t last_index = 0;
  int64_t first_time_ns = 0;
  int64_t last_time_ns = 0;
  while (reader.Next(round)) {
    if (rounds == 0) {
      first_index = round.index;
      first_time_ns = round.time_ns;
    }
    last_index = round.index;
    last_time_ns = round.time_ns;
    ++rounds;
    frames += round.robots.size();
    events += round.events.size();
    for (const Event& event : round.events) ++by_kind[static_cast<size_t>(event.kind)];
  }
  if (rounds == 0) {
    out << "rounds: 0\n";
  } else {
    out << fmt::format("rounds: {} (index {} .. {}, t={} .. {})\n", rounds, first_index, last_index,
                       FormatTime(first_time_ns), FormatTime(last_time_ns));
  }
  out << fmt::format("frames: {}\n", frames) << fmt::format("events: {}\n", events);
  for (size_t kind = 0; kind < by_kind.size(); ++kind) {
    out << fmt::format("  {}: {}\n", replay::ToString(static_cast<EventKind>(kind)), by_kind[kind]);
  }
  out << fmt::format("file: {}\n", Ending(reader));
  return reader.complete() ? kOk : kBadInput;
}

int Dump(const ReplayOptions& options, std::ostream& out, std::ostream& err) {
  std::ifstream in(options.file, std::ios::binary);
  if (!in) {
    err << fmt::format("syrof replay: cannot open '{}'\n", options.file);
    return kBadInput;
  }
  Reader reader(in);
  Header header;
  if (!reader.ReadHeader(header)) {
    err << fmt::format("syrof replay: {}: {}\n", options.file, reader.error().ToString());
    return kBadInput;
  }
  PrintHeader(header, reader.version(), out);
  if (options.summary) {
    const int status = Summarize(reader, out);
    if (status != kOk) err << fmt::format("syrof replay: {}: {}\n", options.file, reader.error().ToString());
    return status;
  }
  if (options.robot) {
    bool known = false;
    for (const replay::RobotInfo& robot : header.robots) known = known || robot.id == *options.robot;
    if (!known) {
      err << fmt::format("syrof replay: {}: no robot {} in this replay\n", options.file, *options.robot);
      return kBadInput;
    }
  }

  if (!options.events_only) PrintLegend(out);
  Round round;
  bool round_found = false;
  while (reader.Next(round)) {
    if (options.round) {
      // Indices increase through a file, so nothing after it can match.
      if (round.index > *options.round) break;
      if (round.index != *options.round) continue;
      round_found = true;
    }
    PrintRound(round, options, out);
  }
  if (reader.failed() && !round_found) {
    err << fmt::format("syrof replay: {}: {}\n", options.file, reader.error().ToString());
    return kBadInput;
  }
  if (options.round && !round_found) {
    err << fmt::format("syrof replay: {}: no round {} in this replay\n", options.file, *options.round);
    return kBadInput;
  }
  return kOk;
}

}  // namespace

CLI::App* SetupReplayCommand(CLI::App& app, ReplayOptions& options) {
  CLI::App* command = app.add_subcommand("replay", "Print a replay file recorded by `syrof run`");
  command->add_option("FILE", options.file, "Replay file")->required();
  CLI::Option* round = command->add_option("--round", options.round, "Print only round N");
  CLI::Option* robot =
      command->add_option("--robot", options.robot, "Print only robot ID and events naming it");
  CLI::Option* events_only =
      command->add_flag("--events-only", options.events_only, "Print events, not frames");
  command->add_flag("--summary", options.summary, "Print counts and whether the file is complete")
      ->excludes(round)
      ->excludes(robot)
      ->excludes(events_only);
  return command;
}

int RunReplayCommand(const ReplayOptions& options, std::ostream& out, std::ostream& err) {
  try {
    const int status = Dump(options, out, err);
    out.flush();
    if (!out) {
      err << "syrof replay: writing the output failed\n";
      return kInternalError;
    }
    return status;
  } catch (const std::exception& error) {
    err << fmt::format("syrof replay: internal error: {}\n", error.what());
    return kInternalError;
  }
}

}  // namespace syrof::cli
