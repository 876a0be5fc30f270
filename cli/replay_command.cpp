#include "replay_command.h"

#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "exit_status.h"
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
  if (kind == 2) return "drone";
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
    out << fmt::format("  robot {}: {}, body radius {} m", robot.id, KindName(robot.kind), robot.body_radius_m);
    for (size_t i = 0; i < robot.inputs.size(); ++i) {
      out << (i == 0 ? ", inputs: " : ", ") << robot.inputs[i].name << "=" << fmt::format("{}", robot.inputs[i].value);
    }
    out << "\n";
  }
  if (header.message) out << fmt::format("message format: {}\n", header.message->ToString());
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

// ---- Exports (docs/replay.md, "Exporting") ----------------------------------

// Seconds with nine decimals, no unit: the time column of every export.
std::string Seconds(int64_t time_ns) {
  std::string text = FormatTime(time_ns);
  text.pop_back();  // the "s"
  return text;
}

// JSON Lines records keep their keys in the documented order ("type" first).
using Json = nlohmann::ordered_json;

// A robot id or partition as a CSV cell: empty for none.
std::string Cell(uint16_t value, uint16_t none) { return value == none ? std::string() : std::to_string(value); }
// The same for JSON: null for none.
Json JsonId(uint16_t value, uint16_t none) { return value == none ? Json() : Json(value); }

std::string Hex(const std::vector<uint8_t>& bytes) {
  std::string text;
  for (const uint8_t byte : bytes) text += fmt::format("{:02x}", byte);
  return text;
}

// Shortest text that reads back as the same float ("nan" and "inf" as such).
std::string Float(float value) { return fmt::format("{}", value); }
// JSON has no NaN or infinity: those become null. A float goes out as the
// shortest decimal that reads back as it (1.1, not 1.100000023841858).
Json JsonFloat(float value) {
  if (!std::isfinite(value)) return Json();
  return Json(std::strtod(Float(value).c_str(), nullptr));
}

constexpr const char* kFramesColumns =
    "round,time_s,robot,presence,status,phase,mode,epoch,true_x_m,true_y_m,true_heading_rad,est_x_m,est_y_m,"
    "est_heading_rad";
constexpr const char* kEventsColumns = "round,time_s,kind,robot,other,partition,epoch,mode";
constexpr const char* kMapsColumns =
    "round,time_s,robot,epoch,mode,member,member_phase,x_m,y_m,heading_rad,vx_m_s,vy_m_s,payload_hex";

class Exporter {
 public:
  Exporter(const ReplayOptions& options, std::ostream& out) : options_(options), out_(out) {}

  void Header(const replay::Header& header, uint16_t version) {
    if (options_.format == "csv") {
      out_ << (options_.table == "events" ? kEventsColumns : options_.table == "maps" ? kMapsColumns : kFramesColumns)
           << "\n";
      return;
    }
    Json robots = Json::array();
    for (const replay::RobotInfo& robot : header.robots) {
      Json inputs = Json::object();
      for (const replay::InputValue& input : robot.inputs) inputs[input.name] = input.value;
      robots.push_back({{"id", robot.id},
                        {"kind", KindName(robot.kind)},
                        {"body_radius_m", JsonFloat(robot.body_radius_m)},
                        {"inputs", std::move(inputs)}});
    }
    Json anchors = Json::array();
    for (const replay::AnchorInfo& anchor : header.anchors) anchors.push_back({JsonFloat(anchor.x_m), JsonFloat(anchor.y_m)});
    Line({{"type", "header"}, {"format_version", version}, {"scenario", header.scenario_name},
          {"app", header.app_name}, {"seed", header.seed}, {"radio_round_ns", header.radio_round_ns},
          {"arena_width_m", JsonFloat(header.arena_width_m)}, {"arena_height_m", JsonFloat(header.arena_height_m)},
          {"robots", std::move(robots)}, {"anchors", std::move(anchors)},
          {"message", header.message ? Json(header.message->ToString()) : Json(nullptr)}});
  }

  void Round(const replay::Round& round) {
    const bool csv = options_.format == "csv";
    if (!options_.events_only && (!csv || options_.table == "frames")) {
      for (const RobotFrame& frame : round.robots) {
        if (!options_.robot || frame.id == *options_.robot) Frame(round, frame, csv);
      }
    }
    if (!csv || options_.table == "events") {
      for (const Event& event : round.events) {
        if (Selected(event, options_)) EventLine(round, event, csv);
      }
    }
    if (!options_.events_only && (!csv || options_.table == "maps")) {
      for (const replay::RobotMap& entry : round.maps) {
        if (!options_.robot || entry.robot == *options_.robot) Map(round, entry, csv);
      }
    }
  }

 private:
  void Line(const Json& record) { out_ << record.dump() << "\n"; }

  void Frame(const replay::Round& round, const RobotFrame& frame, bool csv) {
    if (csv) {
      out_ << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", round.index, Seconds(round.time_ns), frame.id,
                          replay::ToString(frame.presence), frame.status == 0 ? "member" : "joining",
                          PhaseName(frame.phase), ModeName(frame.mode), frame.epoch, Float(frame.true_x_m),
                          Float(frame.true_y_m), Float(frame.true_heading_rad), Float(frame.est_x_m),
                          Float(frame.est_y_m), Float(frame.est_heading_rad));
      return;
    }
    Line({{"type", "frame"}, {"round", round.index}, {"time_ns", round.time_ns}, {"robot", frame.id},
          {"presence", replay::ToString(frame.presence)}, {"status", frame.status == 0 ? "member" : "joining"},
          {"phase", PhaseName(frame.phase)}, {"mode", ModeName(frame.mode)}, {"epoch", frame.epoch},
          {"true_x_m", JsonFloat(frame.true_x_m)}, {"true_y_m", JsonFloat(frame.true_y_m)},
          {"true_heading_rad", JsonFloat(frame.true_heading_rad)}, {"est_x_m", JsonFloat(frame.est_x_m)},
          {"est_y_m", JsonFloat(frame.est_y_m)}, {"est_heading_rad", JsonFloat(frame.est_heading_rad)}});
  }

  void EventLine(const replay::Round& round, const Event& event, bool csv) {
    if (csv) {
      out_ << fmt::format("{},{},{},{},{},{},{},{}\n", round.index, Seconds(event.time_ns),
                          replay::ToString(event.kind), Cell(event.robot, replay::kNoRobot),
                          Cell(event.other, replay::kNoRobot), Cell(event.partition, replay::kNoPartition),
                          event.epoch, ModeName(event.mode));
      return;
    }
    Line({{"type", "event"}, {"round", round.index}, {"time_ns", event.time_ns},
          {"kind", replay::ToString(event.kind)}, {"robot", JsonId(event.robot, replay::kNoRobot)},
          {"other", JsonId(event.other, replay::kNoRobot)},
          {"partition", JsonId(event.partition, replay::kNoPartition)}, {"epoch", event.epoch},
          {"mode", ModeName(event.mode)}});
  }

  void Map(const replay::Round& round, const replay::RobotMap& entry, bool csv) {
    const replay::EpochMap& map = *entry.map;
    if (csv) {
      for (const replay::MapMember& member : map.members) {
        out_ << fmt::format("{},{},{},{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{}\n", round.index,
                            Seconds(round.time_ns), entry.robot, map.epoch, ModeName(map.mode), member.id,
                            PhaseName(member.phase), member.x_mm / 1000.0, member.y_mm / 1000.0,
                            member.heading_mrad / 1000.0, member.vx_mm_s / 1000.0, member.vy_mm_s / 1000.0,
                            Hex(member.payload));
      }
      return;
    }
    Json members = Json::array();
    for (const replay::MapMember& member : map.members) {
      members.push_back({{"id", member.id}, {"phase", PhaseName(member.phase)}, {"x_m", member.x_mm / 1000.0},
                         {"y_m", member.y_mm / 1000.0}, {"heading_rad", member.heading_mrad / 1000.0},
                         {"vx_m_s", member.vx_mm_s / 1000.0}, {"vy_m_s", member.vy_mm_s / 1000.0},
                         {"payload_hex", Hex(member.payload)}});
    }
    Line({{"type", "map"}, {"round", round.index}, {"time_ns", round.time_ns}, {"robot", entry.robot},
          {"epoch", map.epoch}, {"mode", ModeName(map.mode)}, {"members", std::move(members)}});
  }

  const ReplayOptions& options_;
  std::ostream& out_;
};

int Export(const ReplayOptions& options, Reader& reader, const replay::Header& header, std::ostream& out,
           std::ostream& err) {
  Exporter exporter(options, out);
  exporter.Header(header, reader.version());
  Round round;
  bool round_found = false;
  while (reader.Next(round)) {
    if (options.round) {
      if (round.index > *options.round) break;
      if (round.index != *options.round) continue;
      round_found = true;
    }
    exporter.Round(round);
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

int Dump(const ReplayOptions& options, std::ostream& out, std::ostream& err) {
  std::error_code error;
  if (std::filesystem::is_directory(options.file, error)) {
    err << fmt::format("syrof replay: '{}' is a folder, not a replay file\n", options.file);
    return kBadInput;
  }
  std::ifstream in(options.file, std::ios::binary);
  if (!in) {
    err << fmt::format("syrof replay: cannot open '{}': {}\n", options.file, std::strerror(errno));
    return kBadInput;
  }
  Reader reader(in);
  Header header;
  if (!reader.ReadHeader(header)) {
    err << fmt::format("syrof replay: {}: {}\n", options.file, reader.error().ToString());
    return kBadInput;
  }
  if (options.robot) {
    bool known = false;
    for (const replay::RobotInfo& robot : header.robots) known = known || robot.id == *options.robot;
    if (!known) {
      err << fmt::format("syrof replay: {}: no robot {} in this replay\n", options.file, *options.robot);
      return kBadInput;
    }
  }
  if (options.format != "text") return Export(options, reader, header, out, err);
  PrintHeader(header, reader.version(), out);
  if (options.summary) {
    const int status = Summarize(reader, out);
    if (status != kOk) err << fmt::format("syrof replay: {}: {}\n", options.file, reader.error().ToString());
    return status;
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
  CLI::Option* summary = command->add_flag("--summary", options.summary, "Print counts and whether the file is complete")
                             ->excludes(round)
                             ->excludes(robot)
                             ->excludes(events_only);
  CLI::Option* format =
      command->add_option("--format", options.format, "text (default), csv or jsonl (columns: docs/replay.md)")
          ->check(CLI::IsMember({"text", "csv", "jsonl"}));
  command->add_option("--table", options.table, "With --format csv: frames (default), events or maps")
      ->check(CLI::IsMember({"frames", "events", "maps"}))
      ->needs(format);
  summary->excludes(format);
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
