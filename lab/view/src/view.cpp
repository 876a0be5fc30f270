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

std::string ReplayJson(std::istream& in, const std::string& name, const PageOptions& options, Page& page) {
  json data;
  data["data_version"] = kDataVersion;
  data["file"] = name;
  data["kinds"] = KindNames();
  page = Page{};

  if (in.peek() == std::istream::traits_type::eof()) {
    data["status"] = "empty";
    data["message"] = "The replay file is empty (0 bytes): the run recorded nothing. Run it again with `syrof run`.";
    page.error = Error{.where = name, .message = "the file is empty (0 bytes)"};
    return data.dump();
  }

  // Decimation for drawing: the smallest stride that fits the budget, from
  // a first pass that counts the rounds, so that only the frames kept are
  // held: all robots x rounds of them were gigabytes for a long run, or for
  // a hostile file of 65,535 robots and empty rounds. A stream that cannot
  // seek back (a pipe) is read once, holding every frame, and decimated
  // after.
  const std::istream::pos_type start = in.tellg();
  const bool counted = start != std::istream::pos_type(-1);
  size_t rounds_in_file = 0;
  size_t robots_in_file = 0;
  if (counted) {
    replay::Reader counter(in);
    replay::Header counted_header;
    if (counter.ReadHeader(counted_header)) {
      robots_in_file = counted_header.robots.size();
      replay::Round skipped;
      while (counter.Next(skipped)) ++rounds_in_file;
    }
    in.clear();
    in.seekg(start);
  }
  const auto stride_for = [&options](size_t robot_frames) -> size_t {
    if (options.max_robot_frames == 0 || robot_frames <= options.max_robot_frames) return 1;
    return (robot_frames + options.max_robot_frames - 1) / options.max_robot_frames;
  };
  const size_t read_stride = stride_for(robots_in_file * rounds_in_file);  // 1 when not counted

  replay::Reader reader(in);
  replay::Header header;
  if (!reader.ReadHeader(header)) {
    const std::string message = reader.error().ToString();
    const bool newer = message.find("is newer than this reader's") != std::string::npos;
    data["status"] = newer ? "newer" : reader.truncated() ? "truncated" : "invalid";
    data["message"] = newer ? "This replay was written by a newer SyROF (" + message +
                                  "). Open it with the `syrof view` of that version or a later one."
                            : "This file cannot be shown: " + message;
    page.error = Error{.where = name, .message = message};
    return data.dump();
  }

  data.update(HeaderData(header, reader.version()));

  // Read everything the reader accepts; frames are carried forward for a
  // robot a round leaves out, as the format defines.
  const size_t robot_count = header.robots.size();
  std::vector<replay::RobotFrame> current(robot_count);
  for (size_t slot = 0; slot < robot_count; ++slot) current[slot].id = header.robots[slot].id;
  std::vector<Columns> columns(robot_count);
  std::vector<int64_t> round_index;
  std::vector<int64_t> round_time_us;
  json events = json::array();
  json maps = json::array();
  json starts = json::array();
  std::map<const replay::EpochMap*, size_t> map_numbers;  // shared maps once
  // Under SSYNC each start says whether the schedule left its robot out:
  // the robots' own decision (sync::IsActive) on the map they started with.
  // Under ASYNC whether it looked, from its cycles followed as the robot
  // followed them (sync::AsyncTracker), with the look its move comes from.
  std::optional<sync::ActivationConfig> activation;
  std::vector<sync::AsyncTracker> cycles(header.robots.size());
  if (options.scenario != nullptr && options.scenario->activation.model != sync::ActivationModel::kFsync &&
      options.scenario->seed == header.seed) {
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
    if (sync::IsValid(config)) activation = config;
    data["activation"] = {{"model", sync::ToString(spec.model)}, {"schedule", sync::ToString(spec.schedule)}};
  }
  auto is_active = [&](const replay::RobotMap& entry) {
    wire::MemberSet members;
    for (const replay::MapMember& member : entry.map->members) {
      if (member.id < wire::MemberSet::kCapacity) members.set(member.id);
    }
    return sync::IsActive(*activation, entry.map->epoch, members, entry.robot);
  };
  std::vector<std::shared_ptr<const replay::EpochMap>> keep_alive;
  ReplayFacts facts;  // what the replay shows of the run's troubles, for the verdict
  replay::Round round;
  while (reader.Next(round)) {
    const int64_t position = static_cast<int64_t>(round_index.size());
    round_index.push_back(round.index);
    round_time_us.push_back(round.time_ns / 1000);
    size_t slot = 0;
    for (const replay::RobotFrame& frame : round.robots) {
      while (current[slot].id != frame.id) ++slot;  // both increase (the reader checked)
      current[slot] = frame;
    }
    for (size_t i = 0; position % static_cast<int64_t>(read_stride) == 0 && i < robot_count; ++i) {
      const replay::RobotFrame& frame = current[i];
      Columns& column = columns[i];
      column.state.push_back(FrameState(frame));
      column.epoch.push_back(frame.epoch);
      column.x.push_back(Milli(frame.true_x_m));
      column.y.push_back(Milli(frame.true_y_m));
      column.h.push_back(Milli(frame.true_heading_rad));
      column.ex.push_back(Milli(frame.est_x_m));
      column.ey.push_back(Milli(frame.est_y_m));
      column.eh.push_back(Milli(frame.est_heading_rad));
    }
    for (const replay::Event& event : round.events) {
      events.push_back(EventData(event, position));
      switch (event.kind) {
        case replay::EventKind::kCollision: ++facts.collisions; break;
        case replay::EventKind::kAppFault: ++facts.app_faults; break;
        case replay::EventKind::kJoinWait: ++facts.join_waits; break;
        case replay::EventKind::kBeaconLost:
          facts.lost.push_back({.round = round.index, .from = event.robot, .to = event.other});
          break;
        default: break;
      }
    }
    for (const replay::RobotMap& entry : round.maps) {
      auto [found, inserted] = map_numbers.emplace(entry.map.get(), map_numbers.size());
      if (inserted) {
        keep_alive.push_back(entry.map);
        maps.push_back(MapData(*entry.map, header));
      }
      if (activation && activation->model == sync::ActivationModel::kAsync && entry.robot < cycles.size()) {
        // [.., looked, the look's epoch, moves this epoch, the move is cut]
        const sync::AsyncTracker::Step step = cycles[entry.robot].OnEpochStart(*activation, entry.map->epoch, entry.robot);
        starts.push_back({position, entry.robot, found->second, step.looks ? 1 : 0, step.look_epoch, step.moves ? 1 : 0,
                          step.cycle.cut ? 1 : 0});
      } else if (activation) {
        starts.push_back({position, entry.robot, found->second, is_active(entry) ? 1 : 0});
      } else {
        starts.push_back({position, entry.robot, found->second});
      }
    }
    page.events += round.events.size();
  }
  page.rounds = round_index.size();
  page.complete = reader.complete();

  if (page.complete) {
    data["status"] = "complete";
  } else {
    page.error = Error{.where = name, .message = reader.error().ToString()};
    data["status"] = reader.truncated() ? "truncated" : "invalid";
    data["message"] = fmt::format("{} after {} rounds: {}. Everything before the problem is shown.",
                                  reader.truncated() ? "The replay is cut short" : "The replay is damaged",
                                  page.rounds, reader.error().ToString());
  }

  const size_t stride = counted ? read_stride : stride_for(robot_count * page.rounds);
  const size_t stride_after = counted ? 1 : stride;  // what is left to drop of the frames held
  page.frame_stride = stride;
  data["stride"] = stride;
  data["rounds"] = {{"index", Deltas(round_index)}, {"time_us", Deltas(round_time_us)}};
  json robots_frames = json::array();
  for (const Columns& column : columns) {
    auto sampled = [stride_after](const std::vector<int64_t>& values) {
      std::vector<int64_t> kept;
      for (size_t i = 0; i < values.size(); i += stride_after) kept.push_back(values[i]);
      return kept;
    };
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
  data["frames"] = std::move(robots_frames);
  data["events"] = std::move(events);
  data["maps"] = std::move(maps);
  data["starts"] = std::move(starts);
  // The verdict and the goal's target: how the run went, said first.
  if (options.metrics && options.metrics->seed == header.seed) {
    data["verdict"] = VerdictData(VerdictOf(*options.metrics, facts));
  } else {
    Verdict verdict = VerdictOfReplay(facts);
    if (options.metrics) {
      verdict.lines.front().text = fmt::format("not judged: the metrics given are of another run (seed {}, this "
                                               "replay's is {})", options.metrics->seed, header.seed);
    }
    data["verdict"] = VerdictData(verdict);
  }
  size_t goal_robots = 0;  // running or paused at the end: a built-in goal's robots
  for (const replay::RobotFrame& frame : current) {
    goal_robots += frame.presence == replay::Presence::kRunning || frame.presence == replay::Presence::kPaused;
  }
  data["targets"] = options.scenario ? GoalTargets(*options.scenario, goal_robots) : json::array();
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
