#include "syrof/lab/view/view.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>
#include <vector>

#include "syrof/lab/replay/reader.h"
#include "syrof/lab/message/message_format.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/lab/view/page_data.h"
#include "syrof/lab/view/verdict.h"
#include "syrof/sync/activation.h"
#include "syrof/wire/member_set.h"
#include "view_assets.h"

namespace syrof::lab::view {
namespace {

namespace replay = lab::replay;
using nlohmann::json;

// Robot ids and partitions as the page sees them: -1 for none.
int64_t IdOrNone(uint16_t id) { return id == replay::kNoRobot ? -1 : id; }

std::string Hex(const std::vector<uint8_t>& bytes) {
  std::string text;
  for (const uint8_t byte : bytes) text += fmt::format("{:02x}", byte);
  return text;
}

// The event kinds' names, by number.
json KindNames() {
  json names = json::array();
  for (unsigned kind = 0; kind <= static_cast<unsigned>(replay::kLastEventKind); ++kind) {
    names.push_back(replay::ToString(static_cast<replay::EventKind>(kind)));
  }
  return names;
}

// Successive differences: small numbers, so a smaller page.
json Deltas(const std::vector<int64_t>& values) {
  json out = json::array();
  int64_t previous = 0;
  for (const int64_t value : values) {
    out.push_back(value - previous);
    previous = value;
  }
  return out;
}

// Every robot's frame fields over the rounds kept (every stride-th), one
// column per field.
struct Columns {
  std::vector<int64_t> state, epoch, x, y, h, ex, ey, eh;
};

std::string_view Asset(const unsigned char* bytes, size_t size) {
  return {reinterpret_cast<const char*>(bytes), size};
}

// Where `marker` is in `text`, which must hold it exactly once (the
// template is ours; a miss is a build mistake, caught by the tests).
size_t Find(std::string_view text, std::string_view marker) {
  const size_t at = text.find(marker);
  return at == std::string_view::npos ? text.size() : at;
}

}  // namespace

int32_t Milli(float value) {
  if (!std::isfinite(value)) return 0;
  const double milli = std::clamp(static_cast<double>(value) * 1000.0, -1e9, 1e9);
  return static_cast<int32_t>(std::lround(milli));
}

int64_t FrameState(const replay::RobotFrame& frame) {
  return static_cast<int64_t>(frame.presence) | frame.status << 2 | frame.phase << 3 | frame.mode << 5;
}

json EventData(const replay::Event& event, int64_t position) {
  return {position, static_cast<int>(event.kind), IdOrNone(event.robot), IdOrNone(event.other),
          event.epoch, event.mode, event.time_ns / 1000,
          event.partition == replay::kNoPartition ? -1 : int64_t{event.partition}};
}

json MapData(const replay::EpochMap& map, const replay::Header& header) {
  // Each member's payload is decoded here, with lab/message's decoder (the
  // grader checks payloads with the same definition), so the page never
  // parses bytes itself.
  auto decoded = [&header](const std::vector<uint8_t>& payload) -> json {
    if (!header.message || header.message->none || payload.empty()) return nullptr;
    const std::vector<message::FieldValue> values = message::DecodePayload(*header.message, payload);
    if (values.empty()) return nullptr;  // not the format's length: shown as hex, marked
    json fields = json::array();
    for (const message::FieldValue& value : values) fields.push_back({value.name, value.value});
    return fields;
  };
  json members = json::array();
  for (const replay::MapMember& member : map.members) {
    members.push_back({member.id, member.phase, member.x_mm, member.y_mm, member.heading_mrad, member.vx_mm_s,
                       member.vy_mm_s, Hex(member.payload), decoded(member.payload)});
  }
  return {map.epoch, map.mode, std::move(members)};
}

json HeaderData(const replay::Header& header, int replay_version) {
  json data;
  data["data_version"] = kDataVersion;
  data["kinds"] = KindNames();
  data["replay_version"] = replay_version;
  data["scenario"] = header.scenario_name;
  data["app"] = header.app_name;
  data["seed"] = std::to_string(header.seed);  // a u64 does not fit a JS number
  data["round_ns"] = header.radio_round_ns;
  data["arena"] = {header.arena_width_m, header.arena_height_m};
  data["anchors"] = json::array();
  for (const replay::AnchorInfo& anchor : header.anchors) data["anchors"].push_back({anchor.x_m, anchor.y_m});
  data["robots"] = json::array();
  for (const replay::RobotInfo& robot : header.robots) {
    json inputs = json::array();
    for (const replay::InputValue& input : robot.inputs) inputs.push_back({input.name, input.value});
    data["robots"].push_back(
        {{"id", robot.id}, {"kind", robot.kind}, {"radius", robot.body_radius_m}, {"inputs", std::move(inputs)}});
  }
  data["message"] = header.message ? json(header.message->ToString()) : json(nullptr);
  return data;
}

namespace {

// The fields of every page, whatever the file holds: the data's version,
// the file's name and the event kinds' names.
json StartData(const std::string& name) {
  json data;
  data["data_version"] = kDataVersion;
  data["file"] = name;
  data["kinds"] = KindNames();
  return data;
}

// Writes the status and message of a file of 0 bytes.
void WriteEmptyFile(const std::string& name, Page& page, json& data) {
  data["status"] = "empty";
  data["message"] = "The replay file is empty (0 bytes): the run recorded nothing. Run it again with `syrof run`.";
  page.error = Error{.where = name, .message = "the file is empty (0 bytes)"};
}

// Writes the status and message of a file whose header cannot be read: one
// from a newer SyROF is told apart, so that its reader knows what to do.
void WriteUnreadableHeader(const replay::Reader& reader, const std::string& name, Page& page, json& data) {
  const std::string message = reader.error().ToString();
  const bool newer = message.find("is newer than this reader's") != std::string::npos;
  data["status"] = newer ? "newer" : reader.truncated() ? "truncated" : "invalid";
  data["message"] = newer ? "This replay was written by a newer SyROF (" + message +
                                "). Open it with the `syrof view` of that version or a later one."
                          : "This file cannot be shown: " + message;
  page.error = Error{.where = name, .message = message};
}

// Robots x rounds in the file, from a first pass that counts the rounds
// (0 if its header cannot be read), with `in` put back where it was; none
// for a stream that cannot seek back (a pipe).
std::optional<size_t> CountRobotFrames(std::istream& in) {
  const std::istream::pos_type start = in.tellg();
  if (start == std::istream::pos_type(-1)) return std::nullopt;
  size_t rounds_in_file = 0;
  size_t robots_in_file = 0;
  replay::Reader counter(in);
  replay::Header counted_header;
  if (counter.ReadHeader(counted_header)) {
    robots_in_file = counted_header.robots.size();
    replay::Round skipped;
    while (counter.Next(skipped)) ++rounds_in_file;
  }
  in.clear();
  in.seekg(start);
  return robots_in_file * rounds_in_file;
}

// The smallest stride that keeps `robot_frames` within the page's budget.
size_t StrideFor(const PageOptions& options, size_t robot_frames) {
  if (options.max_robot_frames == 0 || robot_frames <= options.max_robot_frames) return 1;
  return (robot_frames + options.max_robot_frames - 1) / options.max_robot_frames;
}

// The activation the robots' starts are followed by, when the scenario
// given is this run's and not FSYNC; writes its "activation" field (even
// when the scenario's activation is not a valid one, and none is returned).
std::optional<sync::ActivationConfig> ActivationOf(const PageOptions& options, const replay::Header& header,
                                                   json& data) {
  if (options.scenario == nullptr || options.scenario->activation.model == sync::ActivationModel::kFsync ||
      options.scenario->seed != header.seed) {
    return std::nullopt;
  }
  const scenario::ActivationSpec& spec = options.scenario->activation;
  sync::ActivationConfig config;
  config.model = spec.model;
  config.schedule = spec.schedule;
  config.seed = options.scenario->seed;
  config.fair_within = spec.fair_within;
  config.script = spec.script;
  config.max_delay_epochs = spec.max_delay_epochs;
  config.min_move_mm = static_cast<uint32_t>(std::lround(spec.min_move_m * 1000.0));
  config.cycles = spec.cycles;
  data["activation"] = {{"model", sync::ToString(spec.model)}, {"schedule", sync::ToString(spec.schedule)}};
  if (!sync::IsValid(config)) return std::nullopt;
  return config;
}

// Whether the schedule lets the robot act at the epoch of the map it
// started with: the robots' own decision (sync::IsActive) on that map.
bool StartsActive(const sync::ActivationConfig& activation, const replay::RobotMap& entry) {
  wire::MemberSet members;
  for (const replay::MapMember& member : entry.map->members) {
    if (member.id < wire::MemberSet::kCapacity) members.set(member.id);
  }
  return sync::IsActive(activation, entry.map->epoch, members, entry.robot);
}

// Everything read of the rounds, kept until the page's data is written.
struct RoundsRead {
  // Each robot's last frame, by slot: frames are carried forward for a
  // robot a round leaves out, as the format defines.
  std::vector<replay::RobotFrame> current;
  std::vector<Columns> columns;  // the frames kept, every read stride-th round
  std::vector<int64_t> round_index;
  std::vector<int64_t> round_time_us;
  json events = json::array();
  json maps = json::array();
  json starts = json::array();
  std::map<const replay::EpochMap*, size_t> map_numbers;  // shared maps once
  std::vector<std::shared_ptr<const replay::EpochMap>> keep_alive;  // so that no map's address is reused
  std::vector<sync::AsyncTracker> cycles;  // under ASYNC each robot's cycles, as it followed them
  ReplayFacts facts;  // what the replay shows of the run's troubles, for the verdict
};

// Carries the round's frames forward and, on a kept round, adds every
// robot's frame to its columns.
void AddFrames(const replay::Round& round, int64_t position, size_t read_stride, RoundsRead& read) {
  size_t slot = 0;
  for (const replay::RobotFrame& frame : round.robots) {
    while (read.current[slot].id != frame.id) ++slot;  // both increase (the reader checked)
    read.current[slot] = frame;
  }
  for (size_t i = 0; position % static_cast<int64_t>(read_stride) == 0 && i < read.current.size(); ++i) {
    const replay::RobotFrame& frame = read.current[i];
    Columns& column = read.columns[i];
    column.state.push_back(FrameState(frame));
    column.epoch.push_back(frame.epoch);
    column.x.push_back(Milli(frame.true_x_m));
    column.y.push_back(Milli(frame.true_y_m));
    column.h.push_back(Milli(frame.true_heading_rad));
    column.ex.push_back(Milli(frame.est_x_m));
    column.ey.push_back(Milli(frame.est_y_m));
    column.eh.push_back(Milli(frame.est_heading_rad));
  }
}

// Adds the round's events, and counts the troubles among them.
void AddEvents(const replay::Round& round, int64_t position, RoundsRead& read) {
  for (const replay::Event& event : round.events) {
    read.events.push_back(EventData(event, position));
    switch (event.kind) {
      case replay::EventKind::kCollision: ++read.facts.collisions; break;
      case replay::EventKind::kAppFault: ++read.facts.app_faults; break;
      case replay::EventKind::kJoinWait: ++read.facts.join_waits; break;
      case replay::EventKind::kBeaconLost:
        read.facts.lost.push_back({.round = round.index, .from = event.robot, .to = event.other});
        break;
      default: break;
    }
  }
}

// Adds the maps first seen in the round and each robot's start on its map:
// under SSYNC whether the schedule left the robot out, under ASYNC whether
// it looked, with the look its move comes from.
void AddMapsAndStarts(const replay::Round& round, int64_t position, const replay::Header& header,
                      const std::optional<sync::ActivationConfig>& activation, RoundsRead& read) {
  for (const replay::RobotMap& entry : round.maps) {
    auto [found, inserted] = read.map_numbers.emplace(entry.map.get(), read.map_numbers.size());
    if (inserted) {
      read.keep_alive.push_back(entry.map);
      read.maps.push_back(MapData(*entry.map, header));
    }
    if (activation && activation->model == sync::ActivationModel::kAsync && entry.robot < read.cycles.size()) {
      // [.., looked, the look's epoch, moves this epoch, the move is cut]
      const sync::AsyncTracker::Step step =
          read.cycles[entry.robot].OnEpochStart(*activation, entry.map->epoch, entry.robot);
      read.starts.push_back({position, entry.robot, found->second, step.looks ? 1 : 0, step.look_epoch,
                             step.moves ? 1 : 0, step.cycle.cut ? 1 : 0});
    } else if (activation) {
      read.starts.push_back({position, entry.robot, found->second, StartsActive(*activation, entry) ? 1 : 0});
    } else {
      read.starts.push_back({position, entry.robot, found->second});
    }
  }
}

// Reads every round the reader accepts, keeping every read stride-th
// round's frames; counts the page's rounds and events.
RoundsRead ReadRounds(replay::Reader& reader, const replay::Header& header,
                      const std::optional<sync::ActivationConfig>& activation, size_t read_stride, Page& page) {
  const size_t robot_count = header.robots.size();
  RoundsRead read;
  read.current.resize(robot_count);
  for (size_t slot = 0; slot < robot_count; ++slot) read.current[slot].id = header.robots[slot].id;
  read.columns.resize(robot_count);
  read.cycles.resize(robot_count);
  replay::Round round;
  while (reader.Next(round)) {
    const int64_t position = static_cast<int64_t>(read.round_index.size());
    read.round_index.push_back(round.index);
    read.round_time_us.push_back(round.time_ns / 1000);
    AddFrames(round, position, read_stride, read);
    AddEvents(round, position, read);
    AddMapsAndStarts(round, position, header, activation, read);
    page.events += round.events.size();
  }
  page.rounds = read.round_index.size();
  page.complete = reader.complete();
  return read;
}

// Writes whether the reader reached the end, and if not what stopped it
// (everything before it is shown).
void WriteStatus(const replay::Reader& reader, const std::string& name, Page& page, json& data) {
  if (page.complete) {
    data["status"] = "complete";
    return;
  }
  page.error = Error{.where = name, .message = reader.error().ToString()};
  data["status"] = reader.truncated() ? "truncated" : "invalid";
  data["message"] = fmt::format("{} after {} rounds: {}. Everything before the problem is shown.",
                                reader.truncated() ? "The replay is cut short" : "The replay is damaged",
                                page.rounds, reader.error().ToString());
}

// Every robot's frames, every stride_after-th of those held: the state as
// it is, the other fields as successive differences.
json FramesData(const std::vector<Columns>& columns, size_t stride_after) {
  auto sampled = [stride_after](const std::vector<int64_t>& values) {
    std::vector<int64_t> kept;
    for (size_t i = 0; i < values.size(); i += stride_after) kept.push_back(values[i]);
    return kept;
  };
  json robots_frames = json::array();
  for (const Columns& column : columns) {
    json state = json::array();
    for (const int64_t value : sampled(column.state)) state.push_back(value);
    robots_frames.push_back({{"s", std::move(state)},
                             {"e", Deltas(sampled(column.epoch))},
                             {"x", Deltas(sampled(column.x))},
                             {"y", Deltas(sampled(column.y))},
                             {"h", Deltas(sampled(column.h))},
                             {"ex", Deltas(sampled(column.ex))},
                             {"ey", Deltas(sampled(column.ey))},
                             {"eh", Deltas(sampled(column.eh))}});
  }
  return robots_frames;
}

// How the run went: from its metrics when they are this run's, else from
// the replay alone (saying why when metrics of another run were given).
json VerdictFor(const PageOptions& options, const replay::Header& header, const ReplayFacts& facts) {
  if (options.metrics && options.metrics->seed == header.seed) return VerdictData(VerdictOf(*options.metrics, facts));
  Verdict verdict = VerdictOfReplay(facts);
  if (options.metrics) {
    verdict.lines.front().text = fmt::format("not judged: the metrics given are of another run (seed {}, this "
                                             "replay's is {})", options.metrics->seed, header.seed);
  }
  return VerdictData(verdict);
}

// The goal's target for the robots running or paused at the end (a built-in
// goal's robots); none without the scenario.
json TargetsFor(const PageOptions& options, const std::vector<replay::RobotFrame>& last_frames) {
  size_t goal_robots = 0;
  for (const replay::RobotFrame& frame : last_frames) {
    goal_robots += frame.presence == replay::Presence::kRunning || frame.presence == replay::Presence::kPaused;
  }
  return options.scenario ? GoalTargets(*options.scenario, goal_robots) : json::array();
}

}  // namespace

std::string ReplayJson(std::istream& in, const std::string& name, const PageOptions& options, Page& page) {
  json data = StartData(name);
  page = Page{};
  if (in.peek() == std::istream::traits_type::eof()) {
    WriteEmptyFile(name, page, data);
    return data.dump();
  }

  // Decimation for drawing: the smallest stride that fits the budget, from
  // a first pass that counts the rounds, so that only the frames kept are
  // held: all robots x rounds of them were gigabytes for a long run, or for
  // a hostile file of 65,535 robots and empty rounds. A stream that cannot
  // seek back (a pipe) is read once, holding every frame, and decimated
  // after.
  const std::optional<size_t> robot_frames_in_file = CountRobotFrames(in);
  const bool counted = robot_frames_in_file.has_value();
  const size_t read_stride = StrideFor(options, robot_frames_in_file.value_or(0));  // 1 when not counted

  replay::Reader reader(in);
  replay::Header header;
  if (!reader.ReadHeader(header)) {
    WriteUnreadableHeader(reader, name, page, data);
    return data.dump();
  }
  data.update(HeaderData(header, reader.version()));
  const std::optional<sync::ActivationConfig> activation = ActivationOf(options, header, data);
  RoundsRead read = ReadRounds(reader, header, activation, read_stride, page);
  WriteStatus(reader, name, page, data);

  const size_t stride = counted ? read_stride : StrideFor(options, header.robots.size() * page.rounds);
  const size_t stride_after = counted ? 1 : stride;  // what is left to drop of the frames held
  page.frame_stride = stride;
  data["stride"] = stride;
  data["rounds"] = {{"index", Deltas(read.round_index)}, {"time_us", Deltas(read.round_time_us)}};
  data["frames"] = FramesData(read.columns, stride_after);
  data["events"] = std::move(read.events);
  data["maps"] = std::move(read.maps);
  data["starts"] = std::move(read.starts);
  // The verdict and the goal's target: how the run went, said first.
  data["verdict"] = VerdictFor(options, header, read.facts);
  data["targets"] = TargetsFor(options, read.current);
  if (page.rounds == 0 && page.complete) {
    data["status"] = "empty";
    data["message"] = "The replay holds no rounds: the run ended before its first radio round.";
  }
  return data.dump();
}

namespace {

// The template's policy, and what the live page's says instead.
constexpr std::string_view kFilePolicyEnd = "img-src data:\"";
constexpr std::string_view kLivePolicyEnd = "img-src data:; connect-src 'self'\"";

std::string Render(const std::string& data_json, const std::string& title, bool live) {
  const std::string_view html_template = Asset(kAsset_viewer_html, kAsset_viewer_html_size);
  std::string live_template;
  if (live) {
    live_template = html_template;
    const size_t at = live_template.find(kFilePolicyEnd);
    if (at != std::string::npos) live_template.replace(at, kFilePolicyEnd.size(), kLivePolicyEnd);
  }
  const std::string_view html = live ? std::string_view(live_template) : html_template;
  const std::string_view css = Asset(kAsset_viewer_css, kAsset_viewer_css_size);
  const std::string_view js = Asset(kAsset_viewer_js, kAsset_viewer_js_size);

  // Inside <script>, "</" could close the element early (a scenario named
  // "</script>"); "<\/" is the same JSON string.
  std::string data;
  data.reserve(data_json.size());
  for (size_t i = 0; i < data_json.size(); ++i) {
    data += data_json[i];
    if (data_json[i] == '<' && i + 1 < data_json.size() && data_json[i + 1] == '/') data += '\\';
  }
  std::string escaped_title;
  for (const char c : title) {
    switch (c) {
      case '<': escaped_title += "&lt;"; break;
      case '>': escaped_title += "&gt;"; break;
      case '&': escaped_title += "&amp;"; break;
      default: escaped_title += c;
    }
  }

  std::string page;
  page.reserve(html.size() + css.size() + js.size() + data.size() + title.size());
  std::string_view rest = html;
  const std::array<std::pair<std::string_view, std::string_view>, 4> parts = {
      {{"@TITLE@", escaped_title}, {"/*@CSS@*/", css}, {"@DATA@", data}, {"/*@JS@*/", js}}};
  for (const auto& [marker, value] : parts) {
    const size_t at = Find(rest, marker);
    if (at == rest.size()) continue;  // not in the template: tests catch that
    page.append(rest.substr(0, at));
    page.append(value);
    rest.remove_prefix(at + marker.size());
  }
  page.append(rest);
  return page;
}

}  // namespace

std::string RenderPage(const std::string& data_json, const std::string& title) {
  return Render(data_json, title, false);
}

std::string RenderLivePage(const std::string& data_json, const std::string& title) {
  return Render(data_json, title, true);
}

Page BuildPage(std::istream& in, const std::string& name, const PageOptions& options) {
  Page page;
  const std::string data = ReplayJson(in, name, options, page);
  page.html = RenderPage(data, "SyROF viewer: " + name);
  return page;
}

}  // namespace syrof::lab::view
